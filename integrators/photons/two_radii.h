// A kernel estimate gathered at the iteration's radius r and, from the same
// photons, at r / 2, so that each sample says how much the kernel's reach
// moves it. A kernel estimate's bias grows like r where the kernel reaches
// past the object's boundary or a halftone's edge (like r^2 where the
// density is smooth): if it grows like r, the estimate at r is off by twice
// the difference of the two. The sample reports that as its bias
// (ChannelSample::bias); the film adds to the pixel's error the bias their
// mean shows beyond its own noise, so the reported error covers the
// kernel's bias as well as the iterations' spread (Hachisuka et al. 2010
// estimate the bias from the kernel's derivatives; two radii need none).
// Where the reach is many mean free paths past a boundary the bias grows
// slower than r and this sees part of it: pp3d and pb2d gather only where
// their kernel stays inside (docs/particle-methods.md, "Their errors").
#pragma once

#include <cmath>

#include "core/film.h"
#include "core/vecmath.h"

namespace pl {

struct TwoRadii {
    double full = 0;  // at the iteration's radius
    double half = 0;  // at half of it

    TwoRadii& operator+=(const TwoRadii& o) {
        full += o.full;
        half += o.half;
        return *this;
    }
    TwoRadii operator*(double k) const { return {full * k, half * k}; }
    // The bias of `full` if it grows like the radius.
    double bias() const { return 2.0 * (full - half); }
};

// Silverman's biweight over a disc of radius r (unit integral), at squared
// distance d2 from its centre (r2 = r^2), at r and r / 2.
inline TwoRadii discBiweight(double d2, double r2) {
    auto at = [&](double radius2) {
        if (!(d2 < radius2)) return 0.0;
        const double w = 1.0 - d2 / radius2;
        return 3.0 / (kPi * radius2) * w * w;
    };
    return {at(r2), at(0.25 * r2)};
}

// The biweight over a ball of radius r (unit integral: 105 / (32 pi r^3)
// (1 - d^2 / r^2)^2), at squared distance d2 from its centre, at r and r / 2.
inline TwoRadii ballBiweight(double d2, double r2) {
    auto at = [&](double radius2) {
        if (!(d2 < radius2)) return 0.0;
        const double w = 1.0 - d2 / radius2;
        return 105.0 / (32.0 * kPi * radius2 * std::sqrt(radius2)) * w * w;
    };
    return {at(r2), at(0.25 * r2)};
}

// The disc's biweight integrated along a chord (a unit 1D kernel across
// a line): 16 / (5 pi r) (1 - d^2 / r^2)^(5/2) at distance d from the
// line, at r and r / 2.
inline TwoRadii lineBiweight(double d2, double r) {
    auto at = [&](double radius) {
        const double radius2 = radius * radius;
        if (!(d2 < radius2)) return 0.0;
        const double u = 1.0 - d2 / radius2;
        return 16.0 / (5.0 * kPi * radius) * u * u * std::sqrt(u);
    };
    return {at(r), at(0.5 * r)};
}

// A sample that adds `gathered` (at r, and its bias) to what the camera path
// found without the kernel.
inline ChannelSample kernelSample(double withoutKernel, const TwoRadii& gathered) {
    ChannelSample sample;
    sample.value = float(withoutKernel + gathered.full);
    sample.bias = float(gathered.bias());
    return sample;
}

}  // namespace pl
