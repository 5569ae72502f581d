#include "io/mesh_io.h"

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "io/file_names.h"
#include "io/input_error.h"
#include "io/output_file.h"

namespace pl {

namespace {

TriangleMesh loadObj(const std::filesystem::path& file) {
    const std::string name = file.string();
    std::ifstream in(file);
    if (!in) throw InputError(name, "cannot open file");
    TriangleMesh mesh;
    std::vector<Vec3f> fileNormals;
    // OBJ indexes positions and normals separately; one output vertex per pair.
    std::map<std::pair<int64_t, int64_t>, uint32_t> vertexOf;
    std::vector<Point3f> positions;
    std::string line;
    size_t lineNo = 0;
    bool anyNormals = false;
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
        } else if (tag == "f") {
            std::vector<uint32_t> poly;
            std::string ref;
            while (ls >> ref) {
                int64_t vi = 0, ni = 0;
                size_t s1 = ref.find('/');
                try {
                    vi = std::stoll(ref.substr(0, s1));
                    if (s1 != std::string::npos) {
                        size_t s2 = ref.find('/', s1 + 1);
                        if (s2 != std::string::npos && s2 + 1 < ref.size()) ni = std::stoll(ref.substr(s2 + 1));
                    }
                } catch (const std::exception&) {
                    bad("malformed face index '" + ref + "'");
                }
                if (vi < 0) vi += int64_t(positions.size()) + 1;
                if (ni < 0) ni += int64_t(fileNormals.size()) + 1;
                if (vi < 1 || vi > int64_t(positions.size())) bad("face index out of range");
                if (ni < 0 || ni > int64_t(fileNormals.size())) bad("normal index out of range");
                anyNormals = anyNormals || ni > 0;
                auto key = std::make_pair(vi, ni);
                auto it = vertexOf.find(key);
                if (it == vertexOf.end()) {
                    it = vertexOf.emplace(key, uint32_t(mesh.positions_mm.size())).first;
                    mesh.positions_mm.push_back(positions[size_t(vi - 1)]);
                    mesh.normals.push_back(ni > 0 ? fileNormals[size_t(ni - 1)] : Vec3f(0, 0, 0));
                }
                poly.push_back(it->second);
            }
            if (poly.size() < 3) bad("face with fewer than three vertices");
            for (size_t k = 1; k + 1 < poly.size(); ++k)  // fan triangulation
                mesh.indices.insert(mesh.indices.end(), {poly[0], poly[k], poly[k + 1]});
        }
    }
    if (!anyNormals) mesh.normals.clear();
    return mesh;
}

// Reads a float accessor of `components` components per element.
std::vector<float> readAccessor(const tinygltf::Model& model, int index, int components,
                                const std::string& name) {
    if (index < 0 || index >= int(model.accessors.size())) throw InputError(name, "bad accessor index");
    const auto& acc = model.accessors[size_t(index)];
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || tinygltf::GetNumComponentsInType(acc.type) != components)
        throw InputError(name, "unsupported vertex attribute type");
    const auto& view = model.bufferViews[size_t(acc.bufferView)];
    const auto& buf = model.buffers[size_t(view.buffer)];
    size_t stride = acc.ByteStride(view);
    size_t begin = view.byteOffset + acc.byteOffset;
    if (stride == 0 || begin + stride * (acc.count ? acc.count - 1 : 0) + components * 4 > buf.data.size())
        throw InputError(name, "accessor runs past its buffer");
    std::vector<float> out(acc.count * size_t(components));
    for (size_t i = 0; i < acc.count; ++i)
        std::memcpy(&out[i * components], &buf.data[begin + i * stride], size_t(components) * 4);
    return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& name) {
    const auto& acc = model.accessors.at(size_t(index));
    const auto& view = model.bufferViews.at(size_t(acc.bufferView));
    const auto& buf = model.buffers.at(size_t(view.buffer));
    size_t size = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType)));
    size_t stride = view.byteStride ? view.byteStride : size;
    size_t begin = view.byteOffset + acc.byteOffset;
    if (begin + stride * (acc.count ? acc.count - 1 : 0) + size > buf.data.size())
        throw InputError(name, "index accessor runs past its buffer");
    std::vector<uint32_t> out(acc.count);
    for (size_t i = 0; i < acc.count; ++i) {
        const unsigned char* p = &buf.data[begin + i * stride];
        if (size == 1) out[i] = *p;
        else if (size == 2) { uint16_t v; std::memcpy(&v, p, 2); out[i] = v; }
        else if (size == 4) { std::memcpy(&out[i], p, 4); }
        else throw InputError(name, "unsupported index type");
    }
    return out;
}

using Mat4 = std::array<double, 16>;  // column-major, as glTF stores it

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr)
            for (int k = 0; k < 4; ++k) r[c * 4 + rr] += a[k * 4 + rr] * b[c * 4 + k];
    return r;
}

Mat4 nodeMatrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        Mat4 m;
        std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
        return m;
    }
    Mat4 t{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, r = t, s = t;
    if (n.translation.size() == 3) { t[12] = n.translation[0]; t[13] = n.translation[1]; t[14] = n.translation[2]; }
    if (n.scale.size() == 3) { s[0] = n.scale[0]; s[5] = n.scale[1]; s[10] = n.scale[2]; }
    if (n.rotation.size() == 4) {
        double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
        r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
             2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
             2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
             0, 0, 0, 1};
    }
    return multiply(t, multiply(r, s));
}

void appendGltfNode(const tinygltf::Model& model, int nodeIndex, const Mat4& parent,
                    TriangleMesh& mesh, bool& allNormals, const std::string& name, int depth) {
    if (depth > 64) throw InputError(name, "node hierarchy too deep (cycle?)");
    const auto& node = model.nodes.at(size_t(nodeIndex));
    Mat4 m = multiply(parent, nodeMatrix(node));
    if (node.mesh >= 0) {
        for (const auto& prim : model.meshes.at(size_t(node.mesh)).primitives) {
            if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
                throw InputError(name, "only triangle primitives are supported");
            auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end()) throw InputError(name, "primitive without POSITION");
            std::vector<float> p = readAccessor(model, pos->second, 3, name);
            std::vector<float> nrm;
            auto nit = prim.attributes.find("NORMAL");
            if (nit != prim.attributes.end()) nrm = readAccessor(model, nit->second, 3, name);
            allNormals = allNormals && !nrm.empty();
            uint32_t base = uint32_t(mesh.positions_mm.size());
            size_t count = p.size() / 3;
            for (size_t i = 0; i < count; ++i) {
                double x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
                mesh.positions_mm.push_back({float(m[0] * x + m[4] * y + m[8] * z + m[12]),
                                             float(m[1] * x + m[5] * y + m[9] * z + m[13]),
                                             float(m[2] * x + m[6] * y + m[10] * z + m[14])});
                Vec3f n(0, 0, 0);
                if (!nrm.empty()) {
                    // Normals transform by the inverse transpose; for the
                    // rotation+scale matrices of printable models the
                    // cofactor matrix does it up to scale.
                    double a = nrm[3 * i], b = nrm[3 * i + 1], c = nrm[3 * i + 2];
                    Vec3f c0{float(m[0]), float(m[1]), float(m[2])};
                    Vec3f c1{float(m[4]), float(m[5]), float(m[6])};
                    Vec3f c2{float(m[8]), float(m[9]), float(m[10])};
                    Vec3f k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);
                    n = k0 * float(a) + k1 * float(b) + k2 * float(c);
                    float len = length(n);
                    n = len > 0 ? n / len : Vec3f(0, 0, 0);
                }
                mesh.normals.push_back(n);
            }
            std::vector<uint32_t> idx;
            if (prim.indices >= 0) {
                idx = readIndices(model, prim.indices, name);
            } else {
                idx.resize(count);
                for (size_t i = 0; i < count; ++i) idx[i] = uint32_t(i);
            }
            if (idx.size() % 3) throw InputError(name, "index count is not a multiple of 3");
            for (uint32_t i : idx) {
                if (i >= count) throw InputError(name, "vertex index out of range");
                mesh.indices.push_back(base + i);
            }
        }
    }
    for (int child : node.children) appendGltfNode(model, child, m, mesh, allNormals, name, depth + 1);
}

TriangleMesh loadGltf(const std::filesystem::path& file) {
    const std::string name = file.string();
    if (!std::filesystem::exists(file)) throw InputError(name, "cannot open file");
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    bool ok = lowerExtension(file) == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, name)
                                              : loader.LoadASCIIFromFile(&model, &err, &warn, name);
    if (!ok) {
        std::string msg = err.empty() ? "cannot read glTF" : err;
        for (char& c : msg) if (c == '\n') c = ' ';
        while (!msg.empty() && msg.back() == ' ') msg.pop_back();
        throw InputError(name, "malformed glTF: " + msg);
    }
    TriangleMesh mesh;
    bool allNormals = true;
    Mat4 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    try {
        if (!model.scenes.empty()) {
            for (int n : model.scenes.at(size_t(sceneIndex)).nodes)
                appendGltfNode(model, n, identity, mesh, allNormals, name, 0);
        } else {
            for (size_t n = 0; n < model.nodes.size(); ++n)
                appendGltfNode(model, int(n), identity, mesh, allNormals, name, 0);
        }
    } catch (const std::out_of_range&) {
        throw InputError(name, "malformed glTF: index out of range");
    }
    if (!allNormals) mesh.normals.clear();
    return mesh;
}

}  // namespace

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
    if (open) throw InputError(file, "mesh is not closed (" + std::to_string(open) + " boundary edges)");
    if (misoriented)
        throw InputError(file, "mesh is not a consistently oriented 2-manifold (" +
                                   std::to_string(misoriented) + " bad edges)");
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

TriangleMesh loadMesh(const std::filesystem::path& file) {
    std::string ext = lowerExtension(file);
    TriangleMesh mesh;
    if (ext == ".obj") mesh = loadObj(file);
    else if (ext == ".gltf" || ext == ".glb") mesh = loadGltf(file);
    else throw InputError(file.string(), "unknown mesh format (expected .obj, .gltf or .glb)");
    validateClosedMesh(mesh, file.string());
    return mesh;
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
