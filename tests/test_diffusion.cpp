// The diffusion predictor (integrators/diffusion/diffusion.h) against closed forms
// and the exact half-space: its exact single scattering through a layered
// column, its sum of the profile over the surface (on a flat face far from
// the edges it must give the profile's total), and its bias against the
// deterministic solver within what docs/diffusion.md reports.
#include <gtest/gtest.h>

#include <cmath>

#include <tbb/global_control.h>

#include "integrators/diffusion/diffusion.h"
#include "media/beam_diffusion.h"
#include "media/slab_transport.h"
#include "render/render.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

constexpr float kIor = 1.5f, kVoxel_mm = 0.1f;
constexpr int kSide = 80;  // 8 mm

// A thick block (4 mm deep at sigma_t 100 /mm: a half-space, the centre of
// its top tens of diffusion lengths from the sides); one albedo per channel.
Scene blockScene(const RGB& albedo, float sigmaT_perMm = 100.0f, int layers = 40) {
    MaterialTable t = test::tableOf({{4, material({sigmaT_perMm, sigmaT_perMm, sigmaT_perMm}, albedo, {0.4f, 0.4f, 0.4f})}});
    return test::boxScene({kSide, kSide, layers}, {kVoxel_mm, kVoxel_mm, kVoxel_mm},
                          [](const Vec3i&) { return Label(4); }, t, kIor);
}

SurfaceVoxelSensor topCentre(const Scene& scene, int layers = 40) {
    std::vector<SurfaceVoxel> centre;
    for (const SurfaceVoxel& v : scene.medium->grid().surfaceVoxels())
        if (v.voxel.z == layers - 1 && v.voxel.x >= 35 && v.voxel.x < 45 && v.voxel.y >= 35 && v.voxel.y < 45)
            centre.push_back(v);
    return SurfaceVoxelSensor(*scene.geometry, scene.medium->frame(), centre);
}

RenderResult renderDiffusion(const Scene& scene, const Sensor& sensor) {
    RenderSettings s;
    s.integrator = "diffusion";
    s.spp = 1;
    return render(scene, sensor, s);
}

// The depth table against the deterministic solver: at albedo 1e-4 a
// slab of optical thickness tau brings out single scattering alone (the
// rest is 1e-4 of it), and without a boundary (ior 1) nothing comes back
// from the bottom face, so top / albedo is cumulative(tau).
TEST(Diffusion, SingleScatteringDepthTableMatchesTheSlabSolver) {
    for (double g : {0.0, 0.4, 0.8}) {
        const SingleScatteringDepthTable table(g, 1.0);
        for (double tau : {0.1, 0.5, 2.0, 8.0}) {
            const double solved = slabEscape({1e-4, g, 1.0, tau}).top / 1e-4;
            EXPECT_NEAR(table.cumulative(tau), solved, 2e-3 * solved) << "g " << g << " tau " << tau;
        }
        // And with the boundary, its depth integral is PBD's rho_ss.
        const SingleScatteringDepthTable withBoundary(g, kIor);
        const BeamDiffusion beam({0.9, g, kIor}, 1.0);
        EXPECT_NEAR(0.9 * withBoundary.total(), beam.singleScatteringTotal(), 1e-4 * beam.singleScatteringTotal());
    }
}

// The multiple-scattering table: over the plane it gives the exact
// half-space minus single scattering; the disc integral reaches it; and a
// source spread over a square reads as the square's mean of the profile
// (brute force), whatever the extinction (the sigma^2 and sigma^4 scalings).
TEST(Diffusion, MatchedProfileTableIntegratesAndSpreadsRight) {
    const BeamDiffusionTable table(0.4, kIor, BeamDiffusionTable::Parts::MultipleMatchedToHalfSpace);
    for (double albedo : {0.5, 0.9, 0.995}) {
        const double single = BeamDiffusion({albedo, 0.4, kIor}, 1.0).singleScatteringTotal();
        const double exact = slabEscape({albedo, 0.4, kIor}).top;
        // Matched at the knots; between them, interpolated across albedo.
        EXPECT_NEAR(table.total(albedo) + single, exact, 5e-3 * exact) << albedo;
        EXPECT_NEAR(table.withinRadius(albedo, 6.0, 1e3), table.total(albedo), 1e-9);
        EXPECT_LT(table.withinRadius(albedo, 6.0, 0.1), table.withinRadius(albedo, 6.0, 0.2));
    }
    for (double sigmaT : {6.0, 24.0})
        for (double r_optical : {0.5, 2.0}) {
            const double r_mm = r_optical / sigmaT, side_mm = 0.5 * r_mm;
            double mean = 0;
            const int n = 64;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const double x = r_mm + ((i + 0.5) / n - 0.5) * side_mm, y = ((j + 0.5) / n - 0.5) * side_mm;
                    mean += table.profile_perMm2(0.9, sigmaT, std::hypot(x, y)) / (n * n);
                }
            const double spread = table.spreadProfile_perMm2(0.9, sigmaT, r_mm, side_mm * side_mm / 6.0);
            const double point = table.profile_perMm2(0.9, sigmaT, r_mm);
            // The second-order correction takes most of the way from the
            // centre's value to the square's mean.
            EXPECT_LT(std::abs(spread - mean), 0.35 * std::abs(point - mean)) << sigmaT << " " << r_optical;
        }
}

// On the flat face of a thick block the predictor must give the exact
// half-space (its multiple-scattering profile is scaled to it per albedo,
// media/beam_diffusion.h), from its column and its sum over the surface:
// what is left is the sum's own error (the cluster tree, the patches'
// extent); and the bias bound it reports must cover it.
TEST(Diffusion, FlatFaceOfAThickBlockGivesTheExactHalfSpace) {
    const RGB albedo{0.5f, 0.9f, 0.99f};
    const Scene scene = blockScene(albedo);
    const SurfaceVoxelSensor sensor = topCentre(scene);
    ASSERT_EQ(sensor.pixelCount(), 100u);
    const RenderResult r = renderDiffusion(scene, sensor);
    const double specular = std::pow((kIor - 1.0) / (kIor + 1.0), 2);
    for (int c = 0; c < 3; ++c) {
        const double exact = specular + (1 - specular) * slabEscape({albedo[c], 0.4, kIor}).top;
        for (size_t p = 0; p < sensor.pixelCount(); ++p) {
            const double v = r.film.mean(p, c);
            EXPECT_NEAR(v, exact, 0.02 * (exact - specular)) << "channel " << c << " pixel " << p;
            EXPECT_GE(r.film.sharedError(p, c), std::abs(v - exact)) << "channel " << c << " pixel " << p;
        }
    }
}

// A layered column: under a thin layer (optical thickness 1), single scattering is the layer's
// own plus what lies below attenuated by the layer (the column's optical
// depth, in and out), exactly.
TEST(Diffusion, SingleScatteringFollowsTheLayers) {
    const float sigmaT = 100.0f;
    MaterialTable t = test::tableOf({{4, material({sigmaT, sigmaT, sigmaT}, {0.99f, 0.99f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                                     {3, material({10.0f, 10.0f, 10.0f}, {0.0f, 0.5f, 0.99f}, {0.4f, 0.4f, 0.4f})}});
    const int layers = 40;
    const Scene scene = test::boxScene({kSide, kSide, layers}, {kVoxel_mm, kVoxel_mm, kVoxel_mm},
                                       [&](const Vec3i& v) { return Label(v.z == layers - 1 ? 3 : 4); }, t, kIor);
    // The patch footprint: the predictor's elements are the sensor's pixels.
    const SurfaceVoxelSensor sensor(*scene.geometry, scene.medium->frame(), scene.medium->grid().surfaceVoxels(),
                                    SurfaceVoxelSensor::Footprint::Patch);
    const Diffusion diffusion(scene, sensor);
    const SingleScatteringDepthTable table(0.4, kIor);
    const double inLayer = table.cumulative(10.0f * kVoxel_mm), under = table.total() - inLayer;
    int checked = 0;
    for (size_t p = 0; p < sensor.pixelCount(); ++p) {
        const Vec3i v = sensor.pixels()[p].voxel;
        if (v.z != layers - 1 || v.x < 35 || v.x >= 45 || v.y < 35 || v.y >= 45) continue;
        const RGB& single = diffusion.singleScattering()[p];
        EXPECT_NEAR(single[0], 0.99 * under, 1e-4 * under);
        EXPECT_NEAR(single[1], 0.5 * inLayer + 0.99 * under, 1e-4 * inLayer);
        EXPECT_NEAR(single[2], 0.99 * table.total(), 1e-4 * table.total());
        ++checked;
    }
    EXPECT_EQ(checked, 100);
}

// Under 1.5 mm of clear resin the light reaches a white core far from
// where it entered, which the predictor does not model: those elements
// report the whole range as their error, the others keep their bound.
TEST(Diffusion, ElementsOverClearResinReportTheWholeRange) {
    MaterialTable t = test::tableOf({{4, material({100, 100, 100}, {0.99f, 0.99f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                                     {6, material({1e-4f, 1e-4f, 1e-4f}, {1, 1, 1}, {0, 0, 0})}});
    const int layers = 40;
    const Scene scene = test::boxScene({kSide, kSide, layers}, {kVoxel_mm, kVoxel_mm, kVoxel_mm},
                                       [&](const Vec3i& v) { return Label(v.z >= layers - 15 ? 6 : 4); }, t, kIor);
    const SurfaceVoxelSensor sensor(*scene.geometry, scene.medium->frame(), scene.medium->grid().surfaceVoxels(),
                                    SurfaceVoxelSensor::Footprint::Patch);
    const Diffusion diffusion(scene, sensor);
    int top = 0, bottom = 0;
    for (size_t p = 0; p < sensor.pixelCount(); ++p) {
        const Vec3i v = sensor.pixels()[p].voxel;
        if (v.x < 35 || v.x >= 45 || v.y < 35 || v.y >= 45) continue;
        for (int c = 0; c < 3; ++c) {
            const float R = diffusion.response()[p][c], bound = diffusion.errorBound()[p][c];
            if (v.z == layers - 1) {
                EXPECT_EQ(bound, std::max(R, 1.0f - R)) << p;
            }
            if (v.z == 0) {
                EXPECT_LT(bound, 0.5f * R) << p;
            }
        }
        top += v.z == layers - 1;
        bottom += v.z == 0;
    }
    EXPECT_EQ(top, 100);
    EXPECT_EQ(bottom, 100);
    EXPECT_GE(diffusion.elementsOverClearResin(), size_t(kSide * kSide));
    EXPECT_LT(diffusion.elementsOverClearResin(), sensor.pixelCount() / 2);
    // No clear resin, nothing to cover.
    const Scene white = blockScene({0.5f, 0.9f, 0.99f}, 20.0f, 20);
    const SurfaceVoxelSensor whole(*white.geometry, white.medium->frame(), white.medium->grid().surfaceVoxels(),
                                   SurfaceVoxelSensor::Footprint::Patch);
    EXPECT_EQ(Diffusion(white, whole).elementsOverClearResin(), 0u);
}

TEST(Diffusion, SameBitsWhateverTheThreads) {
    const Scene scene = blockScene({0.5f, 0.9f, 0.99f}, 20.0f, 20);
    const SurfaceVoxelSensor sensor = topCentre(scene, 20);
    auto renderWith = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return renderDiffusion(scene, sensor);
    };
    const RenderResult one = renderWith(1), two = renderWith(2);
    for (size_t p = 0; p < sensor.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(one.film.mean(p, c), two.film.mean(p, c));
}

}  // namespace
}  // namespace pl
