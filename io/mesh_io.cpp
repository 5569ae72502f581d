#include "io/mesh_io.h"
#include "io/mesh_repair.h"

#include <string>
#include <unordered_map>

#include "io/file_names.h"
#include "core/input_error.h"
#include "io/mesh_formats.h"

namespace pl {

void validateClosedMesh(TriangleMesh& mesh, const std::string& file) {
    if (mesh.indices.empty()) throw InputError(file, "mesh has no triangles");
    // Weld vertices by exact position: files split vertices for normals/UVs.
    std::unordered_map<std::string, uint32_t> weldOf;
    std::vector<uint32_t> weld(mesh.positions_mm.size());
    for (size_t i = 0; i < mesh.positions_mm.size(); ++i) {
        std::string key(reinterpret_cast<const char*>(&mesh.positions_mm[i]), sizeof(Point3f));
        weld[i] = weldOf.emplace(key, uint32_t(weldOf.size())).first->second;
    }
    // Count each directed edge: a closed, oriented surface uses (a,b) once and (b,a) once.
    std::unordered_map<uint64_t, int> directed;
    for (size_t t = 0; t < mesh.triangleCount(); ++t)
        for (int e = 0; e < 3; ++e) {
            uint64_t a = weld[mesh.indices[3 * t + e]], b = weld[mesh.indices[3 * t + (e + 1) % 3]];
            if (a == b) continue;  // degenerate edge
            directed[(a << 32) | b] += 1;
        }
    size_t open = 0, misoriented = 0;
    for (const auto& [key, count] : directed) {
        uint64_t rev = (key << 32) | (key >> 32);
        auto it = directed.find(rev);
        int back = it == directed.end() ? 0 : it->second;
        if (back == 0) ++open;
        else if (count != 1 || back != 1) ++misoriented;
    }
    if (open)
        throw InputError(file, "mesh is not closed (" + std::to_string(open) +
                                   " boundary edges; prepare --repair repairs it)");
    if (misoriented)
        throw InputError(file, "mesh is not a consistently oriented 2-manifold (" +
                                   std::to_string(misoriented) + " bad edges; prepare --repair repairs it)");
    // Signed volume (divergence theorem): negative means inward normals.
    double volume = 0;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Point3f& a = mesh.positions_mm[mesh.indices[3 * t]];
        const Point3f& b = mesh.positions_mm[mesh.indices[3 * t + 1]];
        const Point3f& c = mesh.positions_mm[mesh.indices[3 * t + 2]];
        volume += double(dot(a, cross(b, c))) / 6.0;
    }
    if (volume == 0) throw InputError(file, "mesh encloses no volume");
    if (volume < 0)
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
}

void scaleMesh(TriangleMesh& mesh, double factor) {
    if (factor == 1.0) return;
    for (Point3f& p : mesh.positions_mm)
        p = Point3f(float(double(p.x) * factor), float(double(p.y) * factor), float(double(p.z) * factor));
}

TriangleMesh loadMesh(const std::filesystem::path& file, const MeshPlacement& placement, bool repair) {
    MeshRepairSummary summary;
    return loadMeshAsset(file, placement, repair ? &summary : nullptr).mesh;
}

MeshAsset loadMeshAsset(const std::filesystem::path& file, const MeshPlacement& placement, MeshRepairSummary* repaired) {
    std::string ext = lowerExtension(file);
    MeshAsset asset;
    if (ext == ".obj") asset = loadObj(file);
    else if (ext == ".gltf" || ext == ".glb") asset = loadGltf(file);
    else if (ext == ".stl" || ext == ".ply" || ext == ".3mf") asset = loadWithAssimp(file);
    else throw InputError(file.string(), "unknown mesh format (expected .gltf, .glb, .obj, .stl, .ply or .3mf)");
    // A repaired mesh is closed and oriented outwards (its triangles keep
    // their own vertices, so the index-based check does not apply). Both
    // work in the file's coordinates: the placement scales last, so that
    // prepare can measure the model before it chooses a scale.
    if (repaired)
        asset = repairMesh(asset, file.string(), *repaired);
    else
        validateClosedMesh(asset.mesh, file.string());
    scaleMesh(asset.mesh, placement.millimetresPerFileUnit(file));
    return asset;
}

}  // namespace pl
