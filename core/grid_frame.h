// Placement of a voxel lattice in the world. Spaces:
//  - world: millimetres (Point3f).
//  - cell: continuous voxel space; voxel (i,j,k) covers [i,i+1)x[j,j+1)x[k,k+1).
//    A point maps to its voxel by flooring; OpenVDB's index = cell - 0.5.
//  - world -> cell is a per-axis scale and offset (no matrix).
#pragma once

#include <cstdint>

#include "core/vecmath.h"

namespace pl {

// The printer's voxel: 600 x 300 dpi across the build plate, 27 um layers.
inline constexpr Vec3f kPrinterVoxel_mm{0.0423f, 0.0847f, 0.027f};

// Placement of the voxel lattice: voxels [indexMin, indexMin + resolution).
struct GridFrame {
    Vec3i indexMin{0, 0, 0};
    Vec3i resolution{0, 0, 0};
    Vec3f voxelSize_mm{1, 1, 1};
    Point3f cornerMin_mm{0, 0, 0};  // world position of voxel indexMin's lower corner

    Vec3i indexMax() const {  // exclusive
        return {indexMin.x + resolution.x, indexMin.y + resolution.y, indexMin.z + resolution.z};
    }
    Point3f cornerMax_mm() const {
        return {cornerMin_mm.x + resolution.x * voxelSize_mm.x,
                cornerMin_mm.y + resolution.y * voxelSize_mm.y,
                cornerMin_mm.z + resolution.z * voxelSize_mm.z};
    }
    uint64_t voxelCount() const {
        return uint64_t(resolution.x) * uint64_t(resolution.y) * uint64_t(resolution.z);
    }
    // world -> cell: cell = p * scale + offset, per axis.
    Vec3f worldToCellScale() const {
        return {1.0f / voxelSize_mm.x, 1.0f / voxelSize_mm.y, 1.0f / voxelSize_mm.z};
    }
    Vec3f worldToCellOffset() const {
        return {indexMin.x - cornerMin_mm.x / voxelSize_mm.x,
                indexMin.y - cornerMin_mm.y / voxelSize_mm.y,
                indexMin.z - cornerMin_mm.z / voxelSize_mm.z};
    }
    Point3f voxelCenter_mm(const Vec3i& v) const {
        return {cornerMin_mm.x + (v.x - indexMin.x + 0.5f) * voxelSize_mm.x,
                cornerMin_mm.y + (v.y - indexMin.y + 0.5f) * voxelSize_mm.y,
                cornerMin_mm.z + (v.z - indexMin.z + 0.5f) * voxelSize_mm.z};
    }
    bool contains(const Vec3i& v) const {
        Vec3i hi = indexMax();
        return v.x >= indexMin.x && v.y >= indexMin.y && v.z >= indexMin.z && v.x < hi.x &&
               v.y < hi.y && v.z < hi.z;
    }
};

// The six face neighbours of a voxel, in the order of SurfaceVoxel's bits.
constexpr Vec3i kFaceDirections[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                      {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};

// A voxel of the object with at least one face towards void: bit k of
// exposedFaces is set when the neighbour at kFaceDirections[k] is void.
struct SurfaceVoxel {
    Vec3i voxel;
    uint8_t exposedFaces = 0;
    bool operator==(const SurfaceVoxel& o) const { return voxel == o.voxel && exposedFaces == o.exposedFaces; }
    bool operator!=(const SurfaceVoxel& o) const { return !(*this == o); }
};

}  // namespace pl
