// The Student t distribution's two-sided tail, for tests on means whose
// standard errors were themselves estimated from a few samples (Welch).
#pragma once

#include <cmath>

namespace pl {

namespace detail {
// Continued fraction of the regularised incomplete beta function (modified
// Lentz); converges quickly for x < (a + 1) / (a + b + 2).
inline double betaContinuedFraction(double a, double b, double x) {
    const double tiny = 1e-300;
    double c = 1, d = 1 - (a + b) * x / (a + 1);
    d = 1 / (std::abs(d) < tiny ? tiny : d);
    double h = d;
    for (int m = 1; m <= 500; ++m) {
        for (int step = 0; step < 2; ++step) {
            double aa = step == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                  : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
            d = 1 + aa * d;
            d = 1 / (std::abs(d) < tiny ? tiny : d);
            c = 1 + aa / c;
            if (std::abs(c) < tiny) c = tiny;
            h *= d * c;
            if (step == 1 && std::abs(d * c - 1) < 1e-14) return h;
        }
    }
    return h;
}
}  // namespace detail

// Regularised incomplete beta function I_x(a, b).
inline double incompleteBeta(double a, double b, double x) {
    if (x <= 0) return 0;
    if (x >= 1) return 1;
    double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                            b * std::log1p(-x));
    if (x < (a + 1) / (a + b + 2)) return front * detail::betaContinuedFraction(a, b, x) / a;
    return 1 - front * detail::betaContinuedFraction(b, a, 1 - x) / b;
}

// P(|T| >= t) for T ~ Student t with nu degrees of freedom (nu > 0).
inline double studentTTwoSidedP(double t, double nu) {
    return incompleteBeta(nu / 2, 0.5, nu / (nu + t * t));
}

// The t whose two-sided tail P(|T| >= t) is p, for nu degrees of freedom
// (bisection on the tail).
inline double studentTTwoSidedQuantile(double p, double nu) {
    double lo = 0, hi = 1e3;
    for (int i = 0; i < 100; ++i) {
        const double t = 0.5 * (lo + hi);
        (studentTTwoSidedP(t, nu) > p ? lo : hi) = t;
    }
    return 0.5 * (lo + hi);
}

// P(|Z| >= z) for a standard normal Z.
inline double normalTwoSidedP(double z) { return std::erfc(std::abs(z) / std::sqrt(2.0)); }

}  // namespace pl
