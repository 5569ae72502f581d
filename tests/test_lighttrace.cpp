// lighttrace (integrators/lighttrace/lighttrace.h) against the exact white furnace
// and against volpath with the same patch footprint, voxel by voxel, on
// boxes of one material and of a halftone, with and without a refractive
// boundary. Tolerances come from the standard errors both report (a
// voxel's light-side error from its particles' squared scores; the blocks
// here hold 4 particles per voxel). tests/test_error_honesty.cpp checks
// those errors at the default of 1.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "integrators/lighttrace/lighttrace.h"
#include "media/slab_transport.h"
#include "render_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

const Vec3i kResolution{12, 10, 8};
const Vec3f kVoxel_mm{0.05f, 0.04f, 0.06f};  // anisotropic on purpose

struct Agreement {
    double meanA = 0, meanB = 0;
    size_t values = 0, beyond4Sigma = 0;
};

// Voxel by voxel and channel by channel: how many differ by more than 4
// combined standard errors, and the means over all of them.
Agreement compare(const RenderResult& a, const RenderResult& b) {
    Agreement r;
    for (size_t p = 0; p < a.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            const double ea = a.film.standardError(p, c), eb = b.film.standardError(p, c);
            r.meanA += a.film.mean(p, c);
            r.meanB += b.film.mean(p, c);
            r.beyond4Sigma += std::abs(a.film.mean(p, c) - b.film.mean(p, c)) > 4.0 * std::sqrt(ea * ea + eb * eb);
            ++r.values;
        }
    r.meanA /= double(r.values);
    r.meanB /= double(r.values);
    return r;
}

RenderResult renderPatches(const Scene& scene, const std::string& integrator, uint32_t spp, uint64_t seed) {
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    s.integrator = integrator;
    s.spp = spp;
    s.seed = seed;
    s.parameters.set("particles_per_pixel", 4);
    return render(scene, sensor, s);
}

// lighttrace sample by sample: the film, and per channel the object's mean
// with its standard error from the spread of the samples' object means.
// One particle scores into neighbouring voxels, so the pixels' errors are
// correlated and do not add in quadrature.
struct BlockwiseRender {
    RenderResult result;
    test::Estimate objectMean;
};
// hybrid: whether printpt takes the pixels it serves better
// (LightTraceOptions::hybrid; false: the light side scores into every
// pixel but slivers).
BlockwiseRender renderLightBlocks(const Scene& scene, uint32_t spp, uint64_t seed, bool hybrid,
                                  LightTraceOptions::Scoring scoring = LightTraceOptions{}.scoring) {
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    s.integrator = "lighttrace";
    s.seed = seed;
    s.parameters.set("particles_per_pixel", 4);
    s.parameters.set("lighttrace_hybrid", hybrid);
    s.parameters.setText("lighttrace_scoring", enumName(kLightTraceScoringNames, scoring));
    const auto integrator = makeIntegrator(scene, sensor, s);
    BlockwiseRender b{RenderResult{Film(sensor.pixelCount())}, {}};
    const double n = double(sensor.pixelCount());
    double previous[3] = {0, 0, 0}, sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0};
    for (uint32_t sample = 0; sample < spp; ++sample) {
        renderSamples(*integrator, scene, sensor, s, {}, sample, 1, b.result);
        for (int c = 0; c < 3; ++c) {
            double total = 0;
            for (size_t p = 0; p < sensor.pixelCount(); ++p)
                total += double(b.result.film.mean(p, c)) * b.result.film.samples(p, c);
            const double blockMean = (total - previous[c]) / n;
            previous[c] = total;
            sum[c] += blockMean;
            sumSq[c] += blockMean * blockMean;
        }
    }
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / spp, variance = std::max(0.0, (sumSq[c] - spp * mean * mean) / (spp - 1.0));
        b.objectMean.mean[c] = float(mean);
        b.objectMean.standardError[c] = float(std::sqrt(variance / spp));
    }
    return b;
}

void expectAgreementWithVolpath(const Scene& scene, const std::string& what, bool hybrid,
                                LightTraceOptions::Scoring scoring = LightTraceOptions{}.scoring) {
    const BlockwiseRender blocks = renderLightBlocks(scene, 16, 1, hybrid, scoring);
    const RenderResult& light = blocks.result;
    // Enough volpath samples that a black voxel's reflection (F = 0.04)
    // is surely met: a pixel whose samples are all equal reports no error.
    const RenderResult reference = renderPatches(scene, "volpath", 256, 2);
    const Agreement a = compare(light, reference);
    // The object's means: lighttrace's error from its blocks (16: a t
    // distribution with 15 degrees of freedom, hence 5 rather than 4).
    const test::Estimate volpathMean = test::meanOf(reference);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(blocks.objectMean.mean[c], volpathMean.mean[c],
                    5.0 * std::hypot(blocks.objectMean.standardError[c], volpathMean.standardError[c]))
            << what << ", channel " << c;
    EXPECT_LT(a.beyond4Sigma, a.values / 100 + 2) << what << ": values beyond 4 sigma of " << a.values;
    EXPECT_GT(a.meanA, 0.05) << what;
}

TEST(LightTrace, WhiteFurnaceIsTheEnvironment) {
    MaterialTable t = test::tableOf({{4, material({20, 30, 10}, {1, 1, 1}, {0.4f, 0.0f, -0.3f})}});
    const Scene scene = test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, 1.5f,
                                       {1.0f, 0.5f, 2.0f});
    const BlockwiseRender b = renderLightBlocks(scene, 16, 1, false);
    size_t beyond = 0, values = 0;
    for (size_t p = 0; p < b.result.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            beyond += std::abs(b.result.film.mean(p, c) - scene.environment[c]) > 4.0 * b.result.film.standardError(p, c);
            ++values;
        }
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(b.objectMean.mean[c], scene.environment[c], 5.0 * b.objectMean.standardError[c]) << "channel " << c;
    EXPECT_LT(beyond, values / 100 + 2);
}

// One scattering material, the light side in every pixel, scoring along
// tracks (the default) and at collisions.
TEST(LightTrace, AgreesWithVolpathOnOneMaterial) {
    MaterialTable t = test::tableOf({{4, material({20, 30, 10}, {0.95f, 0.9f, 0.99f}, {0.4f, 0.0f, 0.6f})}});
    for (float ior : {1.0f, 1.5f})
        expectAgreementWithVolpath(
            test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, ior),
            "ior " + std::to_string(ior), false);
    expectAgreementWithVolpath(test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, 1.5f),
                               "collisions", false, LightTraceOptions::Scoring::Collisions);
}

// A box of one resin over its first four 8^3 bricks along x (white) and a
// halftone of two beyond (x >= 32).
Scene hybridBox() {
    MaterialTable t = test::tableOf({{0, material({200, 200, 200}, {0.2f, 0.9f, 0.95f}, {0.3f, 0.3f, 0.3f})},
                                     {4, material({200, 300, 300}, {0.95f, 0.9f, 0.97f}, {0.4f, 0.0f, 0.6f})}});
    auto labels = [](const Vec3i& v) {
        if (v.x < 32) return Label(4);
        return Label(mix64(uint64_t(v.x) * 73856093u ^ uint64_t(v.y) * 19349663u ^ uint64_t(v.z) * 83492791u) % 2 ? 4 : 0);
    };
    return test::boxScene({40, 10, 8}, kVoxel_mm, labels, t, 1.5f);
}

// The hybrid: printpt takes the pixels over one resin and the light side
// those over the halftone (hybridBox); particles enter the first two
// bricks at a lower rate, weighted back. Together they agree with volpath.
TEST(LightTrace, HybridAgreesWithVolpath) {
    const Scene box = hybridBox();
    SurfaceVoxelSensor sensor(*box.geometry, box.medium->frame(), box.medium->grid().surfaceVoxels(),
                              SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    LightTrace hybrid(box, sensor, LightTraceOptions{}, VolPathOptions{}, PrintPtOptions{}, s.majorants, s.seed);
    hybrid.preprocess(sensor, {0, 1, 2});
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(hybrid.cameraOnlyPixels(c), sensor.pixelCount() / 2) << c;
        EXPECT_LT(hybrid.cameraOnlyPixels(c), 9 * sensor.pixelCount() / 10) << c;
    }
    expectAgreementWithVolpath(box, "hybrid", true);
}

TEST(LightTrace, AgreesWithVolpathOnAHalftone) {
    MaterialTable t = test::tableOf({{0, material({30, 30, 30}, {0.2f, 0.9f, 0.95f}, {0.3f, 0.3f, 0.3f})},
                                     {4, material({20, 20, 20}, {0.99f, 0.99f, 0.99f}, {0.3f, 0.3f, 0.3f})},
                                     {3, material({40, 40, 40}, {0.1f, 0.1f, 0.1f}, {0.0f, 0.0f, 0.0f})}});
    auto halftone = [](const Vec3i& v) {
        const uint64_t h = mix64(uint64_t(v.x) * 73856093u ^ uint64_t(v.y) * 19349663u ^ uint64_t(v.z) * 83492791u);
        return Label(h % 3 == 0 ? 0 : h % 3 == 1 ? 4 : 3);
    };
    expectAgreementWithVolpath(test::boxScene(kResolution, kVoxel_mm, halftone, t, 1.5f), "halftone", true);
}

// A ball (a curved mesh cut into patches, some of them slivers that the
// light side leaves to volpath) of a halftone: voxel by voxel as volpath.
// The mesh has no file normals: lighttrace leaves along the geometric
// normal, where volpath would refract the sensor's ray by a shading normal.
TEST(LightTrace, AgreesWithVolpathOnACurvedHalftone) {
    MaterialTable t = test::tableOf({{0, material({30, 30, 30}, {0.2f, 0.9f, 0.95f}, {0.3f, 0.3f, 0.3f})},
                                     {4, material({20, 20, 20}, {0.99f, 0.99f, 0.99f}, {0.3f, 0.3f, 0.3f})}});
    const float radius_mm = 0.45f, voxel_mm = 0.05f;
    const Point3f centre{0.5f, 0.5f, 0.5f};
    LabelGrid grid = test::boxGrid({20, 20, 20}, {voxel_mm, voxel_mm, voxel_mm}, [&](const Vec3i& v) {
        const Point3f c{(v.x + 0.5f) * voxel_mm, (v.y + 0.5f) * voxel_mm, (v.z + 0.5f) * voxel_mm};
        if (!(length(c - centre) < radius_mm)) return test::kTestVoid;
        return Label(mix64(uint64_t(v.x) * 73856093u ^ uint64_t(v.y) * 19349663u ^ uint64_t(v.z) * 83492791u) % 2 ? 4 : 0);
    });
    TriangleMesh ball = synthetic::sphereMesh(centre, radius_mm, 48);
    ball.normals.clear();
    const Scene scene = synthetic::sceneOf(std::move(ball), std::move(grid), t, 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    s.integrator = "lighttrace";
    const LightTrace probe(scene, sensor, readOptions(lightTraceParameters(), s.parameters), VolPathOptions{},
                           PrintPtOptions{}, s.majorants, s.seed);
    EXPECT_GT(probe.cameraOnlyPixels(0), 0u);
    EXPECT_LT(probe.cameraOnlyPixels(0), sensor.pixelCount() / 4);
    expectAgreementWithVolpath(scene, "ball", true);
}

// The deterministic discrete-ordinates solve of a slab (media/slab_transport.h)
// on the central voxels of a 2 x 2 x 0.6 mm slab at sigma_t 100 /mm, n = 1.5
// (the centre is 9 diffusion lengths of the most scattering channel from
// the sides): every voxel within 4 of its reported standard errors, bar
// 1 % and one more.
// The particles cover the whole slab, so there are many per pixel.
TEST(LightTrace, SlabAgainstTheDeterministicSolver) {
    const RGB albedo{0.9f, 0.5f, 0.95f}, g{0.0f, 0.4f, 0.4f};
    constexpr float kSigmaT_perMm = 100.0f, kIor = 1.5f, kSlabVoxel_mm = 0.1f;
    constexpr int kSide = 20, kLayers = 6;
    MaterialTable t = test::tableOf({{4, material({kSigmaT_perMm, kSigmaT_perMm, kSigmaT_perMm}, albedo, g)}});
    const Scene scene = test::boxScene({kSide, kSide, kLayers}, {kSlabVoxel_mm, kSlabVoxel_mm, kSlabVoxel_mm},
                                       [](const Vec3i&) { return Label(4); }, t, kIor);
    std::vector<SurfaceVoxel> centre;
    for (const SurfaceVoxel& v : scene.medium->grid().surfaceVoxels())
        if (v.voxel.z == kLayers - 1 && std::abs(2 * v.voxel.x + 1 - kSide) < 6 && std::abs(2 * v.voxel.y + 1 - kSide) < 6)
            centre.push_back(v);
    ASSERT_EQ(centre.size(), 36u);
    SurfaceVoxelSensor sensor(*scene.geometry, scene.medium->frame(), centre, SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    s.integrator = "lighttrace";
    s.spp = 16;
    s.parameters.set("particles_per_pixel", 300);
    s.parameters.set("lighttrace_hybrid", false);  // the light side everywhere
    const RenderResult r = render(scene, sensor, s);
    const double specular = std::pow((kIor - 1.0) / (kIor + 1.0), 2);
    for (int c = 0; c < 3; ++c) {
        const SlabEscape e = slabEscape({albedo[c], g[c], kIor, double(kSigmaT_perMm) * kLayers * kSlabVoxel_mm});
        const double reference = specular + (1.0 - specular) * (e.top + e.bottom);
        size_t beyond = 0;
        double sum = 0;
        for (size_t p = 0; p < r.film.pixelCount(); ++p) {
            EXPECT_GT(r.film.standardError(p, c), 0.0f);
            beyond += std::abs(r.film.mean(p, c) - reference) > 4.0 * r.film.standardError(p, c);
            sum += r.film.mean(p, c);
        }
        // Errors from 16 blocks: t-distributed with 15 degrees of freedom,
        // P(|t| > 4) ~ 0.0012, so one of the 36 values beyond 4 sigma
        // happens in about 4 % of runs; allow one.
        EXPECT_LE(beyond, r.film.pixelCount() / 100 + 1) << "channel " << c;
        // The pixels share particles: their mean is only checked loosely.
        EXPECT_NEAR(sum / double(r.film.pixelCount()), reference, 0.05 * reference) << "channel " << c;
    }
}

// Blocks are cut into fixed parts added in order: the same bits for any
// thread count, and another seed gives another image.
TEST(LightTrace, SameBitsForOneAndTwoThreads) {
    MaterialTable t = test::tableOf({{0, material({10, 8, 8}, {0.25f, 0.97f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                                     {4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})}});
    const Scene scene = test::boxScene(kResolution, kVoxel_mm, [](const Vec3i& v) { return Label((v.x + v.z) % 2 ? 4 : 0); },
                                       t, 1.5f);
    auto renderWith = [&](int threads, uint64_t seed) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return renderPatches(scene, "lighttrace", 3, seed);
    };
    const RenderResult a = renderWith(1, 7), b = renderWith(2, 7), c = renderWith(2, 8);
    bool differs = false;
    for (size_t p = 0; p < a.film.pixelCount(); ++p)
        for (int ch = 0; ch < 3; ++ch) {
            ASSERT_EQ(a.film.mean(p, ch), b.film.mean(p, ch));
            ASSERT_EQ(a.film.standardError(p, ch), b.film.standardError(p, ch));
            differs = differs || a.film.mean(p, ch) != c.film.mean(p, ch);
        }
    EXPECT_EQ(a.stats.scatterEvents, b.stats.scatterEvents);
    EXPECT_TRUE(differs);
}

// A one-shot render opens each channel as its pass starts and settles it
// after (Film::settleChannel): the same means and errors, bit for bit, as
// the channels' accumulators pooled together at the end, on the hybrid's
// box (light-side blocks, printpt's controls and pools) and with volpath.
TEST(LightTrace, SettlingEachPassKeepsTheValues) {
    const Scene box = hybridBox();
    SurfaceVoxelSensor sensor(*box.geometry, box.medium->frame(), box.medium->grid().surfaceVoxels(),
                              SurfaceVoxelSensor::Footprint::Patch);
    for (const char* integrator : {"lighttrace", "volpath"}) {
        RenderSettings s;
        s.integrator = integrator;
        s.spp = 3;
        const RenderResult settled = render(box, sensor, s);
        RenderResult pooled{Film(sensor.pixelCount())};
        renderSamples(*makeIntegrator(box, sensor, s), box, sensor, s, {}, 0, s.spp, pooled);
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(settled.film.settled(c));
            EXPECT_FALSE(pooled.film.settled(c));
        }
        size_t withError = 0, withSharedError = 0;
        for (size_t p = 0; p < sensor.pixelCount(); ++p)
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(settled.film.mean(p, c), pooled.film.mean(p, c)) << integrator;
                ASSERT_EQ(settled.film.samples(p, c), pooled.film.samples(p, c)) << integrator;
                ASSERT_EQ(settled.film.spreadError(p, c), pooled.film.spreadError(p, c)) << integrator;
                ASSERT_EQ(settled.film.independentError(p, c), pooled.film.independentError(p, c)) << integrator;
                ASSERT_EQ(settled.film.sharedError(p, c), pooled.film.sharedError(p, c)) << integrator;
                withError += settled.film.independentError(p, c) > 0.0f;
                withSharedError += settled.film.sharedError(p, c) > 0.0f;
            }
        EXPECT_GT(withError, sensor.pixelCount() * 2) << integrator;
        if (std::string(integrator) == "lighttrace") {
            EXPECT_GT(withSharedError, 0u);
        }
    }
    // A channel not rendered is opened by no pass: settled with no samples.
    RenderSettings green;
    green.integrator = "volpath";
    green.spp = 2;
    green.channels = {1};
    const RenderResult g = render(box, sensor, green);
    for (size_t p = 0; p < sensor.pixelCount(); ++p) {
        ASSERT_EQ(g.film.samples(p, 0), 0u);
        ASSERT_EQ(g.film.mean(p, 2), 0.0f);
        ASSERT_EQ(g.film.samples(p, 1), 2u);
    }
}

// A notch of void under a flat face: the voxels behind it are surface
// voxels the mesh does not cross (empty patches). printpt serves them along
// the sensor's ray, the light side the rest.
TEST(LightTrace, LeavesEmptyPatchesToPrintPt) {
    MaterialTable t = test::tableOf({{4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})}});
    auto notched = [](const Vec3i& v) {
        return v.x == 0 && v.y >= 4 && v.y < 6 && v.z >= 3 && v.z < 5 ? test::kTestVoid : Label(4);
    };
    const Scene scene = test::boxScene(kResolution, kVoxel_mm, notched, t, 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
    ASSERT_EQ(sensor.patches()->emptyPatches(), 4u);
    RenderSettings s;
    s.integrator = "lighttrace";
    s.spp = 2;
    s.parameters.set("lighttrace_hybrid", false);
    const LightTrace probe(scene, sensor, readOptions(lightTraceParameters(), s.parameters), VolPathOptions{},
                           PrintPtOptions{}, s.majorants, s.seed);
    for (int c = 0; c < 3; ++c) EXPECT_GE(probe.cameraOnlyPixels(c), 4u);
    const RenderResult r = render(scene, sensor, s);
    for (size_t p = 0; p < r.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(r.film.mean(p, c)));
            EXPECT_GT(r.film.mean(p, c), 0.0f);
        }
}

// Other sensors have no patches to score into: a clear refusal.
TEST(LightTrace, RefusesASensorWithoutPatches) {
    MaterialTable t = test::tableOf({{4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})}});
    const Scene scene = test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor raySensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    RenderSettings s;
    s.integrator = "lighttrace";
    s.spp = 1;
    EXPECT_THROW(render(scene, raySensor, s), std::invalid_argument);
}

}  // namespace
}  // namespace pl
