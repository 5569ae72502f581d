#include "prepare/voxelizer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pl {

namespace {
constexpr int kBrick = 8;
}

GridFrame Voxelizer::frameFor(const Bounds3f& meshBounds, const VoxelizeSettings& settings) {
    // The mesh's bounds plus the margin, in whole voxels.
    GridFrame f;
    for (int a = 0; a < 3; ++a) {
        float lo = meshBounds.lo[a] - settings.margin_mm, hi = meshBounds.hi[a] + settings.margin_mm;
        f.voxelSize_mm[a] = settings.voxel_mm[a];
        double n = std::ceil(double(hi - lo) / settings.voxel_mm[a]);
        f.resolution[a] = int(std::min(std::max(n, 1.0), double(1 << 30)));  // absurd sizes stay representable
        f.cornerMin_mm[a] = lo;
    }
    return f;
}

Voxelizer::Voxelizer(const Geometry& geometry, const VoxelizeSettings& settings)
    : geometry_(geometry), settings_(settings), frame_(frameFor(geometry.bounds(), settings)) {
    const Vec3i& r = frame_.resolution;

    // Inside intervals from x scanlines through the voxel centres.
    inside_.resize(size_t(r.y) * r.z);
    float x0_mm = frame_.cornerMin_mm.x - 1.0f;
    float length_mm = r.x * frame_.voxelSize_mm.x + 2.0f;
    tbb::parallel_for(0, r.z, [&](int z) {
        for (int y = 0; y < r.y; ++y) {
            Point3f c = frame_.voxelCenter_mm({0, y, z});
            Ray ray{{x0_mm, c.y, c.z}, {1, 0, 0}};
            // Crossings with their orientation: +1 entering, -1 leaving.
            std::vector<std::pair<float, int>> crossings;
            // All crossings along the column: restart just past each hit
            // (the step is relative: t is in mm from outside the frame).
            float tMin = 0;
            while (auto hit = geometry.intersect(ray, length_mm, tMin)) {
                float tHit = hit->t;
                int sign = hit->ng.x < 0 ? 1 : -1;
                // A crossing reported again on a shared edge: same sign, same place.
                if (crossings.empty() || crossings.back().second != sign || tHit - crossings.back().first > 1e-4f)
                    crossings.push_back({tHit, sign});
                tMin = tHit + std::max(1e-5f, 4e-7f * tHit);
            }
            auto& intervals = inside_[size_t(z) * r.y + y];
            int winding = 0;
            float enter = 0;
            for (const auto& [tc, s] : crossings) {
                int before = winding;
                winding += s;
                float x_mm = x0_mm + tc;
                if (before <= 0 && winding > 0) enter = x_mm;
                if (before > 0 && winding <= 0) {
                    // Voxels whose centre lies in [enter, x_mm).
                    auto first = int32_t(std::ceil((enter - frame_.cornerMin_mm.x) / frame_.voxelSize_mm.x - 0.5f));
                    auto last = int32_t(std::ceil((x_mm - frame_.cornerMin_mm.x) / frame_.voxelSize_mm.x - 0.5f));
                    first = std::max(first, 0);
                    last = std::min(last, r.x);
                    if (first < last) intervals.push_back({first, last});
                }
            }
        }
    });

    // Bricks whose centre is within band + half diagonal of the surface.
    const Vec3f& s = frame_.voxelSize_mm;
    brickRes_ = {(r.x + kBrick - 1) / kBrick, (r.y + kBrick - 1) / kBrick, (r.z + kBrick - 1) / kBrick};
    brickNear_.assign(size_t(brickRes_.x) * brickRes_.y * brickRes_.z, 0);
    float halfDiagonal = 0.5f * kBrick * std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
    tbb::parallel_for(0, brickRes_.z, [&](int bz) {
        for (int by = 0; by < brickRes_.y; ++by)
            for (int bx = 0; bx < brickRes_.x; ++bx) {
                Point3f c{frame_.cornerMin_mm.x + (bx + 0.5f) * kBrick * s.x,
                          frame_.cornerMin_mm.y + (by + 0.5f) * kBrick * s.y,
                          frame_.cornerMin_mm.z + (bz + 0.5f) * kBrick * s.z};
                if (geometry.closestPoint(c, settings.band_mm + halfDiagonal))
                    brickNear_[(size_t(bz) * brickRes_.y + by) * brickRes_.x + bx] = 1;
            }
    });
    nearBrickCount_ = size_t(std::count(brickNear_.begin(), brickNear_.end(), uint8_t(1)));
}

bool Voxelizer::brickNear(int bx, int by, int bz) const {
    return brickNear_[(size_t(bz) * brickRes_.y + by) * brickRes_.x + bx] != 0;
}

std::vector<VoxelRow> Voxelizer::slice(int z) const {
    const Vec3i& r = frame_.resolution;
    const Vec3f& s = frame_.voxelSize_mm;
    std::vector<VoxelRow> rows(size_t(r.y));
    tbb::parallel_for(0, r.y, [&](int y) {
        auto& out = rows[size_t(y)].samples;
        const auto& intervals = inside_[size_t(z) * r.y + y];
        size_t k = 0;
        for (int x = 0; x < r.x; ++x) {
            while (k < intervals.size() && intervals[k].second <= x) ++k;
            bool inside = k < intervals.size() && intervals[k].first <= x;
            VoxelSample v{x, inside, inside, false, 0, {0, 0, 0}, {0, 0, 0}, 0};
            if (brickNear(x / kBrick, y / kBrick, z / kBrick)) {
                Point3f c = frame_.voxelCenter_mm({x, y, z});
                if (auto cp = geometry_.closestPoint(c, settings_.band_mm)) {
                    float d = cp->distance_mm;
                    v.inBand = true;
                    v.sdf_mm = inside ? -d : d;
                    // The distance gradient points from the surface to an
                    // outside point and from an inside point to the surface.
                    v.normal = d > 1e-6f ? (inside ? (cp->p - c) : (c - cp->p)) / d : cp->ng;
                    v.surfacePoint_mm = cp->p;
                    v.prim = cp->prim;
                    if (!inside) {
                        // Centre outside: the voxel overlaps the interior iff
                        // the surface passes through its box.
                        Vec3f half = s * 0.5f;
                        v.member = d <= length(half) && geometry_.surfaceCrossesBox(c - half, c + half);
                    }
                }
            }
            if (v.member || v.inBand) out.push_back(v);
        }
    });
    return rows;
}

}  // namespace pl
