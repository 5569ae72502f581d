// The kernel radius of a progressive density estimator (Knaus and Zwicker
// 2011): each iteration shrinks the kernel's measure (r^k for a kernel over
// k dimensions: 3 for a ball, 2 for a disc, 1 for a line) by
// (i + alpha) / (i + 1), so the bias and the variance both vanish as
// iterations go on.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/vecmath.h"

namespace pl {

class ProgressiveRadius {
public:
    // The first radius is radius_voxels of the grid's smallest voxel side.
    ProgressiveRadius(float radius_voxels, const Vec3f& voxelSize_mm, float alpha, int kernelDimensions)
        : firstRadius_mm_(radius_voxels * std::min(voxelSize_mm.x, std::min(voxelSize_mm.y, voxelSize_mm.z))),
          alpha_(alpha),
          kernelDimensions_(kernelDimensions) {}

    // The radius of iteration i (from 1).
    float at_mm(uint32_t iteration) const {
        double measure = 1.0;
        for (uint32_t j = 1; j < iteration; ++j) measure *= (double(j) + alpha_) / double(j + 1);
        const double scale = kernelDimensions_ == 1   ? measure
                             : kernelDimensions_ == 2 ? std::sqrt(measure)
                                                      : std::cbrt(measure);
        return float(double(firstRadius_mm_) * scale);
    }

private:
    float firstRadius_mm_;
    float alpha_;
    int kernelDimensions_;
};

}  // namespace pl
