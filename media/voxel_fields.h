// Sparse per-voxel fields that `prepare` writes beside the labels: the
// signed distance to the surface in millimetres (negative inside, narrow
// band, +-background beyond it), its unit outward gradient (the normal), and
// optionally the linear-RGB target colours of the surface shell. OpenVDB
// stays in voxel_fields.cpp and io/grid_io.cpp (media/voxel_fields_vdb.h).
#pragma once

#include <memory>

#include "core/rgb.h"
#include "core/vecmath.h"

namespace pl {

class VoxelFields {
public:
    struct Grids;  // the OpenVDB grids (media/voxel_fields_vdb.h)

    explicit VoxelFields(float sdfBackground_mm, bool withColors);
    explicit VoxelFields(std::unique_ptr<Grids> grids);  // read from a file (io/grid_io)
    ~VoxelFields();
    VoxelFields(VoxelFields&&) noexcept;

    // Single-threaded writers.
    void setSdf(const Vec3i& v, float sdf_mm);
    void setNormal(const Vec3i& v, const Vec3f& n);
    void setColor(const Vec3i& v, const RGB& c);
    bool hasColors() const;
    // Marks the inside of the band negative (sign flood fill) and collapses
    // uniform blocks. Call once, after the last set.
    void finish();

    float sdf(const Vec3i& v) const;
    Vec3f normal(const Vec3i& v) const;
    uint64_t memoryBytes() const;
    const Grids& grids() const { return *grids_; }

private:
    std::unique_ptr<Grids> grids_;
};

}  // namespace pl
