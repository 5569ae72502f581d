#include "prepare/surface_appearance.h"

#include <cmath>

namespace pl {

float srgbToLinear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

Texture Texture::fromInterleaved(int width, int height, int channels, const std::vector<float>& values,
                                 bool srgbEncoded) {
    Texture t;
    t.width = width;
    t.height = height;
    t.linear.resize(size_t(width) * height);
    for (size_t i = 0; i < t.linear.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            float v = values[i * size_t(channels) + size_t(std::min(c, channels - 1))];
            t.linear[i][c] = srgbEncoded ? srgbToLinear(v) : v;
        }
    return t;
}

RGB Texture::sample(float u, float v) const {
    if (width <= 0 || height <= 0) return {1, 1, 1};
    // Texel centres at (i + 0.5) / width.
    float x = (u - std::floor(u)) * width - 0.5f, y = (v - std::floor(v)) * height - 0.5f;
    int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    float fx = x - x0, fy = y - y0;
    auto texel = [&](int i, int j) -> const RGB& {
        i = ((i % width) + width) % width;
        j = ((j % height) + height) % height;
        return linear[size_t(j) * width + i];
    };
    RGB out;
    for (int c = 0; c < 3; ++c)
        out[c] = (1 - fy) * ((1 - fx) * texel(x0, y0)[c] + fx * texel(x0 + 1, y0)[c]) +
                 fy * ((1 - fx) * texel(x0, y0 + 1)[c] + fx * texel(x0 + 1, y0 + 1)[c]);
    return out;
}

bool SurfaceAppearance::hasColor() const { return !materials.empty() || !vertexColors.empty(); }

RGB SurfaceAppearance::colorAt(const TriangleMesh& mesh, uint32_t prim, const Point3f& p) const {
    const uint32_t* idx = &mesh.indices[3 * size_t(prim)];
    const Point3f& a = mesh.positions_mm[idx[0]];
    const Point3f& b = mesh.positions_mm[idx[1]];
    const Point3f& c = mesh.positions_mm[idx[2]];
    // Barycentric coordinates of p (on or next to the triangle).
    Vec3f v0 = b - a, v1 = c - a, v2 = p - a;
    float d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0), d21 = dot(v2, v1);
    float denom = d00 * d11 - d01 * d01;
    float w1 = denom != 0 ? (d11 * d20 - d01 * d21) / denom : 0.0f;
    float w2 = denom != 0 ? (d00 * d21 - d01 * d20) / denom : 0.0f;
    float w0 = 1 - w1 - w2;

    RGB color{1, 1, 1};
    if (!materials.empty()) {
        const SurfaceMaterial& m = materials[triangleMaterial.empty() ? 0 : triangleMaterial[prim]];
        color = m.baseColorFactor;
        if (m.texture >= 0 && !uvs.empty()) {
            float u = w0 * uvs[idx[0]][0] + w1 * uvs[idx[1]][0] + w2 * uvs[idx[2]][0];
            float v = w0 * uvs[idx[0]][1] + w1 * uvs[idx[1]][1] + w2 * uvs[idx[2]][1];
            RGB t = textures[size_t(m.texture)].sample(u, v);
            for (int k = 0; k < 3; ++k) color[k] *= t[k];
        }
    }
    if (!vertexColors.empty())
        for (int k = 0; k < 3; ++k)
            color[k] *= w0 * vertexColors[idx[0]][k] + w1 * vertexColors[idx[1]][k] + w2 * vertexColors[idx[2]][k];
    for (float& x : color) x = std::clamp(x, 0.0f, 1.0f);
    return color;
}

}  // namespace pl
