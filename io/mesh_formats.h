// The mesh formats behind loadMeshAsset (io/mesh_io.h), one file each:
// they read the triangles and colours, coordinates in the file's unit;
// loadMeshAsset converts them to millimetres and checks the surface.
#pragma once

#include <filesystem>

#include "io/mesh_io.h"

namespace pl {

// Wavefront OBJ with .mtl base colours and map_Kd textures (io/obj_io.cpp).
MeshAsset loadObj(const std::filesystem::path& file);
// glTF 2.0, .gltf or .glb, through tinygltf (io/gltf_io.cpp).
MeshAsset loadGltf(const std::filesystem::path& file);
// STL (binary and ASCII), PLY and 3MF, through Assimp (io/assimp_io.cpp):
// triangles, vertex colours (PLY) and 3MF's material colours.
MeshAsset loadWithAssimp(const std::filesystem::path& file);

}  // namespace pl
