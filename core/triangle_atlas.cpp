#include "core/triangle_atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/parallel_for.h>

namespace pl {

namespace {

// Texels of margin around each triangle in its rectangle: the filled ring
// (kFilledTexels) rounded up.
constexpr int kGutter = 2;

using Flat = std::array<float, 2>;

// The nearest point of flat triangle (a, b, c) to q, as barycentric
// weights, and its squared distance.
std::array<float, 3> nearestBarycentric(const std::array<Flat, 3>& t, const Flat& q, float& distance2) {
    auto sub = [](const Flat& p, const Flat& r) { return Flat{p[0] - r[0], p[1] - r[1]}; };
    auto dot = [](const Flat& p, const Flat& r) { return p[0] * r[0] + p[1] * r[1]; };
    const Flat e0 = sub(t[1], t[0]), e1 = sub(t[2], t[0]), d = sub(q, t[0]);
    const float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
    const float det = d00 * d11 - d01 * d01;
    if (det > 0) {
        const float d20 = dot(d, e0), d21 = dot(d, e1);
        const float v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
        if (v >= 0 && w >= 0 && v + w <= 1) {
            distance2 = 0;
            return {1 - v - w, v, w};
        }
    }
    // Outside (or degenerate): the nearest point of the three edges.
    std::array<float, 3> best{1, 0, 0};
    distance2 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        const Flat e = sub(t[size_t(k1)], t[size_t(k)]), r = sub(q, t[size_t(k)]);
        const float ee = dot(e, e);
        const float s = ee > 0 ? std::clamp(dot(r, e) / ee, 0.0f, 1.0f) : 0.0f;
        const Flat gap{r[0] - s * e[0], r[1] - s * e[1]};
        const float g2 = dot(gap, gap);
        if (g2 < distance2) {
            distance2 = g2;
            best = {0, 0, 0};
            best[size_t(k)] = 1 - s;
            best[size_t(k1)] = s;
        }
    }
    return best;
}

}  // namespace

TriangleAtlas::TriangleAtlas(const TriangleMesh& mesh, float texel_mm, int mostSide_texels)
    : charts_(mesh.triangleCount()), texel_mm_(texel_mm) {
    // Each triangle flat at true scale, its longest edge along the bottom
    // (so the third corner lies above that edge).
    for (size_t t = 0; t < charts_.size(); ++t) {
        const uint32_t* i = &mesh.indices[3 * t];
        int longest = 0;
        float longest_mm = -1;
        for (int k = 0; k < 3; ++k) {
            const float l = length(mesh.positions_mm[i[(k + 1) % 3]] - mesh.positions_mm[i[k]]);
            if (l > longest_mm) longest_mm = l, longest = k;
        }
        Chart& c = charts_[t];
        c.first = longest;
        const Point3f a = mesh.positions_mm[i[longest]];
        const Vec3f along = mesh.positions_mm[i[(longest + 1) % 3]] - a, third = mesh.positions_mm[i[(longest + 2) % 3]] - a;
        const float s = longest_mm > 0 ? dot(third, along) / longest_mm : 0.0f;
        const float up = std::sqrt(std::max(0.0f, dot(third, third) - s * s));
        c.flat = {Flat{0, 0}, Flat{longest_mm, 0}, Flat{s, up}};
    }
    // Shelves of rectangles, tallest first; the texel grows until the atlas
    // fits mostSide_texels, or, for meshes of so many triangles that their
    // gutters alone do not fit it, until it is about as small as their
    // gutters allow (a side past mostSide_texels).
    double leastArea = 0;
    for (const Chart& c : charts_)
        leastArea += double((c.flat[1][0] > 0 ? 1 : 0) + 2 * kGutter) * double((c.flat[2][1] > 0 ? 1 : 0) + 2 * kGutter);
    const int most = std::max(mostSide_texels, int(std::ceil(std::sqrt(leastArea * 1.3))));
    std::vector<uint32_t> order(charts_.size());
    for (int attempt = 0;; ++attempt) {
        double area = 0;
        int widest = 1;
        for (Chart& c : charts_) {
            c.w = int(std::ceil(c.flat[1][0] / texel_mm_)) + 2 * kGutter;
            c.h = int(std::ceil(c.flat[2][1] / texel_mm_)) + 2 * kGutter;
            area += double(c.w) * c.h;
            widest = std::max(widest, c.w);
        }
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return charts_[a].h > charts_[b].h; });
        width_ = std::max(widest, int(std::ceil(std::sqrt(area * 1.02))));
        int x = 0, y = 0, shelf = 0;
        for (uint32_t t : order) {
            Chart& c = charts_[t];
            if (x + c.w > width_) x = 0, y += shelf, shelf = 0;
            c.x = x, c.y = y;
            x += c.w;
            shelf = std::max(shelf, c.h);
        }
        height_ = std::max(1, y + shelf);
        if (std::max(width_, height_) <= most || attempt == 64) break;
        texel_mm_ *= 1.05f * float(std::max(width_, height_)) / float(most);
    }
    for (Chart& c : charts_) {
        for (Flat& p : c.flat) p = {p[0] / texel_mm_, p[1] / texel_mm_};
        for (int k = 0; k < 3; ++k)
            c.uv[size_t((c.first + k) % 3)] = {(float(c.x + kGutter) + c.flat[size_t(k)][0]) / float(width_),
                               (float(c.y + kGutter) + c.flat[size_t(k)][1]) / float(height_)};
    }
}

std::vector<RGB> TriangleAtlas::bake(const TriangleMesh& mesh,
                                     const std::function<RGB(uint32_t, const Point3f&)>& colorAt) const {
    std::vector<RGB> image(size_t(width_) * size_t(height_), RGB{0, 0, 0});
    const float filled2_texels2 = kFilledTexels * kFilledTexels;
    // Rectangles do not overlap: each texel is written once.
    tbb::parallel_for(size_t(0), charts_.size(), [&](size_t t) {
        const Chart& c = charts_[t];
        const uint32_t* i = &mesh.indices[3 * t];
        const Point3f p[3] = {mesh.positions_mm[i[c.first]], mesh.positions_mm[i[(c.first + 1) % 3]],
                              mesh.positions_mm[i[(c.first + 2) % 3]]};
        for (int j = 0; j < c.h; ++j)
            for (int i = 0; i < c.w; ++i) {
                const Flat q{float(i) + 0.5f - float(kGutter), float(j) + 0.5f - float(kGutter)};
                float distance2;
                const std::array<float, 3> b = nearestBarycentric(c.flat, q, distance2);
                if (distance2 > filled2_texels2) continue;
                const Point3f x = p[0] * b[0] + p[1] * b[1] + p[2] * b[2];
                image[size_t(c.y + j) * size_t(width_) + size_t(c.x + i)] = colorAt(uint32_t(t), x);
            }
    });
    return image;
}

}  // namespace pl
