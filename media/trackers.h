// Trackers over the piecewise-constant label medium, in cell space (see
// label_grid.h) with the ray parameter t in millimetres.
//  - deltaTrack: delta (Woodcock) tracking against the per-brick majorant;
//    samples a free-flight distance with pdf sigma_t(t) T(t).
//  - regularTrack: exact transmittance by 3D-DDA through the voxels
//    (Amanatides-Woo), skipping void bricks and stepping whole uniform bricks.
// Both take the label lookup as a template parameter so the hot loop inlines
// the OpenVDB accessor (label_medium.cpp) or a dense array (tests).
#pragma once

#include <cmath>

#include "core/rng.h"
#include "media/dda.h"
#include "media/majorant_grid.h"
#include "media/materials.h"

namespace pl {

// A ray in cell space: cell(t) = o + d t, t in millimetres along the world ray.
struct CellRay {
    Vec3f o, d;
    Vec3i voxelAt(float t) const {
        return {int(std::floor(o.x + d.x * t)), int(std::floor(o.y + d.y * t)),
                int(std::floor(o.z + d.z * t))};
    }
};

struct FreeFlight {
    bool scattered = false;  // a real collision before tMax
    float t_mm = 0;
    Label label = 0;         // material at the collision
};

// Beyond this optical depth the transmittance is below float precision.
constexpr float kOpaqueOpticalDepth = 100.0f;

inline Vec3i clampToBox(Vec3i v, const Vec3i& lo, const Vec3i& hiExcl) {
    for (int a = 0; a < 3; ++a) v[a] = std::min(std::max(v[a], lo[a]), hiExcl[a] - 1);
    return v;
}

template <class LabelLookup>
FreeFlight deltaTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame,
                      const MajorantGrid& maj, const ChannelLut& lut, int channel,
                      LabelLookup&& labelAt, Rng& rng) {
    const Vec3i fmax = frame.indexMax();
    constexpr int kB = MajorantGrid::kBrickSize;
    // Tentative collisions at the brick's majorant over [tStart, tEnd),
    // accepted with sigma_t / majorant (always, in a uniform brick).
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight& out) {
        float sigmaMaj = maj.maxSigmaT(brick, channel);
        if (sigmaMaj <= 0.0f) return false;  // nothing to collide with
        const float invMaj = 1.0f / sigmaMaj;
        const int sole = maj.soleLabel(brick);
        if (sole >= 0) {
            // One material: every tentative collision is real, no lookup.
            float t = tStart - std::log(1.0f - rng.uniform()) * invMaj;
            if (t >= tEnd) return false;
            out = {true, t, Label(sole)};
            return true;
        }
        const bool uniform = sigmaMaj == maj.minSigmaT(brick, channel);
        // Voxels of this brick inside the frame: round-off must not leave it.
        Vec3i lo{brick.x * kB, brick.y * kB, brick.z * kB};
        Vec3i hi{std::min(lo.x + kB, fmax.x), std::min(lo.y + kB, fmax.y), std::min(lo.z + kB, fmax.z)};
        lo = {std::max(lo.x, frame.indexMin.x), std::max(lo.y, frame.indexMin.y),
              std::max(lo.z, frame.indexMin.z)};
        float t = tStart;
        for (;;) {
            // 1 - u is exact for u = k 2^-24, so logf loses nothing against log1pf.
            t -= std::log(1.0f - rng.uniform()) * invMaj;
            if (t >= tEnd) return false;
            Label l = labelAt(clampToBox(ray.voxelAt(t), lo, hi));
            if (uniform || rng.uniform() * sigmaMaj < lut.sigmaT_perMm[l]) {
                out = {true, t, l};
                return true;
            }
        }
    };
    FreeFlight ff;
    float tFrom = 0.0f;
    if (ray.o.x >= frame.indexMin.x && ray.o.y >= frame.indexMin.y && ray.o.z >= frame.indexMin.z &&
        ray.o.x < fmax.x && ray.o.y < fmax.y && ray.o.z < fmax.z) {
        // Most free flights in dense resin start inside the grid and end in
        // the brick they start in: track that brick first, with no clipping
        // and no brick DDA. Its exit is where the brick (cut to the frame) ends.
        Vec3i first = MajorantGrid::brickOf(clampToBox(ray.voxelAt(0.0f), frame.indexMin, fmax));
        float tExit = tMax_mm;
        for (int a = 0; a < 3; ++a) {
            if (ray.d[a] > 0.0f)
                tExit = std::min(tExit, (float(std::min((first[a] + 1) * kB, fmax[a])) - ray.o[a]) / ray.d[a]);
            if (ray.d[a] < 0.0f)
                tExit = std::min(tExit, (float(std::max(first[a] * kB, frame.indexMin[a])) - ray.o[a]) / ray.d[a]);
        }
        if (trackBrick(first, 0.0f, tExit, ff)) return ff;
        if (tExit >= tMax_mm) return {};
        tFrom = std::max(0.0f, tExit);
    }
    // The rest brick by brick, inside the frame (free flights are
    // memoryless: restarting at a brick's entry is exact).
    float t0 = tFrom, t1 = tMax_mm;
    if (!clipRayToBox(ray.o, ray.d, frame.indexMin, fmax, t0, t1)) return {};
    constexpr float b = 1.0f / kB;
    GridDda bricks(ray.o * b, ray.d * b, t0, t1, maj.brickMin(), maj.brickMax());
    DdaSegment seg;
    while (bricks.next(seg))
        if (trackBrick(seg.cell, seg.t0, seg.t1, ff)) return ff;
    return {};
}

template <class LabelLookup>
float regularTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame,
                   const MajorantGrid& maj, const ChannelLut& lut, int channel,
                   LabelLookup&& labelAt) {
    float t0 = 0.0f, t1 = tMax_mm;
    if (!clipRayToBox(ray.o, ray.d, frame.indexMin, frame.indexMax(), t0, t1)) return 1.0f;
    constexpr float b = 1.0f / MajorantGrid::kBrickSize;
    GridDda bricks(ray.o * b, ray.d * b, t0, t1, maj.brickMin(), maj.brickMax());
    float tau = 0.0f;
    DdaSegment seg;
    while (bricks.next(seg)) {
        float sMax = maj.maxSigmaT(seg.cell, channel);
        if (sMax <= 0.0f) continue;
        if (sMax == maj.minSigmaT(seg.cell, channel)) {
            // Uniform brick: one step.
            tau += sMax * (seg.t1 - seg.t0);
        } else {
            Vec3i lo{seg.cell.x << MajorantGrid::kBrickLog2,
                     seg.cell.y << MajorantGrid::kBrickLog2,
                     seg.cell.z << MajorantGrid::kBrickLog2};
            Vec3i hi{lo.x + MajorantGrid::kBrickSize, lo.y + MajorantGrid::kBrickSize,
                     lo.z + MajorantGrid::kBrickSize};
            GridDda voxels(ray.o, ray.d, seg.t0, seg.t1, lo, hi);
            DdaSegment v;
            while (voxels.next(v)) tau += lut.sigmaT_perMm[labelAt(v.cell)] * (v.t1 - v.t0);
        }
        // Early exit once nothing gets through.
        if (tau > kOpaqueOpticalDepth) return 0.0f;
    }
    return std::exp(-tau);
}

}  // namespace pl
