// Voxelisation of a closed mesh at the printer's (anisotropic) voxel size.
//  - Inside: scanlines along x through the voxel centres of every (y, z)
//    column, with the winding number of the crossings (robust to crossings
//    reported twice on shared edges).
//  - Distance: exact distance in millimetres to the mesh (Embree point
//    queries) for voxels within a band around the surface; bricks of 8^3
//    voxels far from the surface are skipped whole.
//  - Membership: a voxel belongs to the object if its centre is inside, or
//    if the surface passes through its box (it overlaps the interior), so no
//    void sliver separates the mesh from the first voxels of resin.
// Work is streamed slice by slice in z, so memory stays proportional to the
// band, not to the whole grid.
#pragma once

#include <functional>
#include <vector>

#include "core/geometry.h"
#include "core/grid_frame.h"

namespace pl {

struct VoxelizeSettings {
    Vec3f voxel_mm = kPrinterVoxel_mm;
    float margin_mm = 0.12f;                   // void padding around the mesh (Brecka 3.1)
    float band_mm = 1.2f;                      // half-width of the distance band
};

// What the voxeliser knows about one voxel of a slice.
struct VoxelSample {
    int32_t x;
    bool inside;             // centre inside the mesh
    bool member;             // part of the printed object
    bool inBand;             // distance, normal and surface point below are valid
    float sdf_mm;            // signed distance, negative inside
    Vec3f normal;            // unit outward gradient of the distance
    Point3f surfacePoint_mm; // closest point on the mesh
    uint32_t prim;           // triangle of the closest point
};

// One row (fixed y, z) of a slice: samples for the member voxels and the
// band voxels, in increasing x. Voxels not listed are void and outside the
// band (their distance is the band's background).
struct VoxelRow {
    std::vector<VoxelSample> samples;
};

class Voxelizer {
public:
    Voxelizer(const Geometry& geometry, const VoxelizeSettings& settings);
    // The grid a mesh with these bounds gets (check its size before building).
    static GridFrame frameFor(const Bounds3f& meshBounds, const VoxelizeSettings& settings);

    const GridFrame& frame() const { return frame_; }
    // Bricks within reach of the surface, and all bricks.
    size_t nearBricks() const { return nearBrickCount_; }

    // Computes slice z (rows y = 0..res.y-1), in parallel over rows.
    std::vector<VoxelRow> slice(int z) const;

private:
    bool brickNear(int bx, int by, int bz) const;

    const Geometry& geometry_;
    VoxelizeSettings settings_;
    GridFrame frame_;
    // Inside intervals [x0, x1) of voxel indices, per column (y + z * res.y).
    std::vector<std::vector<std::pair<int32_t, int32_t>>> inside_;
    Vec3i brickRes_;
    std::vector<uint8_t> brickNear_;
    size_t nearBrickCount_ = 0;
};

}  // namespace pl
