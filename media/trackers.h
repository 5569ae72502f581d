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
    float t0 = 0.0f, t1 = tMax_mm;
    if (!clipRayToBox(ray.o, ray.d, frame.indexMin, frame.indexMax(), t0, t1)) return {};
    constexpr float b = 1.0f / MajorantGrid::kBrickSize;
    GridDda bricks(ray.o * b, ray.d * b, t0, t1, maj.brickMin(), maj.brickMax());
    DdaSegment seg;
    while (bricks.next(seg)) {
        // Zero majorant: nothing to collide with in this brick.
        float sigmaMaj = maj.maxSigmaT(seg.cell, channel);
        if (sigmaMaj <= 0.0f) continue;
        // Voxels of this brick inside the frame: round-off must not leave it.
        Vec3i lo{seg.cell.x << MajorantGrid::kBrickLog2, seg.cell.y << MajorantGrid::kBrickLog2,
                 seg.cell.z << MajorantGrid::kBrickLog2};
        Vec3i hi{lo.x + MajorantGrid::kBrickSize, lo.y + MajorantGrid::kBrickSize,
                 lo.z + MajorantGrid::kBrickSize};
        lo = {std::max(lo.x, frame.indexMin.x), std::max(lo.y, frame.indexMin.y),
              std::max(lo.z, frame.indexMin.z)};
        Vec3i fmax = frame.indexMax();
        hi = {std::min(hi.x, fmax.x), std::min(hi.y, fmax.y), std::min(hi.z, fmax.z)};
        // Tentative collisions at rate sigmaMaj; accept with sigma_t / sigmaMaj.
        float t = seg.t0;
        for (;;) {
            t -= std::log1p(-rng.uniform()) / sigmaMaj;
            if (t >= seg.t1) break;
            Label l = labelAt(clampToBox(ray.voxelAt(t), lo, hi));
            float sigmaT = lut.sigmaT_perMm[l];
            if (rng.uniform() * sigmaMaj < sigmaT) return {true, t, l};
        }
    }
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
