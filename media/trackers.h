// Trackers over the piecewise-constant label medium, in cell space (see
// label_grid.h) with the ray parameter t in millimetres.
//  - deltaTrack: delta (Woodcock) tracking against the per-brick majorant;
//    samples a free-flight distance with pdf sigma_t(t) T(t);
//    globalDeltaTrack: the same with one majorant for the whole grid.
//  - regularTrack: exact transmittance by 3D-DDA through the voxels
//    (Amanatides-Woo), skipping void bricks and stepping whole uniform bricks.
//  - inverseTrack: the free flight whose optical depth is a given value
//    (inversion of the transmittance by the same DDA): two walks that share
//    that value collide at the same place wherever their media agree
//    (printpt's control variate).
// Both take the label lookup as a template parameter so the hot loop inlines
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
FreeFlight trackBricks(const CellRay& ray, float tMax_mm, const GridFrame& frame, TrackBrick&& trackBrick) {
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

template <class LabelLookup>
FreeFlight deltaTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame,
                      const MajorantGrid& maj, const ChannelLut& lut, int channel,
                      LabelLookup&& labelAt, Rng& rng) {
    // Tentative collisions at the brick's majorant over [tStart, tEnd),
    // accepted with sigma_t / majorant (always, in a uniform brick). The
    // optical depth (at the majorants) left to the next tentative collision
    // carries over into the next brick: it is Exp(1) whatever was spent, so
    // a flight that crosses bricks needs no new logarithm.
    float tauLeft = -1.0f;  // < 0: draw a new one
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight& out) PL_ALWAYS_INLINE {
        float sigmaMaj = maj.maxSigmaT(brick, channel);
        if (sigmaMaj <= 0.0f) return false;  // nothing to collide with
        const float invMaj = 1.0f / sigmaMaj;
        // 1 - u is exact for u = k 2^-24, so logf loses nothing against log1pf.
        auto nextTentative = [&](float from) PL_ALWAYS_INLINE {
            if (tauLeft < 0.0f) tauLeft = sampleOpticalDepth(rng.uniform());
            float t = from + tauLeft * invMaj;
            tauLeft = t >= tEnd ? tauLeft - (tEnd - from) * sigmaMaj : -1.0f;
            return t;
        };
        const int sole = maj.soleLabel(brick);
        if (sole >= 0) {
            // One material: every tentative collision is real, no lookup.
            float t = nextTentative(tStart);
            if (t >= tEnd) return false;
            out = FreeFlight::collision(t, Label(sole));
            return true;
        }
        const bool uniform = sigmaMaj == maj.minSigmaT(brick, channel);
        Vec3i lo, hi;
        brickVoxels(brick, frame, lo, hi);
        float t = tStart;
        for (;;) {
            t = nextTentative(t);
            if (t >= tEnd) return false;
            Label l = labelAt(clampToBox(ray.voxelAt(t), lo, hi));
            if (uniform || rng.uniform() * sigmaMaj < lut.sigmaT_perMm[l]) {
                out = FreeFlight::collision(t, l);
                return true;
            }
        }
    };
    return trackBricks(ray, tMax_mm, frame, trackBrick);
}

// Textbook delta (Woodcock) tracking: one majorant for the whole grid,
// the channel's largest sigma_t, a label lookup at every tentative
// collision. The baseline the per-brick majorants are measured against
// (Brecka 4.6: in a brick of thin resin most tentative collisions of a
// global majorant are null).
template <class LabelLookup>
FreeFlight globalDeltaTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame, float sigmaMaj,
                            const ChannelLut& lut, LabelLookup&& labelAt, Rng& rng) {
    if (sigmaMaj <= 0.0f) return {};
    const Vec3i fmax = frame.indexMax();
    float t = 0.0f, tEnd = tMax_mm;
    if (!clipRayToBox(ray.o, ray.d, frame.indexMin, fmax, t, tEnd)) return {};
    const float invMaj = 1.0f / sigmaMaj;
    for (;;) {
        t += sampleOpticalDepth(rng.uniform()) * invMaj;
        if (t >= tEnd) return {};
        Label l = labelAt(clampToBox(ray.voxelAt(t), frame.indexMin, fmax));
        if (rng.uniform() * sigmaMaj < lut.sigmaT_perMm[l]) return FreeFlight::collision(t, l);
    }
}

// Hero-channel delta tracking for three channels at once: distances are
// sampled with the hero channel's majorants, as deltaTrack would, and
// logRatio[c] += log(p_c / p_hero) of what was sampled, where p_c is the
// density with which channel c's own delta tracking would have taken the
// same tentative collisions, null choices and real collision (or passed
// the segment without one). The per-event ratios are accumulated in log
// space: a path of hundreds of events would underflow a product of pdfs.
template <class LabelLookup>
FreeFlight heroDeltaTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& maj,
                          const std::array<ChannelLut, 3>& luts, int hero, LabelLookup&& labelAt, Rng& rng,
                          RGB& logRatio) {
    const ChannelLut& heroLut = luts[hero];
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight& out) PL_ALWAYS_INLINE {
        const RGB& sigmaMaj = maj.maxSigmaT(brick);
        const float heroMaj = sigmaMaj[hero];
        // Channel c would have taken no tentative collision over [tStart, t).
        auto flew = [&](float t) {
            for (int c = 0; c < 3; ++c) logRatio[c] -= (sigmaMaj[c] - heroMaj) * (t - tStart);
        };
        if (heroMaj <= 0.0f) {
            flew(tEnd);
            return false;
        }
        const float invMaj = 1.0f / heroMaj;
        const int sole = maj.soleLabel(brick);
        if (sole >= 0) {
            // One material: the majorants are its sigma_t, every collision is real.
            float t = tStart + sampleOpticalDepth(rng.uniform()) * invMaj;
            if (t >= tEnd) {
                flew(tEnd);
                return false;
            }
            flew(t);
            for (int c = 0; c < 3; ++c) logRatio[c] += luts[c].logSigmaT[sole] - heroLut.logSigmaT[sole];
            out = FreeFlight::collision(t, Label(sole));
            return true;
        }
        Vec3i lo, hi;
        brickVoxels(brick, frame, lo, hi);
        // Null collisions' ratios sigma_n,c / sigma_n,hero, folded into the
        // logs when the brick is done (or before the product could overflow).
        std::array<double, 3> nullRatio{1, 1, 1};
        bool nulls = false;
        auto foldNulls = [&] {
            if (!nulls) return;
            for (int c = 0; c < 3; ++c) logRatio[c] += float(std::log(nullRatio[c]));
            nullRatio = {1, 1, 1};
            nulls = false;
        };
        float t = tStart;
        for (;;) {
            t += sampleOpticalDepth(rng.uniform()) * invMaj;
            if (t >= tEnd) {
                flew(tEnd);
                foldNulls();
                return false;
            }
            Label l = labelAt(clampToBox(ray.voxelAt(t), lo, hi));
            const float heroSigma = heroLut.sigmaT_perMm[l];
            if (rng.uniform() * heroMaj < heroSigma) {
                flew(t);
                foldNulls();
                for (int c = 0; c < 3; ++c) logRatio[c] += luts[c].logSigmaT[l] - heroLut.logSigmaT[l];
                out = FreeFlight::collision(t, l);
                return true;
            }
            // Null collision: heroMaj > heroSigma here.
            const float heroNull = heroMaj - heroSigma;
            for (int c = 0; c < 3; ++c) nullRatio[c] *= double(sigmaMaj[c] - luts[c].sigmaT_perMm[l]) / heroNull;
            nulls = true;
            for (int c = 0; c < 3; ++c)
                if (nullRatio[c] > 1e100) foldNulls();  // rare: keep the product finite
        }
    };
    return trackBricks(ray, tMax_mm, frame, trackBrick);
}

// Spectral tracking (Kutz et al. 2017) for three channels at once: one
// majorant, the largest of the channels', and at each tentative collision a
// real or a null event chosen with the history-aware probabilities
// P_real ~ max_c |w_c sigma_t,c|, P_null ~ max_c |w_c sigma_n,c|; the
// channel weights w (the path throughput) take sigma / (majorant P) of the
// event. (Absorption stays in the caller's albedo weight.)
template <class LabelLookup>
FreeFlight spectralTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& maj,
                         const std::array<ChannelLut, 3>& luts, LabelLookup&& labelAt, Rng& rng, RGB& weight) {
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight& out) PL_ALWAYS_INLINE {
        const RGB& brickMaj = maj.maxSigmaT(brick);
        const float sigmaMaj = std::max(brickMaj[0], std::max(brickMaj[1], brickMaj[2]));
        if (sigmaMaj <= 0.0f) return false;
        const float invMaj = 1.0f / sigmaMaj;
        const int sole = maj.soleLabel(brick);
        Vec3i lo, hi;
        if (sole < 0) brickVoxels(brick, frame, lo, hi);
        float t = tStart;
        for (;;) {
            t += sampleOpticalDepth(rng.uniform()) * invMaj;
            if (t >= tEnd) return false;
            Label l = sole >= 0 ? Label(sole) : labelAt(clampToBox(ray.voxelAt(t), lo, hi));
            RGB sigma{luts[0].sigmaT_perMm[l], luts[1].sigmaT_perMm[l], luts[2].sigmaT_perMm[l]};
            float pReal = 0.0f, pNull = 0.0f;
            for (int c = 0; c < 3; ++c) {
                pReal = std::max(pReal, std::abs(weight[c] * sigma[c]));
                pNull = std::max(pNull, std::abs(weight[c] * (sigmaMaj - sigma[c])));
            }
            const float pSum = pReal + pNull;
            if (!(pSum > 0.0f)) {
                // Nothing left to carry: end here as a real collision of weight 0.
                weight = {0, 0, 0};
                out = FreeFlight::collision(t, l);
                return true;
            }
            if (rng.uniform() * pSum < pReal) {
                const float scale = pSum / (sigmaMaj * pReal);
                for (int c = 0; c < 3; ++c) weight[c] *= sigma[c] * scale;
                out = FreeFlight::collision(t, l);
                return true;
            }
            const float scale = pSum / (sigmaMaj * pNull);
            for (int c = 0; c < 3; ++c) weight[c] *= (sigmaMaj - sigma[c]) * scale;
        }
    };
    return trackBricks(ray, tMax_mm, frame, trackBrick);
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
