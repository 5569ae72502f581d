// A lower bound of the distance from a point to the object's boundary: the
// distance from the centre of its block of 4^3 voxels to the boundary (one
// Embree point query per block at load) minus the distance from the point to
// that centre (triangle inequality). printpt samples the medium first:
// a collision closer to the ray's start than this bound cannot lie beyond the
// boundary, so the boundary query is skipped (most collisions deep in the
// resin need none).
#pragma once

#include <limits>
#include <vector>

#include "core/geometry.h"
#include "core/grid_frame.h"

namespace pl {

class SurfaceClearance {
public:
    static constexpr int kBlockLog2 = 2;

    // Each block's query looks this far at least (a bound is never larger
    // than its query's reach).
    SurfaceClearance(const Geometry& geometry, const GridFrame& frame, float leastSearchRadius_mm = 0.0f);

    // A distance (mm) that the boundary is no closer than to p; 0 where
    // the boundary may be close or p is outside the frame.
    float at(const Point3f& p) const {
        size_t block;
        Vec3f fromCenter_mm;
        if (!locate(p, block, fromCenter_mm)) return 0.0f;
        return centerDistance_mm_[block] - length(fromCenter_mm);
    }

    // A distance (mm) that the boundary is no farther than from p, where
    // the block's query found it (within its search radius); +inf where
    // that is not known.
    float upperBoundAt(const Point3f& p) const {
        size_t block;
        Vec3f fromCenter_mm;
        if (!locate(p, block, fromCenter_mm)) return std::numeric_limits<float>::infinity();
        const float centre = centerDistance_mm_[block] + margin_mm_;
        if (!(centre < searchRadius_mm_)) return std::numeric_limits<float>::infinity();
        return centre + length(fromCenter_mm) + margin_mm_;
    }

private:
    size_t blockIndex(int x, int y, int z) const { return (size_t(z) * blocks_.y + y) * blocks_.x + x; }
    // p's block and the offset (mm) from the block's centre to p; false
    // outside the frame.
    bool locate(const Point3f& p, size_t& block, Vec3f& fromCenter_mm) const {
        int b[3];
        for (int a = 0; a < 3; ++a) {
            float cell = p[a] * scale_[a] + offset_[a];
            if (!(cell >= 0.0f && cell < float(voxelCount_[a]))) return false;
            b[a] = int(cell) >> kBlockLog2;
            fromCenter_mm[a] = (cell - (float(b[a] << kBlockLog2) + 0.5f * (1 << kBlockLog2))) * voxel_mm_[a];
        }
        block = blockIndex(b[0], b[1], b[2]);
        return true;
    }
    Vec3i blocks_, voxelCount_;
    Vec3f scale_, offset_;  // world -> voxels counted from the frame's corner
    Vec3f voxel_mm_;
    // Distance from each block's centre to the boundary, less a round-off margin.
    std::vector<float> centerDistance_mm_;
    float searchRadius_mm_ = 0, margin_mm_ = 0;
};

}  // namespace pl
