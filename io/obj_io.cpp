#include "io/mesh_formats.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "io/file_names.h"
#include "io/image_io.h"
#include "core/input_error.h"
#include "io/output_file.h"

namespace pl {

namespace {

// Base colours of an OBJ's .mtl file: Kd and map_Kd per material name.
struct ObjMaterials {
    std::map<std::string, uint32_t> index;
    SurfaceAppearance* appearance;
};

void loadMtl(const std::filesystem::path& file, ObjMaterials& out) {
    const std::string name = file.string();
    std::ifstream in(file);
    if (!in) throw InputError(name, "cannot open material library");
    std::string line;
    int current = -1;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string tag;
        if (!(ls >> tag) || tag[0] == '#') continue;
        auto& mats = out.appearance->materials;
        if (tag == "newmtl") {
            std::string m;
            ls >> m;
            current = int(mats.size());
            out.index[m] = uint32_t(current);
            mats.push_back({});
        } else if (current >= 0 && tag == "Kd") {
            RGB kd;
            if (!(ls >> kd[0] >> kd[1] >> kd[2])) throw InputError(name, "malformed Kd");
            mats[size_t(current)].baseColorFactor = kd;
        } else if (current >= 0 && tag == "map_Kd") {
            std::string rest, tex;
            std::getline(ls, rest);
            std::istringstream rs(rest);
            while (rs >> tex) {}  // options may precede the file name; it comes last
            // Exporters on Windows write ".\\name.jpg": the separator is ours.
            std::replace(tex.begin(), tex.end(), '\\', '/');
            const std::filesystem::path texture = file.parent_path() / tex;
            if (!std::filesystem::exists(texture)) {
                std::fprintf(stderr, "printlight: warning: %s: texture %s not found; its material keeps its Kd\n",
                             name.c_str(), texture.string().c_str());
                continue;
            }
            out.appearance->textures.push_back(readTexture(texture));
            mats[size_t(current)].texture = int(out.appearance->textures.size()) - 1;
        }
    }
}

}  // namespace

MeshAsset loadObj(const std::filesystem::path& file) {
    const std::string name = file.string();
    std::ifstream in(file);
    if (!in) throw InputError(name, "cannot open file");
    MeshAsset asset;
    TriangleMesh& mesh = asset.mesh;
    SurfaceAppearance& look = asset.appearance;
    ObjMaterials materials{{}, &look};
    std::vector<Point3f> positions;
    std::vector<Vec3f> fileNormals;
    std::vector<std::array<float, 2>> fileUvs;
    // OBJ indexes positions, UVs and normals separately; one output vertex per triple.
    std::map<std::array<int64_t, 3>, uint32_t> vertexOf;
    std::string line;
    size_t lineNo = 0;
    bool anyNormals = false, anyUvs = false;
    uint32_t currentMaterial = 0;
    auto bad = [&](const std::string& what) {
        throw InputError(name, "line " + std::to_string(lineNo) + ": " + what);
    };
    while (std::getline(in, line)) {
        ++lineNo;
        std::istringstream ls(line);
        std::string tag;
        if (!(ls >> tag) || tag[0] == '#') continue;
        if (tag == "v") {
            Point3f p;
            if (!(ls >> p.x >> p.y >> p.z)) bad("malformed vertex");
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) bad("non-finite vertex");
            positions.push_back(p);
        } else if (tag == "vn") {
            Vec3f n;
            if (!(ls >> n.x >> n.y >> n.z)) bad("malformed normal");
            fileNormals.push_back(n);
        } else if (tag == "vt") {
            std::array<float, 2> uv;
            if (!(ls >> uv[0] >> uv[1])) bad("malformed texture coordinate");
            fileUvs.push_back({uv[0], 1.0f - uv[1]});  // OBJ's v points up; glTF's down
        } else if (tag == "mtllib") {
            std::string lib;
            ls >> lib;
            loadMtl(file.parent_path() / lib, materials);
        } else if (tag == "usemtl") {
            std::string m;
            ls >> m;
            // A name the .mtl does not define (exporters write "None" or
            // "Default") is white, as other OBJ readers take it.
            auto it = materials.index.find(m);
            if (it == materials.index.end()) {
                it = materials.index.emplace(m, uint32_t(look.materials.size())).first;
                look.materials.push_back({});
            }
            currentMaterial = it->second;
        } else if (tag == "f") {
            std::vector<uint32_t> poly;
            std::string ref;
            while (ls >> ref) {
                std::array<int64_t, 3> key{0, 0, 0};  // v, vt, vn (1-based, 0 = none)
                try {
                    size_t start = 0;
                    for (int k = 0; k < 3 && start <= ref.size(); ++k) {
                        size_t slash = ref.find('/', start);
                        std::string part = ref.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
                        if (!part.empty()) key[k] = std::stoll(part);
                        if (slash == std::string::npos) break;
                        start = slash + 1;
                    }
                } catch (const std::exception&) {
                    bad("malformed face index '" + ref + "'");
                }
                const int64_t sizes[3] = {int64_t(positions.size()), int64_t(fileUvs.size()), int64_t(fileNormals.size())};
                for (int k = 0; k < 3; ++k) {
                    if (key[k] < 0) key[k] += sizes[k] + 1;
                    if (key[k] < (k == 0 ? 1 : 0) || key[k] > sizes[k]) bad("face index out of range");
                }
                anyUvs = anyUvs || key[1] > 0;
                anyNormals = anyNormals || key[2] > 0;
                auto it = vertexOf.find(key);
                if (it == vertexOf.end()) {
                    it = vertexOf.emplace(key, uint32_t(mesh.positions_mm.size())).first;
                    mesh.positions_mm.push_back(positions[size_t(key[0] - 1)]);
                    look.uvs.push_back(key[1] > 0 ? fileUvs[size_t(key[1] - 1)] : std::array<float, 2>{0, 0});
                    mesh.normals.push_back(key[2] > 0 ? fileNormals[size_t(key[2] - 1)] : Vec3f(0, 0, 0));
                }
                poly.push_back(it->second);
            }
            if (poly.size() < 3) bad("face with fewer than three vertices");
            for (size_t k = 1; k + 1 < poly.size(); ++k) {  // fan triangulation
                mesh.indices.insert(mesh.indices.end(), {poly[0], poly[k], poly[k + 1]});
                look.triangleMaterial.push_back(currentMaterial);
            }
        }
    }
    if (!anyNormals) mesh.normals.clear();
    if (!anyUvs) look.uvs.clear();
    if (look.materials.empty()) look.triangleMaterial.clear();
    return asset;
}

void writeObj(const TriangleMesh& mesh, const std::filesystem::path& file) {
    OutputFile out(file);
    {
        std::ofstream os(out.tempPath());
        os.precision(9);
        os << "# printlight mesh\n";
        for (const Point3f& p : mesh.positions_mm) os << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            os << "f " << mesh.indices[3 * t] + 1 << ' ' << mesh.indices[3 * t + 1] + 1 << ' '
               << mesh.indices[3 * t + 2] + 1 << '\n';
        if (!os) throw std::runtime_error(file.string() + ": write failed");
    }
    out.commit();
}

}  // namespace pl
