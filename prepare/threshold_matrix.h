// A 3D threshold matrix with blue-noise properties, for halftoning by
// thresholds (prepare/halftone.h, ThresholdHalftone): void and cluster
// (Ulichney 1993) in three dimensions. Every rank 0..N-1 of an
// N-voxel tile is given once; the voxels of ranks below any k lie as far
// apart as they can (the largest void is filled next), so any threshold
// picks a well-spread set. Distances are in millimetres, so anisotropic
// voxels get a matrix that is blue in space, not in index.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vecmath.h"

namespace pl {

class ThresholdMatrix {
public:
    // A tile of `tile` voxels of size voxelSize_mm (deterministic: the same
    // arguments, the same matrix). Made once per voxel size by forVoxel.
    ThresholdMatrix(const Vec3i& tile, const Vec3f& voxelSize_mm);
    // The matrix for these voxels (tileFor's), made on first use and kept.
    static const ThresholdMatrix& forVoxel(const Vec3f& voxelSize_mm);
    // A tile of about 16,000 voxels, near a cube in mm.
    static Vec3i tileFor(const Vec3f& voxelSize_mm);

    // The voxel's threshold in (0, 1): (rank + 0.5) / N, the tile repeated.
    float at(const Vec3i& voxel) const {
        const int x = wrap(voxel.x, tile_.x), y = wrap(voxel.y, tile_.y), z = wrap(voxel.z, tile_.z);
        return threshold_[(size_t(z) * tile_.y + y) * tile_.x + x];
    }
    const Vec3i& tile() const { return tile_; }

private:
    static int wrap(int v, int n) {
        const int r = v % n;
        return r < 0 ? r + n : r;
    }
    Vec3i tile_;
    std::vector<float> threshold_;
};

}  // namespace pl
