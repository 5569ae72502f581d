// CIEDE2000 against the test data of Sharma, Wu and Dalal (2005), and the
// sRGB to L*a*b* conversion against known points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "compare/colour_difference.h"
#include "compare/surface_colour_error.h"
#include "compare/surface_gaussian.h"

namespace pl {
namespace {

TEST(ColorDifference, Ciede2000MatchesSharmasTestData) {
    struct Pair {
        Lab a, b;
        double deltaE;
    };
    const Pair pairs[] = {
        {{50.0f, 2.6772f, -79.7751f}, {50.0f, 0.0f, -82.7485f}, 2.0425},
        {{50.0f, 3.1571f, -77.2803f}, {50.0f, 0.0f, -82.7485f}, 2.8615},
        {{50.0f, 2.8361f, -74.0200f}, {50.0f, 0.0f, -82.7485f}, 3.4412},
        {{50.0f, 0.0f, 0.0f}, {50.0f, -1.0f, 2.0f}, 2.3669},
        {{50.0f, 2.4900f, -0.0010f}, {50.0f, -2.4900f, 0.0009f}, 7.1792},
        {{50.0f, 2.5f, 0.0f}, {73.0f, 25.0f, -18.0f}, 27.1492},
        {{60.2574f, -34.0099f, 36.2677f}, {60.4626f, -34.1751f, 39.4387f}, 1.2644},
    };
    for (const Pair& p : pairs) {
        EXPECT_NEAR(ciede2000(p.a, p.b), p.deltaE, 1e-4) << p.a.L << " " << p.a.a << " " << p.a.b;
        EXPECT_NEAR(ciede2000(p.b, p.a), p.deltaE, 1e-4);  // symmetric
    }
    EXPECT_EQ(ciede2000({40, 10, -5}, {40, 10, -5}), 0.0);
}

TEST(ColorDifference, LinearSrgbToLab) {
    Lab white = labFromLinearSrgb({1, 1, 1});
    EXPECT_NEAR(white.L, 100.0f, 1e-3f);
    EXPECT_NEAR(white.a, 0.0f, 1e-2f);
    EXPECT_NEAR(white.b, 0.0f, 1e-2f);
    Lab black = labFromLinearSrgb({0, 0, 0});
    EXPECT_NEAR(black.L, 0.0f, 1e-4f);
    // Middle grey: Y = 0.18 gives L* = 49.5.
    EXPECT_NEAR(labFromLinearSrgb({0.18f, 0.18f, 0.18f}).L, 49.496f, 1e-2f);
    // Pure sRGB red: L* 53.24, a* 80.09, b* 67.20.
    Lab red = labFromLinearSrgb({1, 0, 0});
    EXPECT_NEAR(red.L, 53.24f, 0.05f);
    EXPECT_NEAR(red.a, 80.09f, 0.1f);
    EXPECT_NEAR(red.b, 67.20f, 0.1f);
}

TEST(ColorDifference, LabToLinearSrgbInvertsIt) {
    // Round trips over the sRGB cube, dark colours included; and a colour
    // outside sRGB comes back outside [0, 1], not clamped.
    for (float r : {0.0f, 0.003f, 0.2f, 0.7f, 1.0f})
        for (float g : {0.0f, 0.05f, 0.5f, 1.0f})
            for (float b : {0.0f, 0.01f, 0.3f, 1.0f}) {
                const RGB back = linearSrgbFromLab(labFromLinearSrgb({r, g, b}));
                EXPECT_NEAR(back[0], r, 2e-5f);
                EXPECT_NEAR(back[1], g, 2e-5f);
                EXPECT_NEAR(back[2], b, 2e-5f);
            }
    const RGB beyond = linearSrgbFromLab({50, 120, 0});
    EXPECT_GT(std::max({beyond[0], beyond[1], beyond[2]}), 1.0f);
}

}  // namespace
}  // namespace pl

namespace pl {
namespace {

// The surface filter on a flat grid of points 0.045 mm apart (no point
// exactly at the 3 sigma cut-off, where round-off would pick a side): a constant
// stays constant, a linear ramp stays itself away from the border (the
// weights are symmetric), and a spike spreads with the Gaussian's weights.
TEST(SurfaceGaussian, KeepsConstantsAndRampsAndSpreadsASpike) {
    std::vector<Point3f> points;
    std::vector<RGB> constant, ramp, spike;
    const int n = 60;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            points.push_back({0.045f * i, 0.045f * j, 1.0f});
            constant.push_back({0.3f, 0.3f, 0.3f});
            ramp.push_back({0.045f * i, 0.045f * j, 0});
            spike.push_back({i == 30 && j == 30 ? 1.0f : 0.0f, 0, 0});
        }
    const SurfaceGaussian filter(points, 0.2f);
    const auto c = filter.apply(constant), r = filter.apply(ramp), s = filter.apply(spike);
    for (size_t k = 0; k < points.size(); ++k) EXPECT_NEAR(c[k][0], 0.3f, 1e-6f);
    const size_t centre = 30 * n + 30;
    EXPECT_NEAR(r[centre][0], ramp[centre][0], 1e-5f);
    EXPECT_NEAR(r[centre][1], ramp[centre][1], 1e-5f);
    // The spike's share at its centre: 1 / (sum of the weights), about
    // 1 / (2 pi (0.2 / 0.045)^2) on this lattice.
    const double share = 1.0 / (2 * 3.14159265 * std::pow(0.2 / 0.045, 2));
    EXPECT_NEAR(s[centre][0], share, 0.05 * share);
    // And a colour error filtered over it: equal inputs, zero.
    const SurfaceColourError e = surfaceColourError(points, ramp, ramp);
    EXPECT_EQ(e.meanFiltered, 0.0);
    EXPECT_EQ(e.mean, 0.0);
}

// The judge's noise estimate: what one more draw of a render's standard
// errors makes is what its noise made against the truth (per voxel and
// over the footprint), and none without noise.
TEST(SurfaceColourError, NoiseEstimateMatchesTheErrorNoiseMakes) {
    std::vector<Point3f> points;
    std::vector<RGB> truth;
    const int n = 80;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            points.push_back({0.045f * i, 0.045f * j, 1.0f});
            truth.push_back((i / 10) % 2 ? RGB{0.6f, 0.3f, 0.2f} : RGB{0.1f, 0.4f, 0.5f});  // 0.45 mm stripes
        }
    std::mt19937 engine(7);
    for (float sigma : {0.02f, 0.05f}) {
        std::normal_distribution<float> normal(0.0f, sigma);
        std::vector<RGB> noisy(truth), errors(truth.size(), RGB{sigma, sigma, sigma});
        for (RGB& c : noisy)
            for (int k = 0; k < 3; ++k) c[k] += normal(engine);
        const SurfaceColourError actual = surfaceColourError(points, noisy, truth);
        const SurfaceColourError estimate = noiseColourError(points, noisy, errors);
        EXPECT_NEAR(estimate.mean, actual.mean, 0.1 * actual.mean) << sigma;
        EXPECT_NEAR(estimate.meanFiltered, actual.meanFiltered, 0.15 * actual.meanFiltered) << sigma;
        EXPECT_LT(actual.meanFiltered, 0.5 * actual.mean) << sigma;  // the footprint averages noise out
    }
    const SurfaceColourError none = noiseColourError(points, truth, std::vector<RGB>(truth.size(), RGB{0, 0, 0}));
    EXPECT_EQ(none.mean, 0.0);
    EXPECT_EQ(none.meanFiltered, 0.0);
}

// A render judged from two independent halves: the halves' disagreement
// measures the noise of their mean, and the polarised cross term of their
// errors takes the noise out of the root mean square error over the
// footprint, however large the noise. Checked over independent repeats
// against the noiseless truth, within three standard errors of the repeats.
TEST(SurfaceColourError, SplitHalvesMeasureNoiseAndTakeItOut) {
    std::vector<Point3f> points;
    std::vector<RGB> reference, truth;
    const int n = 60;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            points.push_back({0.045f * i, 0.045f * j, 1.0f});
            reference.push_back({0.3f, 0.2f, 0.1f});
            // A bias that varies over the surface (about 1 to 4 CIEDE2000).
            const float b = 0.01f + 0.01f * std::sin(0.3f * float(i)) * std::sin(0.2f * float(j));
            truth.push_back({0.3f + b, 0.2f, 0.1f - 0.5f * b});
        }
    const SurfaceGaussian eye(points, kEyeFootprint_mm);
    std::vector<RGB> truthSeen = eye.apply(truth), referenceSeen = eye.apply(reference);
    double truthSq = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        const double e = ciede2000(labFromLinearSrgb(truthSeen[i]), labFromLinearSrgb(referenceSeen[i]));
        truthSq += e * e;
    }
    const double truthRms = std::sqrt(truthSq / double(points.size()));
    for (float sigma : {0.03f, 0.1f}) {
        std::mt19937 engine(11);
        std::normal_distribution<float> normal(0.0f, sigma);
        const int repeats = 8;
        std::vector<double> rms, noiseGap;
        double noisyMean = 0;
        for (int r = 0; r < repeats; ++r) {
            std::vector<RGB> a(truth), b(truth), mean(truth.size());
            for (size_t i = 0; i < truth.size(); ++i)
                for (int k = 0; k < 3; ++k) {
                    a[i][k] += normal(engine);
                    b[i][k] += normal(engine);
                    mean[i][k] = 0.5f * (a[i][k] + b[i][k]);
                }
            const SplitRenderError e = splitRenderError(eye, a, b, reference);
            rms.push_back(e.rmsFilteredNoiseRemoved);
            // The mean's actual noise over the footprint, against the estimate.
            noiseGap.push_back(e.noise.meanFiltered - surfaceColourError(eye, mean, truth).meanFiltered);
            noisyMean += e.error.meanFiltered / repeats;
        }
        auto meanAndError = [&](const std::vector<double>& x) {
            double m = 0, s = 0;
            for (double v : x) m += v / double(x.size());
            for (double v : x) s += (v - m) * (v - m);
            return std::make_pair(m, std::sqrt(s / double(x.size() - 1) / double(x.size())));
        };
        const auto [rmsMean, rmsError] = meanAndError(rms);
        const auto [gapMean, gapError] = meanAndError(noiseGap);
        EXPECT_NEAR(rmsMean, truthRms, 3 * rmsError + 0.02 * truthRms) << sigma;
        EXPECT_NEAR(gapMean, 0.0, 3 * gapError + 0.02) << sigma;
        if (sigma > 0.05f) {
            EXPECT_GT(noisyMean, 1.5 * truthRms) << sigma;  // the noise would have shown as error
        }
    }
}

}  // namespace
}  // namespace pl
