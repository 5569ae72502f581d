// Henyey-Greenstein sampling: chi-square against the analytic distribution,
// pdf normalisation, and value/pdf consistency.
#include <gtest/gtest.h>

#include "core/rng.h"
#include "core/sampling.h"
#include "test_util.h"

namespace pl {
namespace {

// P(cosTheta <= mu) for HG with parameter g.
double hgCdf(double mu, double g) {
    if (std::abs(g) < 1e-4) return 0.5 * (1 + mu);
    return (1 - g * g) / (2 * g) * (1 / std::sqrt(1 + g * g - 2 * g * mu) - 1 / (1 + g));
}

class HgSampling : public ::testing::TestWithParam<float> {};

TEST_P(HgSampling, ChiSquareInCosThetaAndPhi) {
    const float g = GetParam();
    const int muBins = 40, phiBins = 8, n = 400000;
    Rng rng(7, uint64_t(1000 * (g + 2)));
    const Vec3f dIn = normalize(Vec3f(0.3f, -0.5f, 0.8f));
    Frame frame(dIn);
    std::vector<double> observed(muBins * phiBins, 0.0), expected(muBins * phiBins, 0.0);
    for (int i = 0; i < n; ++i) {
        PhaseSample s = sampleHG(dIn, g, rng.uniform(), rng.uniform());
        ASSERT_NEAR(length(s.dOut), 1.0f, 1e-5f);
        double mu = std::clamp(double(dot(s.dOut, dIn)), -1.0, 1.0);
        double phi = std::atan2(double(dot(s.dOut, frame.t)), double(dot(s.dOut, frame.s))) + kPi;
        int bm = std::min(muBins - 1, int((mu + 1) / 2 * muBins));
        int bp = std::min(phiBins - 1, int(phi / (2 * kPi) * phiBins));
        observed[size_t(bm * phiBins + bp)] += 1;
    }
    for (int bm = 0; bm < muBins; ++bm) {
        double p = hgCdf(-1 + 2.0 * (bm + 1) / muBins, g) - hgCdf(-1 + 2.0 * bm / muBins, g);
        for (int bp = 0; bp < phiBins; ++bp) expected[size_t(bm * phiBins + bp)] = n * p / phiBins;
    }
    EXPECT_LT(test::chiSquareZ(observed, expected), test::kChiSquareZLimit) << "g = " << g;
}

TEST_P(HgSampling, PdfIntegratesToOneAndMatchesValue) {
    const float g = GetParam();
    // Integrate 2 pi p(mu) dmu with the midpoint rule, dense near mu = 1.
    double integral = 0;
    const int steps = 2000000;
    for (int i = 0; i < steps; ++i) {
        double mu = -1 + 2.0 * (i + 0.5) / steps;
        integral += 2 * kPi * hgPhase(float(mu), g) * (2.0 / steps);
    }
    EXPECT_NEAR(integral, 1.0, 2e-3) << "g = " << g;
    Rng rng(3, 4);
    for (int i = 0; i < 100; ++i) {
        Vec3f dIn(0, 0, 1);
        PhaseSample s = sampleHG(dIn, g, rng.uniform(), rng.uniform());
        EXPECT_FLOAT_EQ(s.pdf, hgPhase(dot(s.dOut, dIn), g));
        EXPECT_FLOAT_EQ(s.value, s.pdf);
    }
}

INSTANTIATE_TEST_SUITE_P(Anisotropies, HgSampling,
                         ::testing::Values(-0.99f, -0.4f, 0.0f, 0.4f, 0.9f, 0.99f));

TEST(VmfSampling, ChiSquareAndPdfConsistency) {
    const Vec3f mu = normalize(Vec3f(-0.2f, 0.7f, 0.4f));
    Frame frame(mu);
    for (float kappa : {0.5f, 4.0f, 50.0f}) {
        const int muBins = 40, phiBins = 8, n = 300000;
        Rng rng(5, uint64_t(kappa * 10));
        std::vector<double> observed(muBins * phiBins, 0.0), expected(muBins * phiBins, 0.0);
        for (int i = 0; i < n; ++i) {
            DirectionSample s = sampleVMF(mu, kappa, rng.uniform(), rng.uniform());
            ASSERT_NEAR(s.pdf, vmfPdf(mu, kappa, s.d), 1e-3f * s.pdf);
            double c = std::clamp(double(dot(s.d, mu)), -1.0, 1.0);
            double phi = std::atan2(double(dot(s.d, frame.t)), double(dot(s.d, frame.s))) + kPi;
            int bm = std::min(muBins - 1, int((c + 1) / 2 * muBins));
            int bp = std::min(phiBins - 1, int(phi / (2 * kPi) * phiBins));
            observed[size_t(bm * phiBins + bp)] += 1;
        }
        // P(mu.w <= c) = (exp(kappa (c - 1)) - exp(-2 kappa)) / (1 - exp(-2 kappa)).
        auto cdf = [&](double c) { return (std::exp(kappa * (c - 1)) - std::exp(-2.0 * kappa)) / -std::expm1(-2.0 * kappa); };
        for (int bm = 0; bm < muBins; ++bm) {
            double p = cdf(-1 + 2.0 * (bm + 1) / muBins) - cdf(-1 + 2.0 * bm / muBins);
            for (int bp = 0; bp < phiBins; ++bp) expected[size_t(bm * phiBins + bp)] = n * p / phiBins;
        }
        EXPECT_LT(test::chiSquareZ(observed, expected), test::kChiSquareZLimit) << "kappa = " << kappa;
    }
}

TEST(ExponentialSampling, MeanFreePath) {
    Rng rng(1, 2);
    const float sigma = 3.0f;
    double sum = 0, sumSq = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        DistanceSample s = sampleExponential(sigma, rng.uniform());
        EXPECT_NEAR(s.pdf, sigma * std::exp(-sigma * s.t), 1e-4f * sigma);
        sum += s.t;
        sumSq += double(s.t) * s.t;
    }
    double mean = sum / n, se = std::sqrt((sumSq / n - mean * mean) / n);
    EXPECT_NEAR(mean, 1.0 / sigma, 4.5 * se);
}

TEST(Rng, StreamsDependOnlyOnTheirKey) {
    Rng a = Rng::forPath(9, 123, 4, 1), b = Rng::forPath(9, 123, 4, 1), c = Rng::forPath(9, 123, 5, 1);
    bool differs = false;
    for (int i = 0; i < 16; ++i) {
        uint32_t x = a.next32();
        EXPECT_EQ(x, b.next32());
        differs = differs || x != c.next32();
    }
    EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace pl
