// The colour a textured model asks for on its surface: per-triangle
// materials with a base-colour factor, an optional base-colour texture
// (sampled bilinearly, repeat wrap, already decoded to linear RGB) and
// optional per-vertex colours, as glTF 2.0 defines base colour.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/geometry.h"
#include "core/rgb.h"

namespace pl {

struct Texture {
    int width = 0, height = 0;
    std::vector<RGB> linear;  // row-major, top row first
    // Bilinear lookup; (u, v) as in glTF: v = 0 is the top row; repeat wrap.
    RGB sample(float u, float v) const;
    // From interleaved values in [0, 1] with `channels` per texel (grey
    // repeats its channel, alpha is ignored); sRGB-decoded if srgbEncoded.
    static Texture fromInterleaved(int width, int height, int channels, const std::vector<float>& values,
                                   bool srgbEncoded);
};

struct SurfaceMaterial {
    RGB baseColorFactor{1, 1, 1};  // linear
    int texture = -1;              // index into SurfaceAppearance::textures
};

struct SurfaceAppearance {
    std::vector<std::array<float, 2>> uvs;  // per mesh vertex, or empty
    std::vector<RGB> vertexColors;           // per mesh vertex (linear), or empty
    std::vector<uint32_t> triangleMaterial;  // per triangle, or empty (material 0)
    std::vector<SurfaceMaterial> materials;  // empty: white
    std::vector<Texture> textures;

    bool hasColor() const;
    // Base colour (linear RGB) at point p on triangle prim.
    RGB colorAt(const TriangleMesh& mesh, uint32_t prim, const Point3f& p) const;
};

// sRGB transfer function, decode (per channel, [0, 1]).
float srgbToLinear(float v);

}  // namespace pl
