#include "io/mesh_formats.h"

#include <array>
#include <cmath>
#include <map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "io/file_names.h"
#include "core/input_error.h"

namespace pl {

namespace {

std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

RGB decodedSrgb(const aiColor4D& c) { return RGB{srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b)}; }

}  // namespace

MeshAsset loadWithAssimp(const std::filesystem::path& file) {
    const std::string name = file.string();
    if (!std::filesystem::is_regular_file(file)) throw InputError(name, "cannot open file");
    const std::string ext = lowerExtension(file);
    Assimp::Importer importer;
    // Points and lines bound nothing: dropped. Node transforms are applied.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* scene = importer.ReadFile(
        name, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_PreTransformVertices | aiProcess_FindInvalidData);
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
        throw InputError(name, "cannot read the model: " + oneLine(importer.GetErrorString()));

    // STL repeats each vertex in every facet (with the facet's normal):
    // vertices are welded where their positions are equal, so that the
    // surface's edges are shared and its closure can be checked.
    MeshAsset asset;
    TriangleMesh& mesh = asset.mesh;
    SurfaceAppearance& look = asset.appearance;
    std::map<std::array<float, 3>, uint32_t> welded;
    std::vector<RGB> colors;
    bool anyVertexColor = false;
    // 3MF gives colours as materials; STL and PLY materials are the
    // importer's default grey, not the model's.
    const bool materialColours = ext == ".3mf";
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* in = scene->mMeshes[m];
        if (!(in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        std::vector<uint32_t> index(in->mNumVertices);
        for (unsigned v = 0; v < in->mNumVertices; ++v) {
            const aiVector3D& p = in->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw InputError(name, "non-finite vertex position");
            auto [it, added] = welded.emplace(std::array<float, 3>{p.x, p.y, p.z}, uint32_t(mesh.positions_mm.size()));
            if (added) {
                mesh.positions_mm.emplace_back(p.x, p.y, p.z);
                const bool hasColor = in->HasVertexColors(0);
                colors.push_back(hasColor ? decodedSrgb(in->mColors[0][v]) : RGB{1, 1, 1});
                anyVertexColor |= hasColor;
            }
            index[v] = it->second;
        }
        uint32_t material = 0;
        if (materialColours) {
            aiColor4D diffuse(1, 1, 1, 1);
            scene->mMaterials[in->mMaterialIndex]->Get(AI_MATKEY_COLOR_DIFFUSE, diffuse);
            material = uint32_t(look.materials.size());
            look.materials.push_back({decodedSrgb(diffuse), -1});
        }
        for (unsigned f = 0; f < in->mNumFaces; ++f) {
            const aiFace& face = in->mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (int k = 0; k < 3; ++k) mesh.indices.push_back(index[face.mIndices[k]]);
            look.triangleMaterial.push_back(material);
        }
    }
    if (mesh.indices.empty()) throw InputError(name, "the model has no triangles");
    if (anyVertexColor) look.vertexColors = std::move(colors);
    if (look.materials.empty()) look.triangleMaterial.clear();
    return asset;
}

}  // namespace pl
