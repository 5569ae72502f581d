// OpenVDB side of VoxelFields. Include only from .cpp files.
#pragma once

#include <openvdb/openvdb.h>

#include "media/voxel_fields.h"

namespace pl {

struct VoxelFields::Grids {
    openvdb::FloatGrid::Ptr sdf;
    openvdb::Vec3SGrid::Ptr normal;
    openvdb::Vec3SGrid::Ptr colors;  // null unless asked for
    openvdb::FloatGrid::Accessor sdfAccess;
    openvdb::Vec3SGrid::Accessor normalAccess;
    std::unique_ptr<openvdb::Vec3SGrid::Accessor> colorAccess;
};

}  // namespace pl
