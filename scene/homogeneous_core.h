// The homogeneous-core approximation (Brecka 2021, section 3.4): every
// voxel deeper under the surface than a depth takes one label, the one most
// of them hold (a print's white core). Deep light then walks one material
// (printpt's ball walks, tight majorants) at the cost of whatever colour
// lay that deep. Off by default; docs/performance.md measures its error
// per depth and what it saves.
#pragma once

#include "core/geometry.h"
#include "media/label_grid.h"

namespace pl {

struct HomogeneousCore {
    Label label = 0;             // the core's label
    uint64_t coreVoxels = 0;     // voxels found deeper than the depth
    uint64_t changedVoxels = 0;  // of those, voxels that held another label
};

// The grid with the voxels deeper than depth_mm relabelled (depth: a lower
// bound of the distance from the voxel's centre to the mesh, so no voxel
// nearer than depth_mm changes). `grid` and `geometry` in the same frame.
LabelGrid withHomogeneousCore(const LabelGrid& grid, const Geometry& geometry, float depth_mm,
                              HomogeneousCore* core = nullptr);

}  // namespace pl
