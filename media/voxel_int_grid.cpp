#include "media/voxel_int_grid.h"

#include <openvdb/openvdb.h>

namespace pl {

struct VoxelIntGrid::Impl {
    openvdb::Int32Tree tree;
    openvdb::tree::ValueAccessor<openvdb::Int32Tree> accessor;
    explicit Impl(int32_t background) : tree(background), accessor(tree) {}
};

VoxelIntGrid::VoxelIntGrid(int32_t background) : impl_(std::make_unique<Impl>(background)) {}
VoxelIntGrid::~VoxelIntGrid() = default;
VoxelIntGrid::VoxelIntGrid(VoxelIntGrid&&) noexcept = default;
VoxelIntGrid& VoxelIntGrid::operator=(VoxelIntGrid&&) noexcept = default;

int32_t VoxelIntGrid::get(const Vec3i& v) const { return impl_->accessor.getValue(openvdb::Coord(v.x, v.y, v.z)); }

void VoxelIntGrid::set(const Vec3i& v, int32_t value) { impl_->accessor.setValue(openvdb::Coord(v.x, v.y, v.z), value); }

void VoxelIntGrid::forEachSet(const std::function<void(const Vec3i&, int32_t)>& fn) const {
    for (auto it = impl_->tree.cbeginValueOn(); it; ++it) {
        if (!it.isVoxelValue()) continue;  // set voxel by voxel: no tiles
        const openvdb::Coord c = it.getCoord();
        fn(Vec3i{c.x(), c.y(), c.z()}, *it);
    }
}

uint64_t VoxelIntGrid::setCount() const { return impl_->tree.activeVoxelCount(); }

uint64_t VoxelIntGrid::memoryBytes() const { return impl_->tree.memUsage(); }

}  // namespace pl
