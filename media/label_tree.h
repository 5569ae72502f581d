// OpenVDB side of the label grid. Include only from .cpp files: OpenVDB
// headers are slow to compile.
#pragma once

#include <openvdb/openvdb.h>

#include "media/label_grid.h"

namespace pl {

using LabelTreeType = openvdb::tree::Tree4<uint8_t, 5, 4, 3>::Type;
using LabelVdbGrid = openvdb::Grid<LabelTreeType>;

struct LabelGrid::Tree {
    LabelTreeType::Ptr vdb;
};

// Initialises OpenVDB and registers the 8-bit label grid type (idempotent).
void initializeVdb();

inline openvdb::Coord toCoord(const Vec3i& v) { return openvdb::Coord(v.x, v.y, v.z); }

}  // namespace pl
