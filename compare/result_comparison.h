// Compares two renders of the same sensor pixel by pixel: exactly (same code,
// same seed) or statistically, by t tests on each difference using both
// results' standard errors and a bias test per channel (batch regression
// renders, `printlight batch`).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/rgb.h"

namespace pl {

// Per-pixel means and standard errors of the mean, in sensor-pixel order.
struct PixelResults {
    std::vector<RGB> mean, standardError;
    size_t size() const { return mean.size(); }
};

struct ComparisonLimits {
    // A pixel value is an outlier if its difference is as unlikely as a
    // normal deviate beyond outlierSigma (6.3e-5 for 4), judged by Welch's t
    // test and a pooled-variance t test (see result_comparison.cpp): the
    // standard errors come from a few samples each.
    double outlierSigma = 4.0;
    double maxOutlierFraction = 1e-3;   // of compared values
    double maxBiasZ = 5.0;              // |mean difference| / its standard error, per channel
};

struct Comparison {
    bool sameSize = true;
    bool bitIdentical = false;
    size_t values = 0;                 // pixel-channel values compared
    size_t outliers = 0;               // see ComparisonLimits (and any difference with zero standard error)
    size_t nonFinite = 0;              // NaN or Inf in either result
    std::array<double, 3> bias{};      // mean of (new - stored), per channel
    std::array<double, 3> biasZ{};     // bias / its standard error
    double outlierFraction() const { return values ? double(outliers) / double(values) : 0.0; }
    // Statistical verdict (an exact comparison passes only if bitIdentical).
    bool passes(const ComparisonLimits& limits) const;
};

// Compares channels `channels` of `fresh` against `stored`, whose pixels
// hold the means of freshSamples and storedSamples samples (>= 2 for a
// statistical comparison).
Comparison compareResults(const PixelResults& fresh, uint32_t freshSamples, const PixelResults& stored,
                          uint32_t storedSamples, const std::vector<int>& channels,
                          const ComparisonLimits& limits = {});

}  // namespace pl
