#include "core/nearest_surface_voxel.h"

#include <algorithm>
#include <cmath>

namespace pl {

NearestSurfaceVoxel::NearestSurfaceVoxel(const GridFrame& frame, const std::vector<Vec3i>& voxels) : frame_(frame) {
    pixelOf_.reserve(voxels.size());
    for (size_t i = 0; i < voxels.size(); ++i) pixelOf_.emplace(key(voxels[i]), uint32_t(i));
}

void NearestSurfaceVoxel::search(const Point3f& x_mm, const Vec3i& centre, const Vec3i& reach,
                                 std::optional<uint32_t>& best, float& best_mm2) const {
    for (int dz = -reach.z; dz <= reach.z; ++dz)
        for (int dy = -reach.y; dy <= reach.y; ++dy)
            for (int dx = -reach.x; dx <= reach.x; ++dx) {
                const Vec3i v{centre.x + dx, centre.y + dy, centre.z + dz};
                const Vec3f d = frame_.voxelCenter_mm(v) - x_mm;
                const float d2 = dot(d, d);
                // A cell farther than the best so far needs no look-up.
                if (d2 > best_mm2) continue;
                const std::optional<uint32_t> pixel = pixelOf(v);
                if (!pixel) continue;
                if (d2 < best_mm2 || (d2 == best_mm2 && best && *pixel < *best)) best_mm2 = d2, best = *pixel;
            }
}

std::optional<uint32_t> NearestSurfaceVoxel::at(const Point3f& x_mm) const {
    const Vec3f s = frame_.worldToCellScale(), o = frame_.worldToCellOffset();
    const Vec3i cell{int(std::floor(x_mm.x * s.x + o.x)), int(std::floor(x_mm.y * s.y + o.y)),
                     int(std::floor(x_mm.z * s.z + o.z))};
    const Vec3f& size = frame_.voxelSize_mm;
    const float most_mm = kMostVoxels * std::max(size.x, std::max(size.y, size.z));
    // The cells around first; then every cell that could hold a nearer
    // centre (anisotropic voxels: several layers along a thin axis).
    std::optional<uint32_t> best;
    float best_mm2 = most_mm * most_mm;
    search(x_mm, cell, {1, 1, 1}, best, best_mm2);
    const float bound_mm = std::sqrt(best_mm2);
    const Vec3i reach{int(std::ceil(bound_mm / size.x + 0.5f)), int(std::ceil(bound_mm / size.y + 0.5f)),
                      int(std::ceil(bound_mm / size.z + 0.5f))};
    if (reach.x > 1 || reach.y > 1 || reach.z > 1) search(x_mm, cell, reach, best, best_mm2);
    return best;
}

}  // namespace pl
