// Trackers over the piecewise-constant label medium, in cell space (see
// label_grid.h) with the ray parameter t in millimetres.
//  - sampleMajorantFlight: the null-collision trackers' one loop over
//    majorant segments (per brick, or the whole grid's for the textbook
//    tracker); how the channels a path carries decide each tentative
//    collision (delta, hero or spectral tracking) is the events policy's
//    (media/collision_events.h).
//  - sampleDecomposedFlight: decomposition tracking over the same segments
//    (one channel): each brick's least extinction sampled analytically,
//    the rest by delta tracking.
//  - regularTrack: exact transmittance by 3D-DDA through the voxels
//    (Amanatides-Woo), skipping void bricks and stepping whole uniform bricks.
//  - inverseTrack: the free flight whose optical depth is a given value
//    (inversion of the transmittance by the same DDA): two walks that share
//    that value collide at the same place wherever their media agree
//    (printpt's control variate).
// All take the label lookup as a template parameter so the hot loop inlines
// the OpenVDB accessor (label_medium.cpp) or a dense array (tests).
#pragma once

#include <array>
#include <cmath>

#include "core/rng.h"
#include "core/sampling.h"
#include "media/dda.h"
#include "media/majorant_grid.h"
#include "media/materials.h"

namespace pl {

// The per-brick trackers below are lambdas called from two places in
// trackBricks; without this the compiler keeps them (and the small helpers
// of their loops) out of line, and delta tracking, the innermost loop,
// loses 7 %.
#define PL_ALWAYS_INLINE __attribute__((always_inline))

// A ray in cell space: cell(t) = o + d t, t in millimetres along the world ray.
struct CellRay {
    Vec3f o, d;
    PL_ALWAYS_INLINE Vec3i voxelAt(float t) const {
        return {int(std::floor(o.x + d.x * t)), int(std::floor(o.y + d.y * t)),
                int(std::floor(o.z + d.z * t))};
    }
};

// 8 bytes, returned in one register (a 12-byte layout was assembled on the
// stack and read back wider than it was written: a store-forwarding stall
// on every flight).
struct FreeFlight {
    float t_mm = 0;
    Label label = 0;         // material at the collision
    bool scattered = false;  // a real collision before tMax
    static FreeFlight collision(float t_mm, Label label) { return {t_mm, label, true}; }
};

// Beyond this optical depth the transmittance is below float precision.
constexpr float kOpaqueOpticalDepth = 100.0f;

PL_ALWAYS_INLINE inline Vec3i clampToBox(Vec3i v, const Vec3i& lo, const Vec3i& hiExcl) {
    for (int a = 0; a < 3; ++a) v[a] = std::min(std::max(v[a], lo[a]), hiExcl[a] - 1);
    return v;
}

// Runs trackBrick(brick, tStart, tEnd, out) over the majorant bricks the ray
// crosses up to tMax_mm, in order, until it reports a collision (free flights
// are memoryless: restarting at a brick's entry is exact).
template <class TrackBrick>
PL_ALWAYS_INLINE inline FreeFlight trackBricks(const CellRay& ray, float tMax_mm, const GridFrame& frame, TrackBrick&& trackBrick) {
    const Vec3i fmax = frame.indexMax();
    constexpr int kB = MajorantGrid::kBrickSize;
    // Most free flights start inside the grid (no clipping); others start
    // where they enter it.
    float tStart = 0.0f;
    if (!(ray.o.x >= frame.indexMin.x && ray.o.y >= frame.indexMin.y && ray.o.z >= frame.indexMin.z &&
          ray.o.x < fmax.x && ray.o.y < fmax.y && ray.o.z < fmax.z)) {
        float tEnd = tMax_mm;
        if (!clipRayToBox(ray.o, ray.d, frame.indexMin, fmax, tStart, tEnd)) return {};
    }
    // Most end in the brick they start in. One that goes on steps from
    // brick to brick across the face it leaves by (no DDA set-up); each
    // brick ends where it does or where the frame does.
    Vec3i brick = MajorantGrid::brickOf(clampToBox(ray.voxelAt(tStart), frame.indexMin, fmax));
    auto exitAlong = [&](int a) PL_ALWAYS_INLINE {
        if (ray.d[a] > 0.0f) return (float(std::min((brick[a] + 1) * kB, fmax[a])) - ray.o[a]) / ray.d[a];
        if (ray.d[a] < 0.0f) return (float(std::max(brick[a] * kB, frame.indexMin[a])) - ray.o[a]) / ray.d[a];
        return std::numeric_limits<float>::infinity();
    };
    float tNext[3] = {exitAlong(0), exitAlong(1), exitAlong(2)};
    FreeFlight ff;
    for (;;) {
        const int a = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
        const float tExit = std::min(std::max(tNext[a], tStart), tMax_mm);
        if (trackBrick(brick, tStart, tExit, ff)) return ff;
        if (tExit >= tMax_mm) return {};
        const bool leavesFrame = ray.d[a] > 0.0f ? (brick[a] + 1) * kB >= fmax[a] : brick[a] * kB <= frame.indexMin[a];
        if (leavesFrame) return {};
        brick[a] += ray.d[a] > 0.0f ? 1 : -1;
        tNext[a] = exitAlong(a);
        tStart = tExit;
    }
}

// The voxels of a brick inside the frame, [lo, hi): round-off must not
// take a lookup out of the brick.
inline void brickVoxels(const Vec3i& brick, const GridFrame& frame, Vec3i& lo, Vec3i& hi) {
    constexpr int kB = MajorantGrid::kBrickSize;
    const Vec3i fmax = frame.indexMax();
    lo = {std::max(brick.x * kB, frame.indexMin.x), std::max(brick.y * kB, frame.indexMin.y),
          std::max(brick.z * kB, frame.indexMin.z)};
    hi = {std::min(brick.x * kB + kB, fmax.x), std::min(brick.y * kB + kB, fmax.y),
          std::min(brick.z * kB + kB, fmax.z)};
}

// One stretch [tStart, tEnd) of a ray over which one majorant holds: a
// brick's (or, for the textbook tracker, the whole grid's) bounds of
// sigma_t, and the voxels lookups in it are confined to (round-off must
// not take a lookup out of it; unset where the bounds have a sole label).
struct MajorantSegment {
    float tStart, tEnd;
    const MajorantGrid::Bounds* bounds;
    Vec3i lo, hi;
};

// The ray's segments up to tMax_mm, brick by brick, in order: visit(segment,
// out) until it reports a collision (as trackBricks).
template <class Visit>
PL_ALWAYS_INLINE inline FreeFlight forEachBrickSegment(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& maj,
                               Visit&& visit) {
    return trackBricks(ray, tMax_mm, frame,
                       [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight& out) PL_ALWAYS_INLINE {
                           MajorantSegment segment{tStart, tEnd, &maj.bounds(brick), {}, {}};
                           if (segment.bounds->soleLabel < 0) brickVoxels(brick, frame, segment.lo, segment.hi);
                           return visit(segment, out);
                       });
}
// The ray's one segment inside the grid frame, under the whole grid's bounds.
template <class Visit>
FreeFlight wholeGridSegment(const CellRay& ray, float tMax_mm, const GridFrame& frame,
                            const MajorantGrid::Bounds& wholeGrid, Visit&& visit) {
    MajorantSegment segment{0.0f, tMax_mm, &wholeGrid, frame.indexMin, frame.indexMax()};
    if (!clipRayToBox(ray.o, ray.d, segment.lo, segment.hi, segment.tStart, segment.tEnd)) return {};
    FreeFlight out;
    return visit(segment, out) ? out : FreeFlight{};
}

// The label at t in a segment: its sole label, or the lookup confined to
// its voxels (round-off must not take a lookup out of them).
template <class LabelLookup>
PL_ALWAYS_INLINE inline Label labelInSegment(const CellRay& ray, const MajorantSegment& segment, float t,
                                             LabelLookup&& labelAt) {
    const int sole = segment.bounds->soleLabel;
    return sole >= 0 ? Label(sole) : labelAt(clampToBox(ray.voxelAt(t), segment.lo, segment.hi));
}

// The one loop of the null-collision trackers (delta, hero and spectral
// tracking; pbrt-v4's SampleT_maj): tentative collisions at each segment's
// majorant, a label lookup at each (none where the segment has a sole
// label), and the events policy (media/collision_events.h) deciding
// whether it is real. The optical depth left to the next tentative
// collision carries over into the next segment: it is Exp(1) whatever was
// spent, so a flight that crosses bricks needs no new logarithm.
//   events.enter(segment) -> the majorant to sample with (<= 0: nothing collides)
//   events.collides(t, label, rng) -> whether the tentative collision is real
//   events.leave(t) : the segment is crossed up to t without a real collision
// forEachSegment(visit) is forEachBrickSegment or wholeGridSegment bound to the ray.
template <class ForEachSegment, class Events, class LabelLookup>
PL_ALWAYS_INLINE inline FreeFlight sampleMajorantFlight(const CellRay& ray, ForEachSegment&& forEachSegment,
                                                        Events& events, LabelLookup&& labelAt, Rng& rng) {
    float tauLeft = -1.0f;  // < 0: draw a new one
    return forEachSegment([&](const MajorantSegment& segment, FreeFlight& out) PL_ALWAYS_INLINE {
        const float sigmaMaj = events.enter(segment);
        if (sigmaMaj <= 0.0f) {
            events.leave(segment.tEnd);
            return false;
        }
        const float invMaj = 1.0f / sigmaMaj;
        float t = segment.tStart;
        for (;;) {
            if (tauLeft < 0.0f) tauLeft = sampleOpticalDepth(rng.uniform());
            const float tNext = t + tauLeft * invMaj;
            if (tNext >= segment.tEnd) {
                tauLeft -= (segment.tEnd - t) * sigmaMaj;
                events.leave(segment.tEnd);
                return false;
            }
            tauLeft = -1.0f;
            t = tNext;
            const Label l = labelInSegment(ray, segment, t, labelAt);
            if (events.collides(t, l, rng)) {
                out = FreeFlight::collision(t, l);
                return true;
            }
        }
    });
}

// Decomposition tracking (Kutz et al. 2017) for one channel: in each
// majorant segment sigma_t = sigma_c + sigma_r, the control sigma_c the
// segment's least extinction and the residual sigma_r >= 0 the rest. A
// flight through the control is sampled analytically, and a collision with
// it is real whatever the label; the residual's by delta tracking against
// (largest - least), each tentative collision real with probability
// sigma_r / (largest - least). The flight ends at the nearer of the two
// (the sum of two independent exponential processes is the medium's), and
// both optical depths left over carry into the next segment. Every event
// looks the label up, as delta tracking's does (a control collision for
// the label's albedo and phase); it saves the control's share of the
// accept-or-reject draws.
template <class ForEachSegment, class LabelLookup>
PL_ALWAYS_INLINE inline FreeFlight sampleDecomposedFlight(const CellRay& ray, ForEachSegment&& forEachSegment,
                                                          const ChannelLut& lut, int channel, LabelLookup&& labelAt,
                                                          Rng& rng) {
    float controlLeft = -1.0f, residualLeft = -1.0f;  // optical depths left (< 0: draw a new one)
    return forEachSegment([&](const MajorantSegment& segment, FreeFlight& out) PL_ALWAYS_INLINE {
        const float leastSigmaT_perMm = segment.bounds->minSigmaT[channel];
        const float residualMaj_perMm = segment.bounds->maxSigmaT[channel] - leastSigmaT_perMm;
        float tControl = std::numeric_limits<float>::infinity();
        if (leastSigmaT_perMm > 0.0f) {
            if (controlLeft < 0.0f) controlLeft = sampleOpticalDepth(rng.uniform());
            tControl = segment.tStart + controlLeft / leastSigmaT_perMm;
        }
        const float tStop = std::min(tControl, segment.tEnd);
        if (residualMaj_perMm > 0.0f) {
            const float invMaj = 1.0f / residualMaj_perMm;
            for (float t = segment.tStart;;) {
                if (residualLeft < 0.0f) residualLeft = sampleOpticalDepth(rng.uniform());
                const float tNext = t + residualLeft * invMaj;
                if (tNext >= tStop) {
                    residualLeft -= (tStop - t) * residualMaj_perMm;
                    break;
                }
                residualLeft = -1.0f;
                t = tNext;
                const Label l = labelInSegment(ray, segment, t, labelAt);
                if (rng.uniform() * residualMaj_perMm < lut.sigmaT_perMm[l] - leastSigmaT_perMm) {
                    out = FreeFlight::collision(t, l);
                    return true;
                }
            }
        }
        if (tControl < segment.tEnd) {
            out = FreeFlight::collision(tControl, labelInSegment(ray, segment, tControl, labelAt));
            return true;
        }
        if (leastSigmaT_perMm > 0.0f) controlLeft -= (segment.tEnd - segment.tStart) * leastSigmaT_perMm;
        return false;
    });
}

// Russian roulette on a transmittance estimate: once the estimate
// exp(-(tau - logScale)) falls below exp(-rouletteDepth), it survives with
// probability estimate / exp(-rouletteDepth) and is scaled back up to that.
// Unbiased; a segment through dense resin then ends about one optical depth
// past the threshold instead of being tracked voxel by voxel to its end.
struct TransmittanceRoulette {
    float rouletteDepth = kOpaqueOpticalDepth;  // no roulette below this optical depth
    Rng* rng = nullptr;                           // none: exact transmittance
    float logScale = 0.0f;
    // False: the estimate is 0 (the walk along the segment was ended).
    PL_ALWAYS_INLINE bool survives(float tau) {
        float excess = tau - logScale - rouletteDepth;
        if (!rng || excess <= 0.0f) return true;
        if (!(rng->uniform() < std::exp(-excess))) return false;
        logScale += excess;
        return true;
    }
};

// Transmittance along the ray up to tMax_mm by regular tracking: exact, or
// an unbiased estimate with the roulette above.
template <class LabelLookup>
float regularTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame,
                   const MajorantGrid& maj, const ChannelLut& lut, int channel,
                   LabelLookup&& labelAt, TransmittanceRoulette roulette = {}) {
    float tau = 0.0f;
    bool ended = false;  // by the roulette, or nothing gets through
    // Uniform bricks in one step, mixed ones voxel by voxel.
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight&) PL_ALWAYS_INLINE {
        const float sMax = maj.maxSigmaT(brick, channel);
        if (sMax <= 0.0f) return false;
        if (sMax == maj.minSigmaT(brick, channel)) {
            tau += sMax * (tEnd - tStart);
        } else {
            Vec3i lo, hi;
            brickVoxels(brick, frame, lo, hi);
            GridDda voxels(ray.o, ray.d, tStart, tEnd, lo, hi);
            DdaSegment v;
            while (voxels.next(v)) {
                tau += lut.sigmaT_perMm[labelAt(v.cell)] * (v.t1 - v.t0);
                if (!roulette.survives(tau)) return ended = true;
            }
        }
        // Early exit once nothing gets through.
        return ended = !roulette.survives(tau) || tau - roulette.logScale > kOpaqueOpticalDepth;
    };
    trackBricks(ray, tMax_mm, frame, trackBrick);
    return ended ? 0.0f : std::exp(-(tau - roulette.logScale));
}

// The collision at optical depth `opticalDepth` (an Exp(1) sample gives a
// free flight with pdf sigma_t(t) T(t)), by regular tracking up to tMax_mm.
template <class LabelLookup>
FreeFlight inverseTrack(const CellRay& ray, float tMax_mm, float opticalDepth, const GridFrame& frame,
                        const MajorantGrid& maj, const ChannelLut& lut, int channel, LabelLookup&& labelAt) {
    float tau = 0.0f;
    // Does [s0, s1) in label l reach the optical depth?
    auto reaches = [&](Label l, float s0, float s1, FreeFlight& out) PL_ALWAYS_INLINE {
        float sigma = lut.sigmaT_perMm[l];
        float step = sigma * (s1 - s0);
        if (tau + step < opticalDepth || sigma <= 0.0f) {
            tau += step;
            return false;
        }
        out = FreeFlight::collision(std::min(s1, s0 + (opticalDepth - tau) / sigma), l);
        return true;
    };
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight& out) PL_ALWAYS_INLINE {
        if (maj.maxSigmaT(brick, channel) <= 0.0f) return false;
        int sole = maj.soleLabel(brick);
        if (sole >= 0) return reaches(Label(sole), tStart, tEnd, out);
        Vec3i lo, hi;
        brickVoxels(brick, frame, lo, hi);
        GridDda voxels(ray.o, ray.d, tStart, tEnd, lo, hi);
        DdaSegment v;
        while (voxels.next(v))
            if (reaches(labelAt(v.cell), v.t0, v.t1, out)) return true;
        return false;
    };
    return trackBricks(ray, tMax_mm, frame, trackBrick);
}

}  // namespace pl
