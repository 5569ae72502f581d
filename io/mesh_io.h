// Triangle meshes from glTF 2.0 (.gltf/.glb, through tinygltf) and OBJ.
// The object must be one closed, consistently oriented surface; it is
// re-oriented so that its normals point outwards.
#pragma once

#include <filesystem>

#include "core/geometry.h"

namespace pl {

TriangleMesh loadMesh(const std::filesystem::path& file);

// Throws InputError(file, ...) unless every edge is shared by exactly two
// triangles with opposite orientation. Flips the winding if the enclosed
// volume is negative.
void validateClosedMesh(TriangleMesh& mesh, const std::string& file);

// Writes a Wavefront OBJ (positions and triangles).
void writeObj(const TriangleMesh& mesh, const std::filesystem::path& file);

}  // namespace pl
