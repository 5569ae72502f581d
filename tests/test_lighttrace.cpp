// lighttrace (integrators/lighttrace.h) against the exact white furnace
// and against volpath with the same patch footprint, voxel by voxel, on
// boxes of one material and of a halftone, with and without a refractive
// boundary. Tolerances come from the standard errors both report.
#include <gtest/gtest.h>

#include "render_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

const Vec3i kResolution{12, 10, 8};
const Vec3f kVoxel_mm{0.05f, 0.04f, 0.06f};  // anisotropic on purpose

struct Agreement {
    double meanA = 0, meanB = 0, errorOfMeanDifference = 0;
    size_t values = 0, beyond4Sigma = 0;
};

// Voxel by voxel and channel by channel: how many differ by more than 4
// combined standard errors, and the means over all of them.
Agreement compare(const RenderResult& a, const RenderResult& b) {
    Agreement r;
    double variance = 0;
    for (size_t p = 0; p < a.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            const double ea = a.film.standardError(p, c), eb = b.film.standardError(p, c);
            r.meanA += a.film.mean(p, c);
            r.meanB += b.film.mean(p, c);
            variance += ea * ea + eb * eb;
            r.beyond4Sigma += std::abs(a.film.mean(p, c) - b.film.mean(p, c)) > 4.0 * std::sqrt(ea * ea + eb * eb);
            if (getenv("DBG") && std::abs(a.film.mean(p, c) - b.film.mean(p, c)) > 4.0 * std::sqrt(ea * ea + eb * eb))
                printf("p %zu c %d  %g +- %g  vs %g +- %g\n", p, c, a.film.mean(p, c), ea, b.film.mean(p, c), eb);
            ++r.values;
        }
    r.meanA /= double(r.values);
    r.meanB /= double(r.values);
    r.errorOfMeanDifference = std::sqrt(variance) / double(r.values);
    return r;
}

RenderResult renderPatches(const Scene& scene, const std::string& integrator, uint32_t spp, uint64_t seed) {
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    s.integrator = integrator;
    s.spp = spp;
    s.seed = seed;
    return render(scene, sensor, s);
}

void expectAgreementWithVolpath(const Scene& scene, const std::string& what) {
    const uint32_t k = getenv("SPPK") ? atoi(getenv("SPPK")) : 1;
    const RenderResult light = renderPatches(scene, "lighttrace", 16 * k, 1);
    const RenderResult reference = renderPatches(scene, "volpath", 64 * k, 2);
    const Agreement a = compare(light, reference);
    EXPECT_NEAR(a.meanA, a.meanB, 4.0 * a.errorOfMeanDifference) << what;
    EXPECT_LT(a.beyond4Sigma, a.values / 100 + 2) << what << ": values beyond 4 sigma of " << a.values;
    EXPECT_GT(a.meanA, 0.05) << what;
}

TEST(LightTrace, WhiteFurnaceIsTheEnvironment) {
    MaterialTable t = test::tableOf({{4, material({20, 30, 10}, {1, 1, 1}, {0.4f, 0.0f, -0.3f})}});
    const Scene scene = test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, 1.5f,
                                       {1.0f, 0.5f, 2.0f});
    const RenderResult r = renderPatches(scene, "lighttrace", 16, 1);
    size_t beyond = 0, values = 0;
    double sum[3] = {0, 0, 0}, variance[3] = {0, 0, 0};
    for (size_t p = 0; p < r.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            const double Le = scene.environment[c], e = r.film.standardError(p, c);
            sum[c] += r.film.mean(p, c);
            variance[c] += e * e;
            beyond += std::abs(r.film.mean(p, c) - Le) > 4.0 * e;
            ++values;
        }
    const double n = double(r.film.pixelCount());
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(sum[c] / n, scene.environment[c], 4.0 * std::sqrt(variance[c]) / n) << "channel " << c;
    EXPECT_LT(beyond, values / 100 + 2);
}

TEST(LightTrace, AgreesWithVolpathOnOneMaterial) {
    MaterialTable t = test::tableOf({{4, material({20, 30, 10}, {0.95f, 0.9f, 0.99f}, {0.4f, 0.0f, 0.6f})}});
    for (float ior : {1.0f, 1.5f})
        expectAgreementWithVolpath(
            test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, ior),
            "ior " + std::to_string(ior));
}

TEST(LightTrace, AgreesWithVolpathOnAHalftone) {
    MaterialTable t = test::tableOf({{0, material({30, 30, 30}, {0.2f, 0.9f, 0.95f}, {0.3f, 0.3f, 0.3f})},
                                     {4, material({20, 20, 20}, {0.99f, 0.99f, 0.99f}, {0.3f, 0.3f, 0.3f})},
                                     {3, material({40, 40, 40}, {0.1f, 0.1f, 0.1f}, {0.0f, 0.0f, 0.0f})}});
    auto halftone = [](const Vec3i& v) {
        const uint64_t h = mix64(uint64_t(v.x) * 73856093u ^ uint64_t(v.y) * 19349663u ^ uint64_t(v.z) * 83492791u);
        return Label(h % 3 == 0 ? 0 : h % 3 == 1 ? 4 : 3);
    };
    expectAgreementWithVolpath(test::boxScene(kResolution, kVoxel_mm, halftone, t, 1.5f), "halftone");
}

}  // namespace
}  // namespace pl
