// A texture atlas for a triangle mesh: each triangle laid flat in its own
// rectangle of texels (its longest edge along the bottom, at true scale),
// the rectangles packed in shelves. Enough to bake a colour that varies
// over the surface into one image with texture coordinates any glTF viewer
// samples, without a parametrisation of the whole surface.
//
// Texels whose centres lie within kFilledTexels of a triangle are filled
// (with the colour at the nearest point of the triangle): bilinear lookups
// inside the triangle never read an unfilled texel. Viewers must sample
// without mipmaps (the rectangles' neighbours would bleed in).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/geometry.h"
#include "core/rgb.h"

namespace pl {

class TriangleAtlas {
public:
    // texel_mm: the texel's side on the surface; grown (and said by
    // texel_mm()) where the atlas would pass mostSide_texels a side.
    TriangleAtlas(const TriangleMesh& mesh, float texel_mm, int mostSide_texels = kMostSide_texels);

    // A texture side every WebGL device takes, and more texels than a
    // screen shows of a whole object: past it a finer atlas only slows
    // the page (the .vdb and .exr keep every voxel).
    static constexpr int kMostSide_texels = 4096;
    static constexpr float kFilledTexels = 1.5f;

    int width() const { return width_; }
    int height() const { return height_; }
    float texel_mm() const { return texel_mm_; }
    // Texture coordinates of triangle t's corners, in the mesh's order
    // (glTF's: v = 0 at the top row).
    const std::array<std::array<float, 2>, 3>& uv(size_t triangle) const { return charts_[triangle].uv; }

    // The image (row-major, top row first): colorAt(triangle, point on it)
    // for each filled texel, black elsewhere; mesh: the atlas's own.
    // Triangles in parallel; the same bits whatever the threads.
    std::vector<RGB> bake(const TriangleMesh& mesh, const std::function<RGB(uint32_t, const Point3f&)>& colorAt) const;

private:
    struct Chart {
        // The triangle flat (millimetres while the layout is made, texels
        // after): corners 0, 1 on the bottom edge.
        std::array<std::array<float, 2>, 3> flat;
        int x = 0, y = 0, w = 0, h = 0;  // the rectangle in the atlas
        std::array<std::array<float, 2>, 3> uv;  // the mesh's corner order
        int first = 0;  // the mesh's corner laid as flat corner 0 (the rest follow in order)
    };
    std::vector<Chart> charts_;
    int width_ = 0, height_ = 0;
    float texel_mm_;
};

}  // namespace pl
