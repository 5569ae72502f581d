#include "media/voxel_fields.h"

#include <openvdb/tools/SignedFloodFill.h>

#include "media/label_tree.h"
#include "media/voxel_fields_vdb.h"

namespace pl {

namespace {
std::unique_ptr<VoxelFields::Grids> makeGrids(float background, bool withColors) {
    initializeVdb();
    auto sdf = openvdb::FloatGrid::create(background);
    auto normal = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    openvdb::Vec3SGrid::Ptr colors = withColors ? openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f)) : nullptr;
    auto g = std::unique_ptr<VoxelFields::Grids>(
        new VoxelFields::Grids{sdf, normal, colors, sdf->getAccessor(), normal->getAccessor(), nullptr});
    if (colors) g->colorAccess = std::make_unique<openvdb::Vec3SGrid::Accessor>(colors->getAccessor());
    return g;
}
}  // namespace

VoxelFields::VoxelFields(float sdfBackground_mm, bool withColors)
    : grids_(makeGrids(sdfBackground_mm, withColors)) {}
VoxelFields::VoxelFields(std::unique_ptr<Grids> grids) : grids_(std::move(grids)) {}
VoxelFields::~VoxelFields() = default;
VoxelFields::VoxelFields(VoxelFields&&) noexcept = default;

void VoxelFields::setSdf(const Vec3i& v, float sdf_mm) { grids_->sdfAccess.setValueOn(toCoord(v), sdf_mm); }
void VoxelFields::setNormal(const Vec3i& v, const Vec3f& n) {
    grids_->normalAccess.setValueOn(toCoord(v), openvdb::Vec3s(n.x, n.y, n.z));
}
void VoxelFields::setColor(const Vec3i& v, const RGB& c) {
    if (grids_->colorAccess) grids_->colorAccess->setValueOn(toCoord(v), openvdb::Vec3s(c[0], c[1], c[2]));
}
bool VoxelFields::hasColors() const { return grids_->colors != nullptr; }

void VoxelFields::finish() {
    grids_->sdfAccess.clear();
    grids_->normalAccess.clear();
    if (grids_->colorAccess) grids_->colorAccess->clear();
    openvdb::tools::signedFloodFill(grids_->sdf->tree());
    grids_->sdf->tree().prune();
    grids_->normal->tree().prune();
}

float VoxelFields::sdf(const Vec3i& v) const { return grids_->sdf->tree().getValue(toCoord(v)); }
Vec3f VoxelFields::normal(const Vec3i& v) const {
    openvdb::Vec3s n = grids_->normal->tree().getValue(toCoord(v));
    return {n.x(), n.y(), n.z()};
}

uint64_t VoxelFields::memoryBytes() const {
    uint64_t m = grids_->sdf->memUsage() + grids_->normal->memUsage();
    if (grids_->colors) m += grids_->colors->memUsage();
    return m;
}

}  // namespace pl
