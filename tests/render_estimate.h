// Means over all pixels of a render, with their standard errors, and the
// agreement check the estimator tests share.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "render/render.h"

namespace pl::test {

struct Estimate {
    RGB mean, standardError;
};

// Mean over all pixels, with the standard error of that mean: the pixels'
// independent errors in quadrature, and the errors they share through
// estimated control means as if all were one (a bound).
inline Estimate meanOf(const RenderResult& r) {
    Estimate e{};
    size_t n = r.film.pixelCount();
    for (int c = 0; c < 3; ++c) {
        double sum = 0, var = 0, shared = 0;
        for (size_t p = 0; p < n; ++p) {
            sum += r.film.mean(p, c);
            var += double(r.film.spreadError(p, c)) * r.film.spreadError(p, c);
            shared += r.film.sharedError(p, c);
        }
        e.mean[c] = float(sum / n);
        shared /= double(n);
        e.standardError[c] = float(std::sqrt(var / (double(n) * n) + shared * shared));
    }
    return e;
}
inline Estimate renderMean(const Scene& scene, const Sensor& sensor, const RenderSettings& settings) {
    return meanOf(render(scene, sensor, settings));
}

// The two means differ by less than 4 combined standard errors, per channel.
inline void expectAgreement(const Estimate& a, const Estimate& b, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        double combined = std::sqrt(double(a.standardError[c]) * a.standardError[c] +
                                    double(b.standardError[c]) * b.standardError[c]);
        EXPECT_GT(combined, 0.0);
        EXPECT_NEAR(a.mean[c], b.mean[c], 4.0 * combined) << what << ", channel " << c;
    }
}

}  // namespace pl::test
