// Regression comparison (printlight batch): the Student t tail against
// closed forms, and compareResults on synthetic renders whose truth is
// known: equal distributions pass, a bias or a local change fails.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "compare/error_calibration.h"
#include "compare/result_comparison.h"
#include "compare/student_t.h"

namespace pl {
namespace {

TEST(StudentT, MatchesClosedForms) {
    for (double t : {0.1, 1.0, 3.0, 10.0, 300.0}) {
        // nu = 1 is the Cauchy distribution, nu = 2 has an algebraic tail.
        EXPECT_NEAR(studentTTwoSidedP(t, 1), 1 - 2 / M_PI * std::atan(t), 1e-12 + 1e-9 * (1 - 2 / M_PI * std::atan(t)));
        double p2 = 1 - t / std::sqrt(t * t + 2);
        EXPECT_NEAR(studentTTwoSidedP(t, 2), p2, 1e-9 * p2 + 1e-15);
    }
    // Large nu: the normal tail (4 sigma: 6.334e-5).
    EXPECT_NEAR(studentTTwoSidedP(4, 1e7) / normalTwoSidedP(4), 1.0, 1e-4);
    EXPECT_NEAR(normalTwoSidedP(4), 6.334248e-5, 1e-10);
    // A tabulated quantile: t(0.975, 10) = 2.228139.
    EXPECT_NEAR(studentTTwoSidedP(2.228139, 10), 0.05, 1e-6);
}

// A synthetic render: each pixel the mean of n samples of value(pixel, rng).
template <class Draw>
PixelResults syntheticRender(size_t pixels, uint32_t n, uint64_t seed, Draw draw) {
    std::mt19937_64 rng(seed);
    PixelResults r;
    for (size_t p = 0; p < pixels; ++p) {
        RGB mean{0, 0, 0}, se{0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            double s = 0, s2 = 0;
            for (uint32_t i = 0; i < n; ++i) {
                double x = draw(p, c, rng);
                s += x;
                s2 += x * x;
            }
            double m = s / n, var = std::max(0.0, (s2 - n * m * m) / (n - 1));
            mean[c] = float(m);
            se[c] = float(std::sqrt(var / n));
        }
        r.mean.push_back(mean);
        r.standardError.push_back(se);
    }
    return r;
}

const std::vector<int> kRgb{0, 1, 2};

TEST(ResultComparison, SameRenderIsBitIdentical) {
    auto draw = [](size_t, int, std::mt19937_64& g) { return std::exponential_distribution<double>(2.0)(g); };
    PixelResults a = syntheticRender(1000, 4, 1, draw), b = syntheticRender(1000, 4, 1, draw);
    Comparison c = compareResults(a, 4, b, 4, kRgb);
    EXPECT_TRUE(c.bitIdentical);
    EXPECT_TRUE(c.passes({}));
    b.mean[500][1] = std::nextafter(b.mean[500][1], 1.0f);  // one ulp
    EXPECT_FALSE(compareResults(a, 4, b, 4, kRgb).bitIdentical);
}

TEST(ResultComparison, IndependentSeedsOfOneDistributionPass) {
    // Skewed, heavy-ish tailed samples and all-or-nothing (Bernoulli) pixels,
    // whose few samples often all agree: neither may look like a regression.
    auto draw = [](size_t p, int c, std::mt19937_64& g) {
        if (p % 3 == 0) return std::bernoulli_distribution(0.8)(g) ? 1.0 : 0.0;
        return std::lognormal_distribution<double>(0.1 * c, 1.0)(g);
    };
    for (uint32_t n : {2u, 4u, 16u}) {
        PixelResults a = syntheticRender(60000, n, 10 + n, draw), b = syntheticRender(60000, n, 20 + n, draw);
        Comparison c = compareResults(a, n, b, n, kRgb);
        EXPECT_FALSE(c.bitIdentical);
        EXPECT_TRUE(c.passes({})) << "n " << n << ": outliers " << c.outlierFraction() << ", bias z "
                                  << c.biasZ[0] << " " << c.biasZ[1] << " " << c.biasZ[2];
    }
    // Different variances, same means (two estimators): Welch's test.
    auto wide = [](size_t, int, std::mt19937_64& g) { return std::normal_distribution<double>(1.0, 3.0)(g); };
    auto narrow = [](size_t, int, std::mt19937_64& g) { return std::normal_distribution<double>(1.0, 0.1)(g); };
    Comparison c = compareResults(syntheticRender(60000, 4, 1, wide), 4, syntheticRender(60000, 16, 2, narrow), 16, kRgb);
    EXPECT_TRUE(c.passes({})) << c.outlierFraction();
}

TEST(ResultComparison, ABiasOrALocalChangeFails) {
    auto draw = [](double shift) {
        return [shift](size_t, int c, std::mt19937_64& g) { return std::normal_distribution<double>(c == 1 ? 1.0 + shift : 1.0, 1.0)(g); };
    };
    // A global bias of 1 % of the per-sample spread in green only: invisible
    // per pixel at 8 spp, but the mean over 200k pixels has a standard error of
    // 1 / sqrt(8 * 100000) ~ 0.0011, so the bias is ~9 of them.
    Comparison biased = compareResults(syntheticRender(200000, 8, 1, draw(0.01)), 8,
                                       syntheticRender(200000, 8, 2, draw(0.0)), 8, kRgb);
    EXPECT_FALSE(biased.passes({}));
    EXPECT_GT(biased.biasZ[1], 5.0);
    EXPECT_LT(std::abs(biased.biasZ[0]), 5.0);
    // A local change: 1 % of the pixels off by 3 per-sample sigma at 64 spp.
    auto local = [](size_t p, int c, std::mt19937_64& g) {
        return std::normal_distribution<double>(p % 100 == 0 ? 4.0 : 1.0, 1.0)(g);
    };
    Comparison changed = compareResults(syntheticRender(20000, 64, 3, local), 64,
                                        syntheticRender(20000, 64, 4, draw(0.0)), 64, kRgb);
    EXPECT_GT(changed.outlierFraction(), 0.005);
    EXPECT_FALSE(changed.passes({}));
    // NaN is always a failure; so is a different pixel count.
    PixelResults a = syntheticRender(100, 4, 5, draw(0.0)), b = a;
    b.mean[3][2] = std::nanf("");
    EXPECT_EQ(compareResults(b, 4, a, 4, kRgb).nonFinite, 1u);
    EXPECT_FALSE(compareResults(b, 4, a, 4, kRgb).passes({}));
    b.mean.pop_back();
    b.standardError.pop_back();
    EXPECT_FALSE(compareResults(b, 4, a, 4, kRgb).passes({}));
}

}  // namespace
}  // namespace pl

namespace pl {
namespace {

// The calibration of reported errors: exact errors give a mean z^2 of 1
// and the normal's tail, errors half as large a mean z^2 of 4, and a
// difference reported with no error counts beyond four.
TEST(ErrorCalibration, TellsHonestErrorsFromSmallOnes) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> normal;
    const size_t n = 200000;
    PixelResults a, b;
    for (size_t p = 0; p < n; ++p) {
        const float sigma = 0.01f + 0.001f * float(p % 100);
        a.mean.push_back({float(1 + sigma * normal(rng)), 1.0f, 1.0f});
        b.mean.push_back({float(1 + sigma * normal(rng)), 1.0f, 1.0f});
        a.standardError.push_back({sigma, 0.0f, 0.5f * sigma});
        b.standardError.push_back({sigma, 0.0f, 0.5f * sigma});
    }
    ErrorCalibration honest = calibrateErrors(a, b);
    EXPECT_EQ(honest.values, 3 * n);
    EXPECT_NEAR(honest.meanZSq[0], 1.0, 0.02);
    EXPECT_EQ(honest.zeroErrorButDiffer, 0u);  // channel 1: no error, no difference
    EXPECT_EQ(honest.meanZSq[2], 0.0);         // channel 2: no difference
    EXPECT_LT(honest.shareBeyondFour(), 1e-4);
    for (size_t p = 0; p < n; ++p) {
        a.standardError[p][0] *= 0.5f;
        b.standardError[p][0] *= 0.5f;
        b.mean[p][1] = 1.5f;
    }
    ErrorCalibration small = calibrateErrors(a, b);
    EXPECT_NEAR(small.meanZSq[0], 4.0, 0.1);
    EXPECT_EQ(small.zeroErrorButDiffer, n);
    EXPECT_GT(small.shareBeyondFour(), 1.0 / 3.0);  // the whole channel 1, and channel 0's tail
}

}  // namespace
}  // namespace pl
