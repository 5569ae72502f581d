// Photon beam diffusion (media/beam_diffusion.h) against what it must
// reproduce: published fits of the Fresnel moments, its own closed-form
// totals (the radial profiles integrated over the plane), scale
// invariance, and, for its bias, the exact half-space of the deterministic
// solver (media/slab_transport.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "media/beam_diffusion.h"

namespace pl {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The integral of 2 pi r f(r) over the plane: trapezoids in log r from
// 1e-7 mm to 60 diffusion lengths (profiles are at most 1/r at 0).
template <class F>
double overThePlane(F f, double diffusionLength_mm) {
    constexpr int n = 6000;
    const double lo = std::log(1e-7), hi = std::log(60.0 * diffusionLength_mm);
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
        const double r = std::exp(lo + (hi - lo) * i / n);
        sum += (i == 0 || i == n ? 0.5 : 1.0) * 2.0 * kPi * r * r * f(r);
    }
    return sum * (hi - lo) / n;
}

TEST(BeamDiffusion, FresnelMomentsMatchPublishedFits) {
    EXPECT_NEAR(fresnelMomentInside(1, 1.0), 0.0, 1e-12);  // no boundary, no reflection
    EXPECT_NEAR(fresnelMomentInside(2, 1.0), 0.0, 1e-12);
    // Internal diffuse reflectance 2 C1 against Egan and Hilgeman's fit
    // (-1.440/n^2 + 0.710/n + 0.668 + 0.0636 n), and C2 against pbrt-v3's
    // polynomial fit; both fits are good to about 1e-3.
    for (double n : {1.3, 1.5}) {
        EXPECT_NEAR(2.0 * fresnelMomentInside(1, n), -1.440 / (n * n) + 0.710 / n + 0.668 + 0.0636 * n, 2e-3) << n;
    }
    const double n = 1.5;
    const double c2Fit = -547.033 + 45.3087 / (n * n * n) - 218.725 / (n * n) + 458.843 / n + 404.557 * n -
                         189.519 * n * n + 54.9327 * n * n * n - 9.00603 * n * n * n * n + 0.63942 * std::pow(n, 5);
    EXPECT_NEAR(fresnelMomentInside(2, n), c2Fit, 1.5e-3);
}

TEST(BeamDiffusion, ProfilesIntegrateToTheirClosedForms) {
    for (double g : {0.0, 0.4})
        for (double albedo : {0.5, 0.9, 0.999}) {
            const BeamDiffusion d({albedo, g, 1.5}, 2.0);
            const double ms = overThePlane([&](double r) { return d.multipleScattering_perMm2(r, false); },
                                           d.diffusionLength_mm());
            EXPECT_NEAR(ms / d.multipleScatteringTotalWithoutCorrection(), 1.0, 1e-3) << g << " " << albedo;
            const double ss = overThePlane([&](double r) { return d.singleScattering_perMm2(r); }, d.diffusionLength_mm());
            EXPECT_NEAR(ss / d.singleScatteringTotal(), 1.0, 5e-3) << g << " " << albedo;
        }
}

TEST(BeamDiffusion, TotalsDoNotDependOnTheScale) {
    const BeamDiffusion a({0.9, 0.4, 1.5}, 1.0), b({0.9, 0.4, 1.5}, 25.0);
    EXPECT_NEAR(a.singleScatteringTotal(), b.singleScatteringTotal(), 1e-12);
    EXPECT_NEAR(a.multipleScatteringTotalWithoutCorrection(), b.multipleScatteringTotalWithoutCorrection(), 1e-12);
    EXPECT_NEAR(a.diffusionLength_mm(), 25.0 * b.diffusionLength_mm(), 1e-9);
    EXPECT_NEAR(a.multipleScattering_perMm2(0.3), b.multipleScattering_perMm2(0.3 / 25.0) / (25.0 * 25.0), 1e-12);
}

// The table (what the predictor looks up) against the profile it tabulates.
TEST(BeamDiffusion, TheTableReproducesTheProfileAndItsTotal) {
    const BeamDiffusionTable table(0.4, 1.5);
    for (double albedo : {0.25, 0.9, 0.97, 0.995}) {
        const BeamDiffusion d({albedo, 0.4, 1.5}, 6.0);  // white's red extinction, per mm
        const double direct = overThePlane(
            [&](double r) { return d.singleScattering_perMm2(r) + d.multipleScattering_perMm2(r); }, d.diffusionLength_mm());
        EXPECT_NEAR(table.total(albedo) / direct, 1.0, 0.015) << albedo;
        // What a predictor summing the profile over the surface would get
        // wrong: the lookups' absolute error over the plane.
        const double lookupError = overThePlane(
            [&](double r) {
                return std::abs(table.profile_perMm2(albedo, 6.0, r) - d.singleScattering_perMm2(r) -
                                d.multipleScattering_perMm2(r));
            },
            d.diffusionLength_mm());
        EXPECT_LT(lookupError, 0.02 * direct) << albedo;
    }
    EXPECT_EQ(table.profile_perMm2(0.9, 6.0, 1e3), 0.0);  // beyond the table
}

// The approximation's bias: the light a normal beam brings out of the
// half-space, diffusion (single + multiple scattering, with the
// near-surface correction) against the exact solution. Diffusion is an
// approximation; the bound is the one known for it at these albedos
// (-8.5 % to +9.6 % measured, docs/diffusion.md; within 12 % asserted),
// and the table is printed.
TEST(BeamDiffusion, BiasAgainstTheExactHalfSpaceIsWithinItsKnownBound) {
    std::printf("g, albedo, exact, diffusion, relative bias\n");
    for (double g : {0.0, 0.4})
        for (double albedo : {0.5, 0.9, 0.99, 0.999}) {
            const SlabMedium medium{albedo, g, 1.5};
            const BeamDiffusion d(medium, 1.0);
            const double diffusion = overThePlane(
                [&](double r) { return d.singleScattering_perMm2(r) + d.multipleScattering_perMm2(r); },
                d.diffusionLength_mm());
            const double exact = slabEscape(medium).top;
            std::printf("%.1f, %.3f, %.5f, %.5f, %+.3f\n", g, albedo, exact, diffusion, diffusion / exact - 1.0);
            EXPECT_NEAR(diffusion / exact, 1.0, 0.12) << g << " " << albedo;
        }
}

}  // namespace
}  // namespace pl
