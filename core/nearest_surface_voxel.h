// The surface voxel whose centre is nearest to a point of the surface,
// without the patches: a table from voxel to sensor pixel, searched around
// the point's cell. For colours that belong to surface voxels shown on the
// mesh. The patches (core/surface_patches.h) look their owners up in the
// same table, by their own rule (the nearest in the first box of cells
// that holds any).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <absl/container/flat_hash_map.h>

#include "core/grid_frame.h"

namespace pl {

class NearestSurfaceVoxel {
public:
    // voxels: the surface voxels in sensor-pixel order.
    NearestSurfaceVoxel(const GridFrame& frame, const std::vector<Vec3i>& voxels);
    // The pixel of the voxel whose centre is nearest to x (ties: the lower
    // pixel), among those within kMostVoxels of the largest voxel side;
    // none if there is none.
    std::optional<uint32_t> at(const Point3f& x_mm) const;
    static constexpr float kMostVoxels = 2.0f;
    // The pixel of a surface voxel; none for any other voxel.
    std::optional<uint32_t> pixelOf(const Vec3i& voxel) const {
        auto it = pixelOf_.find(key(voxel));
        if (it == pixelOf_.end()) return std::nullopt;
        return it->second;
    }

private:
    static uint64_t key(const Vec3i& v) {
        return (uint64_t(uint32_t(v.x + (1 << 20)) & 0x1FFFFF) << 42) |
               (uint64_t(uint32_t(v.y + (1 << 20)) & 0x1FFFFF) << 21) | uint64_t(uint32_t(v.z + (1 << 20)) & 0x1FFFFF);
    }
    // The nearest within the box of cells centre +- reach; best_mm2 in/out.
    void search(const Point3f& x_mm, const Vec3i& centre, const Vec3i& reach, std::optional<uint32_t>& best,
                float& best_mm2) const;

    GridFrame frame_;
    absl::flat_hash_map<uint64_t, uint32_t> pixelOf_;
};

}  // namespace pl
