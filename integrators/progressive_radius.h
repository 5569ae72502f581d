// The kernel radius of a progressive density estimator (Knaus and Zwicker
// 2011): each iteration shrinks the kernel's measure (r^k for a kernel over
// k dimensions: 3 for a ball, 2 for a disc, 1 for a line) by (i + alpha) / (i + 1), so
// the bias and the variance both vanish as iterations go on.
#pragma once

#include <cmath>
#include <cstdint>

namespace pl {

// The radius of iteration i (from 1), starting from firstRadius_mm.
inline float progressiveRadius_mm(float firstRadius_mm, float alpha, int kernelDimensions, uint32_t iteration) {
    double measure = 1.0;
    for (uint32_t j = 1; j < iteration; ++j) measure *= (double(j) + alpha) / double(j + 1);
    const double scale = kernelDimensions == 1   ? measure
                         : kernelDimensions == 2 ? std::sqrt(measure)
                                                 : std::cbrt(measure);
    return float(double(firstRadius_mm) * scale);
}

}  // namespace pl
