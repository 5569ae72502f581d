#include "io/mesh_formats.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "core/nearest_surface_voxel.h"
#include "core/triangle_atlas.h"
#include "io/base64.h"
#include "io/file_names.h"
#include "io/image_io.h"
#include "core/input_error.h"
#include "io/output_file.h"

namespace pl {

namespace {

// glTF 1.0: a binary container of version 1, or JSON whose asset version
// is 1.x or whose top-level collections are dictionaries (glTF 2.0 has
// arrays). tinygltf reads 2.0 only and would give a parser's message.
bool isGltf1(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    char head[8] = {};
    in.read(head, sizeof head);
    if (std::memcmp(head, "glTF", 4) == 0) {
        uint32_t version = 0;
        std::memcpy(&version, head + 4, 4);
        return version == 1;
    }
    in.seekg(0);
    const nlohmann::json json = nlohmann::json::parse(in, nullptr, false);
    if (!json.is_object()) return false;
    if (json.contains("asset") && json["asset"].is_object() && json["asset"].contains("version") &&
        json["asset"]["version"].is_string() && json["asset"]["version"].get<std::string>().rfind("1", 0) == 0)
        return true;
    for (const char* collection : {"meshes", "accessors", "nodes"})
        if (json.contains(collection) && json[collection].is_object()) return true;
    return false;
}

// Reads an accessor as floats, `components` per element; integer types are
// normalised to [0, 1] (glTF's normalized colours and texture coordinates).
std::vector<float> readAccessor(const tinygltf::Model& model, int index, int components,
                                const std::string& name) {
    if (index < 0 || index >= int(model.accessors.size())) throw InputError(name, "bad accessor index");
    const auto& acc = model.accessors[size_t(index)];
    int have = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    if (have < components) throw InputError(name, "vertex attribute has too few components");
    int size = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    if (size <= 0) throw InputError(name, "unsupported vertex attribute type");
    const auto& view = model.bufferViews.at(size_t(acc.bufferView));
    const auto& buf = model.buffers.at(size_t(view.buffer));
    size_t stride = size_t(acc.ByteStride(view));
    size_t begin = view.byteOffset + acc.byteOffset;
    if (stride == 0 || begin + stride * (acc.count ? acc.count - 1 : 0) + size_t(have * size) > buf.data.size())
        throw InputError(name, "accessor runs past its buffer");
    std::vector<float> out(acc.count * size_t(components));
    for (size_t i = 0; i < acc.count; ++i)
        for (int c = 0; c < components; ++c) {
            const unsigned char* p = &buf.data[begin + i * stride + size_t(c * size)];
            float v;
            switch (acc.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p, 4); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p / 255.0f; break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); v = u / 65535.0f; break; }
                default: throw InputError(name, "unsupported vertex attribute type");
            }
            out[i * components + size_t(c)] = v;
        }
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

struct GltfState {
    MeshAsset asset;
    bool allNormals = true, anyUvs = false, anyColors = false;
};

void appendGltfNode(const tinygltf::Model& model, int nodeIndex, const Mat4& parent,
                    GltfState& st, const std::string& name, int depth) {
    TriangleMesh& mesh = st.asset.mesh;
    SurfaceAppearance& look = st.asset.appearance;
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
            for (float x : p)
                if (!std::isfinite(x)) throw InputError(name, "non-finite vertex position");
            std::vector<float> nrm;
            auto nit = prim.attributes.find("NORMAL");
            if (nit != prim.attributes.end()) nrm = readAccessor(model, nit->second, 3, name);
            st.allNormals = st.allNormals && !nrm.empty();
            std::vector<float> uv, col;
            auto uit = prim.attributes.find("TEXCOORD_0");
            if (uit != prim.attributes.end()) uv = readAccessor(model, uit->second, 2, name);
            auto cit = prim.attributes.find("COLOR_0");
            if (cit != prim.attributes.end()) col = readAccessor(model, cit->second, 3, name);
            st.anyUvs = st.anyUvs || !uv.empty();
            st.anyColors = st.anyColors || !col.empty();
            uint32_t base = uint32_t(mesh.positions_mm.size());
            size_t count = p.size() / 3;
            if ((!uv.empty() && uv.size() / 2 != count) || (!col.empty() && col.size() / 3 != count) ||
                (!nrm.empty() && nrm.size() / 3 != count))
                throw InputError(name, "vertex attributes of different lengths");
            for (size_t i = 0; i < count; ++i) {
                look.uvs.push_back(uv.empty() ? std::array<float, 2>{0, 0} : std::array<float, 2>{uv[2 * i], uv[2 * i + 1]});
                look.vertexColors.push_back(col.empty() ? RGB{1, 1, 1} : RGB{col[3 * i], col[3 * i + 1], col[3 * i + 2]});
            }
            // glTF materials map one to one onto ours (loaded in loadGltf).
            uint32_t material = prim.material >= 0 ? uint32_t(prim.material) : uint32_t(model.materials.size());
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
            look.triangleMaterial.insert(look.triangleMaterial.end(), idx.size() / 3, material);
        }
    }
    for (int child : node.children) appendGltfNode(model, child, m, st, name, depth + 1);
}

// An 8- or 16-bit sRGB image decoded by tinygltf, as linear RGB.
Texture textureFromGltfImage(const tinygltf::Image& im, const std::string& name) {
    if (im.width <= 0 || im.height <= 0 || im.component < 1 || (im.bits != 8 && im.bits != 16) ||
        im.image.size() < size_t(im.width) * im.height * im.component * (im.bits / 8))
        throw InputError(name, "texture image '" + im.uri + "' could not be decoded");
    std::vector<float> values(size_t(im.width) * im.height * size_t(im.component));
    for (size_t at = 0; at < values.size(); ++at)
        values[at] = im.bits == 8 ? im.image[at] / 255.0f : (im.image[2 * at] | (im.image[2 * at + 1] << 8)) / 65535.0f;
    return Texture::fromInterleaved(im.width, im.height, im.component, values, true);
}

}  // namespace

MeshAsset loadGltf(const std::filesystem::path& file) {
    const std::string name = file.string();
    if (!std::filesystem::exists(file)) throw InputError(name, "cannot open file");
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    bool ok = lowerExtension(file) == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, name)
                                              : loader.LoadASCIIFromFile(&model, &err, &warn, name);
    // Only a file tinygltf refused or that does not say 2.x is read again
    // to see whether it is glTF 1.0 (a 2.0 model is parsed once).
    if ((!ok || model.asset.version.rfind("2", 0) != 0) && isGltf1(file))
        throw InputError(name, "glTF 1.0 is not supported (only glTF 2.0; convert it, e.g. with Blender)");
    if (!ok) {
        std::string msg = err.empty() ? "cannot read glTF" : err;
        for (char& c : msg) if (c == '\n') c = ' ';
        while (!msg.empty() && msg.back() == ' ') msg.pop_back();
        throw InputError(name, "malformed glTF: " + msg);
    }
    GltfState st;
    Mat4 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    try {
        if (!model.scenes.empty()) {
            for (int n : model.scenes.at(size_t(sceneIndex)).nodes)
                appendGltfNode(model, n, identity, st, name, 0);
        } else {
            for (size_t n = 0; n < model.nodes.size(); ++n)
                appendGltfNode(model, int(n), identity, st, name, 0);
        }
        // Base colours: factor (linear) and texture (sRGB) per material, plus
        // one default white material for primitives without one.
        SurfaceAppearance& look = st.asset.appearance;
        std::map<int, int> textureOfImage;
        for (const auto& m : model.materials) {
            SurfaceMaterial sm;
            const auto& pbr = m.pbrMetallicRoughness;
            for (int c = 0; c < 3 && c < int(pbr.baseColorFactor.size()); ++c) sm.baseColorFactor[c] = float(pbr.baseColorFactor[size_t(c)]);
            if (pbr.baseColorTexture.index >= 0) {
                int image = model.textures.at(size_t(pbr.baseColorTexture.index)).source;
                if (!textureOfImage.count(image)) {
                    look.textures.push_back(textureFromGltfImage(model.images.at(size_t(image)), name));
                    textureOfImage[image] = int(look.textures.size()) - 1;
                }
                sm.texture = textureOfImage[image];
            }
            look.materials.push_back(sm);
        }
        look.materials.push_back({});
    } catch (const std::out_of_range&) {
        throw InputError(name, "malformed glTF: index out of range");
    }
    TriangleMesh& mesh = st.asset.mesh;
    SurfaceAppearance& look = st.asset.appearance;
    if (!st.allNormals) mesh.normals.clear();
    if (!st.anyUvs) look.uvs.clear();
    if (!st.anyColors) look.vertexColors.clear();
    if (model.materials.empty()) {
        look.materials.clear();
        look.triangleMaterial.clear();
    }
    return std::move(st.asset);
}


namespace {
template <class T>
void appendBytes(std::vector<unsigned char>& buf, const T* data, size_t count) {
    const auto* p = reinterpret_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + count * sizeof(T));
    while (buf.size() % 4) buf.push_back(0);
}
}  // namespace

namespace {

// glTF's unit is the metre; printlight's the millimetre.
Point3f metresOf(const Point3f& p_mm) {
    return Point3f(float(double(p_mm.x) / 1000.0), float(double(p_mm.y) / 1000.0), float(double(p_mm.z) / 1000.0));
}

// The document of one mesh of one primitive, in one node of one scene.
nlohmann::json oneMeshDocument(nlohmann::json bufferViews, nlohmann::json accessors, nlohmann::json primitive) {
    return {{"asset", {{"version", "2.0"}, {"generator", "printlight"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"bufferViews", std::move(bufferViews)},
            {"accessors", std::move(accessors)},
            {"meshes", {{{"primitives", {std::move(primitive)}}}}}};
}

// A glTF document of one mesh (positions in metres, as glTF says, from
// millimetres; UVs and linear vertex colours, as floats, where the
// appearance has them; no index buffer where the mesh has no indices) and
// its binary buffer.
struct GltfDocument {
    nlohmann::json gltf;
    std::vector<unsigned char> buffer;
};

GltfDocument meshDocument(const TriangleMesh& mesh, const SurfaceAppearance& look) {
    using nlohmann::json;
    GltfDocument doc;
    std::vector<unsigned char>& buf = doc.buffer;
    json views = json::array(), accessors = json::array(), attributes = json::object();
    auto addView = [&](const void* data, size_t bytes, size_t count, int componentType, const char* type,
                       int target) {
        size_t offset = buf.size();
        appendBytes(buf, static_cast<const unsigned char*>(data), bytes);
        views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
        accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", componentType}, {"count", count}, {"type", type}});
        return int(accessors.size()) - 1;
    };
    size_t n = mesh.positions_mm.size();
    std::vector<Point3f> positions_m;
    positions_m.reserve(n);
    Bounds3f b;
    for (const Point3f& p : mesh.positions_mm) {
        positions_m.push_back(metresOf(p));
        b.expand(positions_m.back());
    }
    attributes["POSITION"] = addView(positions_m.data(), n * 12, n, 5126, "VEC3", 34962);
    accessors.back()["min"] = {b.lo.x, b.lo.y, b.lo.z};
    accessors.back()["max"] = {b.hi.x, b.hi.y, b.hi.z};
    if (!look.uvs.empty()) attributes["TEXCOORD_0"] = addView(look.uvs.data(), n * 8, n, 5126, "VEC2", 34962);
    if (!look.vertexColors.empty())
        attributes["COLOR_0"] = addView(look.vertexColors.data(), n * 12, n, 5126, "VEC3", 34962);
    json primitive = {{"attributes", attributes}, {"mode", 4}};
    if (!mesh.indices.empty())
        primitive["indices"] = addView(mesh.indices.data(), mesh.indices.size() * 4, mesh.indices.size(), 5125, "SCALAR", 34963);
    doc.gltf = oneMeshDocument(views, accessors, primitive);
    return doc;
}

}  // namespace

void writeGltf(const TriangleMesh& mesh, const SurfaceAppearance& look, const std::string& textureUri,
               const std::filesystem::path& file) {
    using nlohmann::json;
    GltfDocument doc = meshDocument(mesh, look);
    json& gltf = doc.gltf;
    gltf["buffers"] = {{{"byteLength", doc.buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(doc.buffer.data(), doc.buffer.size())}}};
    json& primitive = gltf["meshes"][0]["primitives"][0];
    if (!textureUri.empty() || !look.materials.empty()) {
        RGB f = look.materials.empty() ? RGB{1, 1, 1} : look.materials[0].baseColorFactor;
        json pbr = {{"baseColorFactor", {f[0], f[1], f[2], 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}};
        if (!textureUri.empty()) {
            pbr["baseColorTexture"] = {{"index", 0}};
            gltf["images"] = {{{"uri", textureUri}}};
            gltf["textures"] = {{{"source", 0}}};
        }
        gltf["materials"] = {{{"pbrMetallicRoughness", pbr}}};
        primitive["material"] = 0;
    }
    writeTextFile(file, gltf.dump(1) + "\n");
}

void writePredictionGlb(const TriangleMesh& mesh_mm, const GridFrame& frame, const std::vector<Vec3i>& voxels,
                        const std::vector<RGB>& linearColor, const std::filesystem::path& file) {
    using nlohmann::json;
    // Texels of the voxel's middle side: the colours change from voxel to
    // voxel, and the eye's footprint spans several.
    if (linearColor.size() != voxels.size())
        throw std::invalid_argument("writePredictionGlb: one colour per surface voxel is needed");
    std::array<float, 3> sides_mm{frame.voxelSize_mm.x, frame.voxelSize_mm.y, frame.voxelSize_mm.z};
    std::sort(sides_mm.begin(), sides_mm.end());
    const TriangleAtlas atlas(mesh_mm, sides_mm[1]);
    // WebGL 2's largest textures; a mesh of more triangles than their
    // gutters fit in it (some 10 million) has no atlas.
    constexpr int kMostTextureSide_texels = 16384;
    if (std::max(atlas.width(), atlas.height()) > kMostTextureSide_texels)
        throw GlbTooLarge("the prediction on the model: " + std::to_string(mesh_mm.triangleCount()) +
                          " triangles need a texture of " + std::to_string(atlas.width()) + " x " +
                          std::to_string(atlas.height()) + " texels: " + file.string() +
                          " is not written (the .exr and .vdb hold the prediction)");
    const NearestSurfaceVoxel nearest(frame, voxels);
    Texture texture;
    texture.width = atlas.width();
    texture.height = atlas.height();
    texture.linear = atlas.bake(mesh_mm, [&](uint32_t, const Point3f& x_mm) {
        const std::optional<uint32_t> pixel = nearest.at(x_mm);
        return pixel ? linearColor[*pixel] : RGB{0, 0, 0};
    });
    const std::vector<unsigned char> png = texturePngBytes(texture);
    texture = Texture();
    // Three vertices of its own per triangle: each is in its own chart.
    TriangleMesh flat;
    SurfaceAppearance look;
    const size_t triangles = mesh_mm.triangleCount();
    flat.positions_mm.reserve(3 * triangles);
    look.uvs.reserve(3 * triangles);
    for (size_t t = 0; t < triangles; ++t) {
        const auto& uv = atlas.uv(t);
        for (int k = 0; k < 3; ++k) {
            flat.positions_mm.push_back(mesh_mm.positions_mm[mesh_mm.indices[3 * t + size_t(k)]]);
            look.uvs.push_back(uv[size_t(k)]);
        }
    }
    GltfDocument doc = meshDocument(flat, look);
    const uint64_t meshBytes = doc.buffer.size(), allBytes = meshBytes + png.size();
    constexpr uint64_t kMostGlbBytes = 0xFFFFFFFFull - (1u << 20);  // less room for the JSON
    if (allBytes > kMostGlbBytes)
        throw GlbTooLarge("the prediction on the model (" + std::to_string(triangles) + " triangles, " +
                          std::to_string(allBytes >> 30) + " GiB) exceeds a .glb's 4 GiB: " + file.string() +
                          " is not written (the .exr and .vdb hold the prediction)");
    json& gltf = doc.gltf;
    gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", meshBytes}, {"byteLength", png.size()}});
    gltf["images"] = {{{"bufferView", gltf["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
    // Linear, no mipmaps: the charts' neighbours in the atlas must not bleed in.
    gltf["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}}};
    gltf["textures"] = {{{"source", 0}, {"sampler", 0}}};
    // Unlit: the colours are the radiance leaving the surface already; a
    // viewer's own lights must not shade them again.
    gltf["extensionsUsed"] = {"KHR_materials_unlit"};
    gltf["materials"] = {{{"pbrMetallicRoughness",
                           {{"baseColorFactor", {1, 1, 1, 1}}, {"baseColorTexture", {{"index", 0}}},
                            {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
                          {"extensions", {{"KHR_materials_unlit", json::object()}}}}};
    gltf["meshes"][0]["primitives"][0]["material"] = 0;
    gltf["buffers"] = {{{"byteLength", allBytes}}};
    // The binary container: header, JSON chunk (space-padded), BIN chunk
    // (zero-padded to 4 bytes).
    std::string text = gltf.dump();
    while (text.size() % 4) text.push_back(' ');
    const uint64_t binBytes = (allBytes + 3) / 4 * 4;
    auto u32 = [](std::string& out, uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    std::string head;
    u32(head, 0x46546C67);  // "glTF"
    u32(head, 2);
    u32(head, uint32_t(12 + 8 + text.size() + 8 + binBytes));
    u32(head, uint32_t(text.size()));
    u32(head, 0x4E4F534A);  // "JSON"
    head += text;
    u32(head, uint32_t(binBytes));
    u32(head, 0x004E4942);  // "BIN"
    OutputFile out(file);
    {
        std::ofstream f(out.tempPath(), std::ios::binary);
        f.write(head.data(), std::streamsize(head.size()));
        f.write(reinterpret_cast<const char*>(doc.buffer.data()), std::streamsize(meshBytes));
        f.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
        const char zeros[4] = {0, 0, 0, 0};
        f.write(zeros, std::streamsize(binBytes - allBytes));
        if (!f) throw std::runtime_error("cannot write " + file.string());
    }
    out.commit();
}

}  // namespace pl
