// Repairs what real meshes get wrong before printing: vertices duplicated
// along seams or per facet (welded), degenerate triangles (dropped),
// inconsistent orientation, cracks whose two sides match (stitched) and
// holes (filled), with CGAL's polygon mesh processing. The result is one
// closed surface oriented outwards; each triangle keeps its own three
// vertices so that every triangle from the input keeps its colours (UVs,
// vertex colours, material). Triangles that fill a hole take the material
// and the nearest colours of an input triangle next to them.
#pragma once

#include <string>

#include "io/mesh_io.h"

namespace pl {

struct MeshRepairSummary {
    size_t weldedVertices = 0, degenerateTriangles = 0, reorientedTriangles = 0, stitchedEdges = 0,
           holesFilled = 0, fillTriangles = 0;
    std::string text() const;  // one line, e.g. for prepare's summary
};

// Throws InputError(file, ...) if the mesh cannot be made closed.
MeshAsset repairMesh(const MeshAsset& asset, const std::string& file, MeshRepairSummary& summary);

}  // namespace pl
