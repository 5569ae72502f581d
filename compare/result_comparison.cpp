#include "compare/result_comparison.h"

#include <cmath>
#include <cstring>

#include "compare/student_t.h"

namespace pl {

bool Comparison::passes(const ComparisonLimits& limits) const {
    if (!sameSize || nonFinite) return false;
    if (outlierFraction() > limits.maxOutlierFraction) return false;
    for (double z : biasZ)
        if (!(std::abs(z) <= limits.maxBiasZ)) return false;
    return true;
}

namespace {
// Is a difference d of two means (nA, nB samples; squared standard errors
// varA, varB) less likely than pLimit? Two t tests must both say so:
// Welch's (the variances may differ, e.g. between estimators) and one on the
// variance of all nA + nB samples pooled, which under the null hypothesis
// includes the spread between the two means; the second keeps pixels whose
// few samples all came out equal (sample variance 0: an all-or-nothing
// path contribution) from counting as certain differences.
bool isOutlier(double d, double varA, uint32_t nA, double varB, uint32_t nB, double sigma, double pLimit) {
    if (d == 0) return false;
    if (nA < 2 || nB < 2) return true;  // no variance estimate: any difference counts
    double na = nA, nb = nB;
    double var = varA + varB;
    if (var > 0) {
        double t = std::abs(d) / std::sqrt(var);
        if (t <= sigma) return false;  // t tails are heavier than normal ones: never beyond
        // Welch-Satterthwaite degrees of freedom of the combined variance.
        double nu = var * var / (varA * varA / (na - 1) + varB * varB / (nb - 1));
        if (studentTTwoSidedP(t, nu) >= pLimit) return false;
    }
    // Sample variance of all samples together, from the per-run sample
    // variances (n * se^2) and the difference of the means.
    double pooled = ((na - 1) * na * varA + (nb - 1) * nb * varB + d * d * na * nb / (na + nb)) / (na + nb - 1);
    double t = std::abs(d) / std::sqrt(pooled * (1 / na + 1 / nb));
    return t > sigma && studentTTwoSidedP(t, na + nb - 2) < pLimit;
}
}  // namespace

Comparison compareResults(const PixelResults& fresh, uint32_t freshSamples, const PixelResults& stored,
                          uint32_t storedSamples, const std::vector<int>& channels,
                          const ComparisonLimits& limits) {
    Comparison c;
    if (fresh.size() != stored.size() || fresh.standardError.size() != fresh.size() ||
        stored.standardError.size() != stored.size()) {
        c.sameSize = false;
        return c;
    }
    c.bitIdentical = true;
    std::array<double, 3> sumDiff{}, sumVar{};
    const double pLimit = normalTwoSidedP(limits.outlierSigma);
    for (size_t p = 0; p < fresh.size(); ++p)
        for (int ch : channels) {
            float a = fresh.mean[p][ch], b = stored.mean[p][ch];
            float sa = fresh.standardError[p][ch], sb = stored.standardError[p][ch];
            // Bitwise, so that -0 vs 0 and NaN payloads count as differences.
            if (std::memcmp(&a, &b, sizeof a) || std::memcmp(&sa, &sb, sizeof sa)) c.bitIdentical = false;
            ++c.values;
            if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(sa) || !std::isfinite(sb)) {
                ++c.nonFinite;
                continue;
            }
            double d = double(a) - double(b);
            double varA = double(sa) * sa, varB = double(sb) * sb;
            sumDiff[ch] += d;
            sumVar[ch] += varA + varB;
            if (isOutlier(d, varA, freshSamples, varB, storedSamples, limits.outlierSigma, pLimit)) ++c.outliers;
        }
    size_t pixels = fresh.size();
    for (int ch : channels) {
        if (!pixels) break;
        c.bias[ch] = sumDiff[ch] / double(pixels);
        // Pixels are independent: the mean difference has variance sum(var) / n^2.
        double se = std::sqrt(sumVar[ch]) / double(pixels);
        c.biasZ[ch] = se > 0 ? c.bias[ch] / se : (sumDiff[ch] == 0 ? 0.0 : HUGE_VAL);
    }
    return c;
}

}  // namespace pl
