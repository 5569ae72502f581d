#include "core/surface_clearance.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace pl {

SurfaceClearance::SurfaceClearance(const Geometry& geometry, const GridFrame& frame, float leastSearchRadius_mm) {
    constexpr int kB = 1 << kBlockLog2;
    voxelCount_ = frame.resolution;
    blocks_ = {(voxelCount_.x + kB - 1) / kB, (voxelCount_.y + kB - 1) / kB, (voxelCount_.z + kB - 1) / kB};
    scale_ = frame.worldToCellScale();
    offset_ = {-frame.cornerMin_mm.x * scale_.x, -frame.cornerMin_mm.y * scale_.y, -frame.cornerMin_mm.z * scale_.z};
    voxel_mm_ = frame.voxelSize_mm;
    centerDistance_mm_.assign(size_t(blocks_.x) * blocks_.y * blocks_.z, 0.0f);
    const Vec3f block_mm{kB * frame.voxelSize_mm.x, kB * frame.voxelSize_mm.y, kB * frame.voxelSize_mm.z};
    // Beyond this no query is needed: flights that long are rare in resin.
    const float searchRadius_mm = searchRadius_mm_ = std::max(4.0f * length(block_mm), leastSearchRadius_mm);
    // Room for round-off in the ray origin and the world -> cell mapping.
    const float margin_mm = margin_mm_ = 4.0f * geometry.rayEpsilon_mm() + 1e-4f * length(block_mm);
    tbb::parallel_for(0, blocks_.z, [&](int z) {
        for (int y = 0; y < blocks_.y; ++y)
            for (int x = 0; x < blocks_.x; ++x) {
                Point3f center{frame.cornerMin_mm.x + (x + 0.5f) * block_mm.x,
                               frame.cornerMin_mm.y + (y + 0.5f) * block_mm.y,
                               frame.cornerMin_mm.z + (z + 0.5f) * block_mm.z};
                auto c = geometry.closestPoint(center, searchRadius_mm);
                float d = c ? c->distance_mm : searchRadius_mm;
                centerDistance_mm_[blockIndex(x, y, z)] = d - margin_mm;
            }
    });
}

}  // namespace pl
