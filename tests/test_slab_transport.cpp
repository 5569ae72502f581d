// The deterministic slab solver (media/slab_transport.h) against what it
// must reproduce: exact quadrature, Chandrasekhar's H-function for the
// isotropic half-space without a boundary, Beer-Lambert with Fresnel
// inter-reflections in a non-scattering slab, the values of Prahl's
// adding-doubling package, and the Monte Carlo mean of printpt's
// half-space walk.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "integrators/printpt/half_space_walk.h"
#include "media/slab_transport.h"

namespace pl {
namespace {

TEST(SlabTransport, QuadraturesAreExactForPolynomials) {
    for (int n : {2, 5, 12, 24}) {
        std::vector<double> x(static_cast<size_t>(n)), w(static_cast<size_t>(n));
        gaussLegendre(n, x.data(), w.data());
        for (int k = 0; k <= 2 * n - 1; ++k) {
            double sum = 0;
            for (int i = 0; i < n; ++i) sum += w[size_t(i)] * std::pow(x[size_t(i)], k);
            EXPECT_NEAR(sum, k % 2 ? 0.0 : 2.0 / (k + 1), 1e-13) << "Gauss n " << n << " degree " << k;
        }
        gaussRadauRight(n, x.data(), w.data());
        EXPECT_EQ(x[size_t(n - 1)], 1.0);
        for (int k = 0; k <= 2 * n - 2; ++k) {
            double sum = 0;
            for (int i = 0; i < n; ++i) sum += w[size_t(i)] * std::pow(x[size_t(i)], k);
            EXPECT_NEAR(sum, k % 2 ? 0.0 : 2.0 / (k + 1), 1e-13) << "Radau n " << n << " degree " << k;
        }
    }
}

// Chandrasekhar's H-function of isotropic scattering, by iterating
// 1/H(mu) = sqrt(1 - a) + (a/2) int_0^1 mu' H(mu') / (mu + mu') dmu'
// on a fine Gauss rule (independent of the solver's discrete ordinates).
double hFunction(double albedo, double mu) {
    constexpr int n = 200;
    std::vector<double> x(n), w(n), H(n, 1.0);
    gaussLegendre(n, x.data(), w.data());
    for (int i = 0; i < n; ++i) {
        x[size_t(i)] = 0.5 * (x[size_t(i)] + 1.0);
        w[size_t(i)] *= 0.5;
    }
    auto inverse = [&](double m) {
        double s = 0;
        for (int j = 0; j < n; ++j) s += w[size_t(j)] * x[size_t(j)] * H[size_t(j)] / (m + x[size_t(j)]);
        return std::sqrt(1.0 - albedo) + 0.5 * albedo * s;
    };
    for (int iteration = 0; iteration < 3000; ++iteration) {
        std::vector<double> next(n);
        for (int i = 0; i < n; ++i) next[size_t(i)] = 1.0 / inverse(x[size_t(i)]);
        H = next;
    }
    return 1.0 / inverse(mu);
}

// Isotropic, no boundary: the half-space's reflectance for a normal beam
// is 1 - H(1) sqrt(1 - a).
TEST(SlabTransport, MatchesTheHFunctionWithoutABoundary) {
    for (double albedo : {0.5, 0.9, 0.99, 0.999}) {
        SlabEscape e = slabEscape({albedo, 0.0, 1.0});
        const double reference = 1.0 - hFunction(albedo, 1.0) * std::sqrt(1.0 - albedo);
        EXPECT_NEAR(e.top, reference, 1e-9) << "albedo " << albedo;
        EXPECT_LT(e.error, 1e-8);
        EXPECT_EQ(e.bottom, 0.0);
    }
}

// No scattering: the beam crosses, and bounces between the faces with
// reflectance R = F(1) each time.
TEST(SlabTransport, NonScatteringSlabIsBeerLambertWithInterreflections) {
    for (double tau : {0.1, 1.0, 4.0}) {
        SlabEscape e = slabEscape({0.0, 0.4, 1.5, tau});
        const double R = 0.04, T = std::exp(-tau);
        EXPECT_NEAR(e.bottom, (1 - R) * T / (1 - R * R * T * T), 1e-10) << tau;
        EXPECT_NEAR(e.top, (1 - R) * R * T * T / (1 - R * R * T * T), 1e-10) << tau;
    }
}

// Prahl's adding-doubling package (iadpython, tests/test_combo.py, infinite
// slabs: "UR1", total reflectance for normal collimated light, the
// specular part included). With a boundary its 16-point quadrature is good
// to about 1e-4 (the solver and 2^26 Monte Carlo walks agree with each
// other to 3e-5 and differ from it by 1.3e-4: docs/formats.md).
TEST(SlabTransport, AgreesWithPrahlsAddingDoubling) {
    EXPECT_NEAR(slabEscape({0.8, 0.0, 1.0}).top, 0.28525, 1e-5);  // n = 1: the specular part is 0
    const double specular = std::pow(0.4 / 2.4, 2);                // n = 1.4
    const double ur1 = specular + (1 - specular) * slabEscape({0.8, 0.0, 1.4}).top;
    EXPECT_NEAR(ur1, 0.18095, 2e-4);
}

// The solver is the exact mean of printpt's half-space walk: 2^18 walks
// (their own standard error) agree with it, with and without anisotropy.
TEST(SlabTransport, IsTheMeanOfTheHalfSpaceWalk) {
    for (float g : {0.0f, 0.4f})
        for (float albedo : {0.5f, 0.9f, 0.99f}) {
            const HalfSpace hs{{0, 0, 0}, {0, 0, 1}, 1.0f, albedo, g, 1.0f / 1.5f};
            const HalfSpaceMean mc = estimateHalfSpaceMean(hs, {0.25f, 1.0f}, 1.0f, int64_t(1) << 18, 77);
            const SlabEscape exact = slabEscape({albedo, g, 1.5});
            EXPECT_NEAR(mc.mean, exact.top, 4.0 * mc.standardError) << "albedo " << albedo << " g " << g;
        }
}

// A thick slab is a half-space; light is conserved without absorption in
// the limit (top + bottom -> 1 as the albedo -> 1, thin slab).
TEST(SlabTransport, ThickSlabIsAHalfSpaceAndThinSlabsConserve) {
    const SlabEscape halfSpace = slabEscape({0.9, 0.4, 1.5});
    const SlabEscape thick = slabEscape({0.9, 0.4, 1.5, 200.0});
    EXPECT_NEAR(thick.top, halfSpace.top, 1e-12);
    EXPECT_LT(thick.bottom, 1e-20);
    const SlabEscape thin = slabEscape({0.999999, 0.4, 1.5, 0.5});
    EXPECT_NEAR(thin.top + thin.bottom, 1.0, 1e-5);
}

}  // namespace
}  // namespace pl
