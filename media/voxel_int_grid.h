// Sparse integers on voxels (an OpenVDB tree behind it): a value where one
// was set, the background elsewhere. Memory follows the voxels set, not
// the grid's volume: the optimisation loop's shell of a tray-sized object.
// Reads and writes go through one cached accessor: one thread at a time.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "core/vecmath.h"

namespace pl {

class VoxelIntGrid {
public:
    explicit VoxelIntGrid(int32_t background);
    ~VoxelIntGrid();
    VoxelIntGrid(VoxelIntGrid&&) noexcept;
    VoxelIntGrid& operator=(VoxelIntGrid&&) noexcept;

    int32_t get(const Vec3i& v) const;
    void set(const Vec3i& v, int32_t value);
    // Every voxel set, in the tree's order (the same whatever was set first).
    void forEachSet(const std::function<void(const Vec3i&, int32_t)>& fn) const;
    uint64_t setCount() const;
    uint64_t memoryBytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pl
