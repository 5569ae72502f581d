#include "scene/homogeneous_core.h"

#include <algorithm>
#include <array>

#include "core/surface_clearance.h"

namespace pl {

LabelGrid withHomogeneousCore(const LabelGrid& grid, const Geometry& geometry, float depth_mm, HomogeneousCore* core) {
    const GridFrame& frame = grid.frame();
    const float block_mm = float(1 << SurfaceClearance::kBlockLog2) * length(frame.voxelSize_mm);
    // Queries reach past the depth, so that a block's bound can exceed it.
    const SurfaceClearance clearance(geometry, frame, depth_mm + block_mm);
    // Deep voxels of every label but `skip` (and void).
    auto visitDeepVoxels = [&](Label skip, const auto& fn) {
        grid.visitRegions([&](const Vec3i& lo, const Vec3i& hi, Label l) {
            if (l == grid.voidLabel() || l == skip) return;
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x)
                        if (clearance.at(frame.voxelCenter_mm({x, y, z})) > depth_mm) fn(Vec3i{x, y, z}, l);
        });
    };
    std::array<uint64_t, 256> deep{};
    visitDeepVoxels(grid.voidLabel(), [&](const Vec3i&, Label l) { deep[l] += 1; });
    HomogeneousCore found;
    found.label = Label(std::max_element(deep.begin(), deep.end()) - deep.begin());
    for (uint64_t count : deep) found.coreVoxels += count;
    // The core's own voxels (most of the deep ones) need no second look.
    std::vector<LabelGrid::Change> changes;
    visitDeepVoxels(found.label, [&](const Vec3i& v, Label) { changes.push_back({v, found.label}); });
    found.changedVoxels = changes.size();
    if (core) *core = found;
    return grid.withChanges(changes);
}

}  // namespace pl
