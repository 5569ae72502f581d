// Predictions that carry over (api/predictor.h, CarryOver): after label
// changes, the kept samples of voxels whose paths read no relabelled voxel
// in a way the new label contradicts (a real collision, or a null collision
// the new extinction would have made real) and no brick whose bounds
// changed stay as they are and the others are traced again, so every prediction
// holds the bits of a render of all its samples in one go; the reported
// errors stay honest as the samples accumulate over a loop; settings and
// whole grids start afresh.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <string>

#include "api/predictor.h"
#include "core/rng.h"
#include "io/grid_io.h"
#include "io/mesh_io.h"
#include "test_util.h"

namespace pl {
namespace {

namespace fs = std::filesystem;

constexpr Label kCyan = 0, kMagenta = 1, kBlack = 3, kWhite = 4;
// A 6 x 1 x 1 mm bar of 0.05 mm voxels (15 x 3 x 3 majorant bricks), white
// under a halftone of cyan and magenta: its paths stay within a few
// tenths of a millimetre, so a change at one end leaves the other's alone.
const Vec3i kBar{120, 20, 20};
const Vec3f kVoxel_mm{0.05f, 0.05f, 0.05f};

Label barLabel(const Vec3i& v) {
    const bool shell = v.y < 3 || v.z < 3 || v.y >= kBar.y - 3 || v.z >= kBar.z - 3 || v.x < 3 || v.x >= kBar.x - 3;
    if (!shell) return kWhite;
    return (mix64(uint64_t(v.x) * 7919 + uint64_t(v.y) * 131 + uint64_t(v.z)) & 3) == 0 ? kMagenta : kCyan;
}

fs::path writeBarScene(const std::string& name) {
    fs::path dir = test::freshTempDir("carry_over_" + name);
    writeObj(test::boxMesh({0, 0, 0}, {6, 1, 1}), dir / "bar.obj");
    writeLabelGridBin(test::boxGrid(kBar, kVoxel_mm, barLabel), dir / "grid.bin");
    fs::copy_file(test::sourceDir() / "data/materials/resins_illustrative.json", dir / "materials.json");
    std::ofstream(dir / "scene.json") << R"({"object": {"mesh": "bar.obj", "labels": "grid.bin", "materials": "materials.json"},
        "sensor": {"type": "surface_voxels"},
        "render": {"integrator": "volpath", "spp": 3, "seed": 5, "channel": "rgb"}})";
    return dir / "scene.json";
}

// Swaps cyan and magenta in every seventh shell voxel of x in [x0, x1) (a
// sparse pattern: no two are face neighbours). Every brick keeps both, so
// no brick's bounds change: only the voxels' own labels tell a path that
// read them.
std::vector<LabelGrid::Change> changesAt(int x0, int x1, uint64_t seed) {
    std::vector<LabelGrid::Change> changes;
    for (int z = 0; z < kBar.z; ++z)
        for (int y = 0; y < kBar.y; ++y)
            for (int x = x0; x < x1; ++x) {
                const Vec3i v{x, y, z};
                if (barLabel(v) == kWhite || (uint64_t(x + 2 * y + 3 * z) + seed) % 7 != 0) continue;
                changes.push_back({v, barLabel(v) == kCyan ? kMagenta : kCyan});
            }
    return changes;
}

void expectSameBits(const SurfacePrediction& a, const SurfacePrediction& b) {
    ASSERT_EQ(a.radiance.size(), b.radiance.size());
    size_t differ = 0;
    for (size_t i = 0; i < a.radiance.size(); ++i)
        differ += a.radiance[i] != b.radiance[i] || a.standardError[i] != b.standardError[i] || a.samples[i] != b.samples[i];
    EXPECT_EQ(differ, 0u) << "of " << a.radiance.size() << " voxels";
}

TEST(CarryOver, KeepsWhatNoChangeReachesAndEqualsAFullRenderOfTheSameSamples) {
    const fs::path scene = writeBarScene("bits");
    auto carried = Predictor::fromSceneFile(scene);
    carried->carryOver().enabled = true;
    SurfacePrediction p = carried->predict();
    EXPECT_TRUE(p.startedAfresh);
    const size_t n = p.radiance.size();
    // Changes at one end, then the other: each prediction adds 3 samples.
    carried->changeLabels(changesAt(0, 12, 1));
    p = carried->predict();
    EXPECT_FALSE(p.startedAfresh);
    EXPECT_GT(p.retracedVoxels, 0u);
    EXPECT_LT(p.retracedVoxels, n / 2) << "a change at one end reaches the whole bar";
    carried->changeLabels(changesAt(100, 120, 2));
    p = carried->predict();
    EXPECT_GT(p.retracedVoxels, 0u);
    EXPECT_LT(p.retracedVoxels, n / 2);
    // One black voxel in the middle: its brick's majorant rises, so every
    // path that crossed the brick is traced again, whatever voxels it read.
    carried->changeLabels({{{60, 0, 10}, kBlack}});
    p = carried->predict();
    EXPECT_GT(p.retracedVoxels, 0u);
    carried->changeLabels({});  // nothing relabelled: nothing traced again
    p = carried->predict();
    EXPECT_EQ(p.retracedVoxels, 0u);
    for (uint32_t s : p.samples) ASSERT_EQ(s, 15u);

    // The final labels rendered with all 15 samples in one go.
    auto fresh = Predictor::fromSceneFile(scene);
    fresh->setLabels(carried->labels().withChanges({}));
    fresh->settings().spp = 15;
    expectSameBits(p, fresh->predict());
}

// z-scores of two estimates with their reported errors, over voxels and
// channels: mean z^2 and the share beyond 4.
struct ZScores {
    double meanSquare = 0, beyond4 = 0;
    size_t count = 0;
};
ZScores zScores(const SurfacePrediction& a, const SurfacePrediction& b) {
    ZScores z;
    size_t beyond = 0;
    for (size_t i = 0; i < a.radiance.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double se2 = double(a.standardError[i][c]) * a.standardError[i][c] +
                               double(b.standardError[i][c]) * b.standardError[i][c];
            if (!(se2 > 0)) continue;
            const double d = (a.radiance[i][c] - b.radiance[i][c]) / std::sqrt(se2);
            z.meanSquare += d * d;
            beyond += std::abs(d) > 4;
            ++z.count;
        }
    z.meanSquare /= double(z.count);
    z.beyond4 = double(beyond) / double(z.count);
    return z;
}

double meanVariance(const SurfacePrediction& p) {
    double sum = 0;
    for (const RGB& se : p.standardError)
        for (int c = 0; c < 3; ++c) sum += double(se[c]) * se[c];
    return sum / (3.0 * double(p.standardError.size()));
}

// Reported errors honest by two estimates' disagreement: mean z^2 in
// [0.5, 1.6] and |z| > 4 under 0.1 %, as the low-spp test checks renders.
void expectHonest(const ZScores& z, const std::string& when) {
    ASSERT_GT(z.count, 1000u) << when;
    EXPECT_GT(z.meanSquare, 0.5) << when;
    EXPECT_LT(z.meanSquare, 1.6) << when;
    EXPECT_LT(z.beyond4, 1e-3) << when;
}

// Two predictors of the bar that carry over by `method`, each prediction
// drawing `spp` new samples (their seeds the caller's).
std::array<std::unique_ptr<Predictor>, 2> twoLoops(const fs::path& scene, CarryOver::Method method, uint32_t spp) {
    std::array<std::unique_ptr<Predictor>, 2> loops;
    for (auto& loop : loops) {
        loop = Predictor::fromSceneFile(scene);
        loop->carryOver().enabled = true;
        loop->carryOver().method = method;
        loop->settings().spp = spp;
    }
    return loops;
}

// Two loops of independent seeds on the same label changes (each
// iteration relabels a random stretch of the bar): their carried-over
// estimates differ by their combined reported error at iterations 1, 4 and
// 16, as two plain renders do.
TEST(CarryOver, ErrorsStayHonestAsSamplesAccumulate) {
    auto loops = twoLoops(writeBarScene("honest"), CarryOver::Method::KeptSamples, 1);
    for (int k = 0; k < 2; ++k) loops[k]->settings().seed = 100 + uint64_t(k);
    Rng rng(3, 1);
    for (int iteration = 1; iteration <= 16; ++iteration) {
        SurfacePrediction p[2];
        for (int k = 0; k < 2; ++k) p[k] = loops[k]->predict();
        if (iteration == 1 || iteration == 4 || iteration == 16) {
            expectHonest(zScores(p[0], p[1]), "iteration " + std::to_string(iteration));
            EXPECT_EQ(p[0].samples[0], uint32_t(iteration));
        }
        const int x0 = int(rng.next32() % 100);
        const std::vector<LabelGrid::Change> changes = changesAt(x0, x0 + 8, uint64_t(iteration));
        for (int k = 0; k < 2; ++k) loops[k]->changeLabels(changes);
    }
}

// The running estimate by control variates over a loop of 16 predictions,
// a new seed each, on small label changes: two loops of independent seeds
// differ by their combined error at iterations 1, 4 and 16; at 16 the
// estimate agrees with a render of many samples within its error (no bias
// from the weights); and its variance has fallen well below one
// prediction's.
TEST(CarryOver, ControlVariatesStayHonestAndGetLessNoisy) {
    const fs::path scene = writeBarScene("control_variates");
    auto loops = twoLoops(scene, CarryOver::Method::ControlVariates, 2);
    Rng rng(3, 1);
    SurfacePrediction p[2];
    double firstVariance = 0;
    for (int iteration = 1; iteration <= 16; ++iteration) {
        for (int k = 0; k < 2; ++k) {
            loops[k]->settings().seed = 1000 * uint64_t(k + 1) + uint64_t(iteration);
            p[k] = loops[k]->predict();
            EXPECT_EQ(p[k].startedAfresh, iteration == 1);
        }
        if (iteration == 1) firstVariance = meanVariance(p[0]);
        if (iteration == 1 || iteration == 4 || iteration == 16)
            expectHonest(zScores(p[0], p[1]), "iteration " + std::to_string(iteration));
        if (iteration == 16) break;
        const int x0 = int(rng.next32() % 100);
        const std::vector<LabelGrid::Change> changes = changesAt(x0, x0 + 8, uint64_t(iteration));
        for (int k = 0; k < 2; ++k) loops[k]->changeLabels(changes);
    }
    EXPECT_LT(meanVariance(p[0]), 0.25 * firstVariance);
    EXPECT_GT(p[0].retracedVoxels, 0u);
    EXPECT_LT(p[0].retracedVoxels, p[0].radiance.size() / 2);

    auto reference = Predictor::fromSceneFile(scene);
    reference->setLabels(loops[0]->labels().withChanges({}));
    reference->settings().spp = 64;
    reference->settings().seed = 77;
    expectHonest(zScores(p[0], reference->predict()), "against the reference");
}

TEST(CarryOver, StartsAfreshOnANewGridOrOtherSettings) {
    const fs::path scene = writeBarScene("afresh");
    auto predictor = Predictor::fromSceneFile(scene);
    predictor->carryOver().enabled = true;
    predictor->predict();
    predictor->settings().spp = 6;  // the samples a prediction adds: carried on
    SurfacePrediction p = predictor->predict();
    EXPECT_FALSE(p.startedAfresh);
    EXPECT_EQ(p.samples[0], 9u);
    predictor->settings().seed += 1;
    p = predictor->predict();
    EXPECT_TRUE(p.startedAfresh);
    EXPECT_EQ(p.samples[0], 6u);
    predictor->setLabels(predictor->labels().withChanges({}));
    EXPECT_TRUE(predictor->predict().startedAfresh);
    // Control variates: a new seed carries on, the same seed (the same
    // samples again) starts afresh.
    predictor->carryOver().method = CarryOver::Method::ControlVariates;
    EXPECT_TRUE(predictor->predict().startedAfresh);
    predictor->settings().seed += 1;
    EXPECT_FALSE(predictor->predict().startedAfresh);
    // A black voxel raises its brick's majorant; put back, the running
    // estimate keeps the majorant raised.
    const Vec3i v{60, 0, 10};
    predictor->changeLabels({{v, kBlack}});
    predictor->settings().seed += 1;
    EXPECT_FALSE(predictor->predict().startedAfresh);
    predictor->changeLabels({{v, barLabel(v)}});
    predictor->settings().seed += 1;
    EXPECT_FALSE(predictor->predict().startedAfresh);
    EXPECT_TRUE(predictor->predict().startedAfresh);
    // Off: a plain prediction, the bits of the predictor without carry-over
    // (the exact majorants again).
    predictor->carryOver().enabled = false;
    const SurfacePrediction off = predictor->predict();
    auto plain = Predictor::fromSceneFile(scene);
    plain->settings() = predictor->settings();
    expectSameBits(off, plain->predict());
}

}  // namespace
}  // namespace pl
