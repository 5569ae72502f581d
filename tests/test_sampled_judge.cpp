// The judge of sampled footprints (compare/footprint_sample.h,
// api/appearance_optimizer.h judgeLabels): a footprint's mean is the eye's
// Gaussian's at its centre; the 95 % interval of a stratified sample's
// mean covers the whole surface's mean as often as it says, on values
// with the spatial structure of a print; and a judge of sampled footprints
// covers the whole-surface judge's error over repeats.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

#include "api/appearance_optimizer.h"
#include "compare/footprint_sample.h"
#include "compare/surface_colour_error.h"
#include "compare/surface_gaussian.h"
#include "core/rng.h"
#include "io/grid_io.h"
#include "io/mesh_io.h"
#include "test_util.h"

namespace pl {
namespace {

namespace fs = std::filesystem;

// A 6 x 3 x 1 mm plate of 0.05 mm voxels: white, its 0.15 mm shell a
// halftone of cyan and magenta whose share drifts along x (the error
// varies over the surface, and at the edges).
const Vec3i kPlate{120, 60, 20};
Label plateLabel(const Vec3i& v) {
    const bool shell = v.x < 3 || v.y < 3 || v.z < 3 || v.x >= kPlate.x - 3 || v.y >= kPlate.y - 3 || v.z >= kPlate.z - 3;
    if (!shell) return 4;
    const double magentaShare = 0.1 + 0.6 * v.x / double(kPlate.x);
    return double(mix64(uint64_t(v.x) * 7919 + uint64_t(v.y) * 131 + uint64_t(v.z)) % 1000) < 1000 * magentaShare ? 1 : 0;
}

fs::path writePlateScene(const std::string& integrator) {
    fs::path dir = test::freshTempDir("sampled_judge_" + integrator);
    writeObj(test::boxMesh({0, 0, 0}, {6, 3, 1}), dir / "plate.obj");
    writeLabelGridBin(test::boxGrid(kPlate, {0.05f, 0.05f, 0.05f}, plateLabel), dir / "grid.bin");
    fs::copy_file(test::sourceDir() / "data/materials/resins_illustrative.json", dir / "materials.json");
    std::ofstream(dir / "scene.json") << R"({"object": {"mesh": "plate.obj", "labels": "grid.bin", "materials": "materials.json"},
        "sensor": {"type": "surface_voxels"},
        "render": {"integrator": ")" << integrator << R"(", "spp": 1, "seed": 5}})";
    return dir / "scene.json";
}

std::vector<Point3f> platePoints() {
    std::vector<Point3f> points;
    for (const SurfaceVoxel& v : test::boxGrid(kPlate, {0.05f, 0.05f, 0.05f}, plateLabel).surfaceVoxels())
        points.push_back({(v.voxel.x + 0.5f) * 0.05f, (v.voxel.y + 0.5f) * 0.05f, (v.voxel.z + 0.5f) * 0.05f});
    return points;
}

TEST(FootprintSample, FootprintsAreTheEyesGaussianAtTheirCentresOnePerStratum) {
    const std::vector<Point3f> points = platePoints();
    std::vector<RGB> values(points.size());
    Rng rng(1, 2);
    for (RGB& v : values) v = {rng.uniform(), rng.uniform(), 10 * rng.uniform()};
    const SurfaceGaussian eye(points, kEyeFootprint_mm);
    const FootprintSample sample(points, eye, kEyeFootprint_mm, 40, 7);
    ASSERT_EQ(sample.size(), 40u);
    EXPECT_EQ(std::set<uint32_t>(sample.centres().begin(), sample.centres().end()).size(), 40u);
    const std::vector<RGB> whole = eye.apply(values), sampled = sample.apply(values);
    for (size_t k = 0; k < sample.size(); ++k)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(sampled[k][c], whole[sample.centres()[k]][c], 1e-5 * (1 + std::abs(whole[sample.centres()[k]][c])));
    // Another seed, other centres; the same seed, the same.
    EXPECT_NE(FootprintSample(points, eye, kEyeFootprint_mm, 40, 8).centres(), sample.centres());
    EXPECT_EQ(FootprintSample(points, eye, kEyeFootprint_mm, 40, 7).centres(), sample.centres());
    // Every point a footprint weighs is among the points to render: values
    // elsewhere change nothing.
    EXPECT_LT(sample.points().size(), points.size());
    std::vector<RGB> onlyRendered(points.size(), RGB{1e6f, 1e6f, 1e6f});
    for (uint32_t i : sample.points()) onlyRendered[i] = values[i];
    EXPECT_EQ(sample.apply(onlyRendered), sampled);
}

// Values with a print's structure (a gradient, edges, grain): over 400
// seeds the 95 % interval of 30 sampled footprints' mean covers the mean of
// every point's footprint at least 370 times (binomial: 380 expected),
// and it is not merely wide.
TEST(FootprintSample, IntervalsCoverTheWholeSurfacesMeanAsOftenAsTheySay) {
    const std::vector<Point3f> points = platePoints();
    std::vector<RGB> values(points.size());
    Rng rng(3, 4);
    for (size_t i = 0; i < points.size(); ++i) {
        const Point3f& p = points[i];
        const bool edge = std::min({p.x, 6 - p.x, p.y, 3 - p.y, p.z, 1 - p.z}) < 0.2f && (p.z < 0.1f || p.z > 0.9f);
        values[i] = {float(p.x / 6 + (edge ? 1.5 : 0) + 0.5 * rng.uniform()), 0, 0};
    }
    const SurfaceGaussian eye(points, kEyeFootprint_mm);
    const std::vector<RGB> seen = eye.apply(values);
    double wholeMean = 0;
    for (const RGB& v : seen) wholeMean += v[0];
    wholeMean /= double(seen.size());
    int covered = 0;
    double squareMiss = 0, halfWidths = 0;
    for (uint64_t seed = 0; seed < 400; ++seed) {
        const FootprintSample sample(points, eye, kEyeFootprint_mm, 30, seed);
        std::vector<double> x;
        for (const RGB& v : sample.apply(values)) x.push_back(v[0]);
        const SampledMean m = stratifiedMean(x);
        covered += std::abs(m.mean - wholeMean) <= m.halfWidth95;
        squareMiss += (m.mean - wholeMean) * (m.mean - wholeMean);
        halfWidths += m.halfWidth95;
    }
    EXPECT_GE(covered, 370);
    // Not honest by being wide: the mean half width within 1.5-4 standard
    // deviations of the estimates (1.96 for an exact interval; the strata
    // make it wider).
    const double spread = std::sqrt(squareMiss / 400);
    EXPECT_GT(halfWidths / 400, 1.5 * spread);
    EXPECT_LT(halfWidths / 400, 4.0 * spread);
}

// The judge on the plate's labels against a grey target, by the diffusion
// predictor (deterministic: the whole surface's judge is exact): over 20
// seeds, 12 sampled footprints' 95 % interval covers the whole judge's
// mean error over the footprint at least 16 times (19 expected; fewer
// than 16 has probability 0.3 % for an honest interval), and it renders a
// part of the surface only.
TEST(SampledJudge, CoversTheWholeSurfacesJudgeOverRepeats) {
    auto predictor = Predictor::fromSceneFile(writePlateScene("diffusion"));
    const std::vector<RGB> mapped(predictor->surfaceVoxelCount(), RGB{0.25f, 0.2f, 0.45f});
    OptimizeSettings settings;
    settings.judge = true;
    settings.judgeSpp = 2;
    settings.judgeFootprints = 0;
    const OptimizeJudgement whole = judgeLabels(*predictor, settings, mapped);
    EXPECT_EQ(whole.footprints, 0u);
    EXPECT_GT(whole.meanDeltaEFiltered, 1.0);
    settings.judgeFootprints = 12;
    int covered = 0;
    for (uint64_t seed = 0; seed < 20; ++seed) {
        settings.judgeSeed = seed;
        const OptimizeJudgement j = judgeLabels(*predictor, settings, mapped);
        ASSERT_EQ(j.footprints, 12u);
        EXPECT_LT(j.renderedVoxels, predictor->surfaceVoxelCount() / 2);
        covered += std::abs(j.meanDeltaEFiltered - whole.meanDeltaEFiltered) <= j.meanDeltaEFilteredHalfWidth95;
    }
    EXPECT_GE(covered, 16);
}

}  // namespace
}  // namespace pl
