// Triangle meshes from glTF 2.0 (.gltf/.glb, through tinygltf), OBJ (with
// .mtl base colours and map_Kd textures), and STL, PLY and 3MF (through
// Assimp; io/mesh_formats.h), in millimetres. The object must be one
// closed, consistently oriented surface; it is re-oriented so that its
// normals point outwards.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "core/geometry.h"
#include "core/grid_frame.h"
#include "io/length_units.h"
#include "prepare/surface_appearance.h"

namespace pl {

struct MeshAsset {
    TriangleMesh mesh;
    SurfaceAppearance appearance;  // colours, if the file has any
};

struct MeshRepairSummary;
// The model in millimetres, placed by `placement` (its file's unit and a
// scale). repaired: none refuses a mesh that is not one closed surface;
// given, the mesh is repaired (io/mesh_repair.h) and what was done is
// reported there.
MeshAsset loadMeshAsset(const std::filesystem::path& file, const MeshPlacement& placement = {},
                        MeshRepairSummary* repaired = nullptr);
// Multiplies every position by millimetresPerFileUnit (in double, rounded
// once): what loadMeshAsset does with the placement's factor.
void scaleMesh(TriangleMesh& mesh, double millimetresPerFileUnit);
TriangleMesh loadMesh(const std::filesystem::path& file, const MeshPlacement& placement = {}, bool repair = false);

// Throws InputError(file, ...) unless every edge is shared by exactly two
// triangles with opposite orientation. Flips the winding if the enclosed
// volume is negative.
void validateClosedMesh(TriangleMesh& mesh, const std::string& file);

// Writes a Wavefront OBJ (positions and triangles).
void writeObj(const TriangleMesh& mesh, const std::filesystem::path& file);

// Writes a glTF 2.0 file (.gltf with the buffer embedded; coordinates in
// metres, as glTF says, from the mesh's millimetres) with optional UVs,
// vertex colours (linear) and a base-colour texture referenced by a relative
// path (an sRGB PNG beside the file).
void writeGltf(const TriangleMesh& mesh, const SurfaceAppearance& appearance,
               const std::string& textureUri, const std::filesystem::path& file);

// The prediction on the model, as a glTF binary any viewer opens: the
// object's own mesh (millimetres, as loaded for the render; in metres in
// the file) with the colours of its surface voxels (linear RGB, clamped to
// [0, 1]) baked into a texture: each point of the surface shows the voxel
// whose centre is nearest (core/nearest_surface_voxel.h), in an atlas of
// the triangles (core/triangle_atlas.h) at the voxel's middle side, as an
// 8-bit sRGB PNG, under an unlit material.
// GlbTooLarge (before anything is written) if it would exceed the
// format's 4 GiB.
struct GlbTooLarge : std::length_error {
    using std::length_error::length_error;
};
void writePredictionGlb(const TriangleMesh& mesh_mm, const GridFrame& frame, const std::vector<Vec3i>& voxels,
                        const std::vector<RGB>& linearColor, const std::filesystem::path& file);

}  // namespace pl
