// Unbiased stochastic estimates of the transmittance along a fixed
// segment, beside regularTrack's exact one (trackers.h), to measure them
// against it (bench --transmittance):
//  - ratioTrack: ratio tracking (Cramer 1978; Novak et al. 2014) against
//    the brick majorants: tentative collisions at the brick's largest
//    sigma_t, each multiplying the estimate by the null fraction
//    1 - sigma_t / majorant;
//  - pinTrack: pin transmittance (Hansen 2025, eqs. 3.5-3.8) with the
//    voxels the segment crosses as the pin's intervals: each voxel's
//    transmittance t_i is exact, and the estimate takes the factor
//    c_i = exp(-majorant x length_i) <= t_i with probability
//    (1 - t_i) / (1 - c_i), so that E[factor] = 1 - (1 - c_i)(1 - t_i) /
//    (1 - c_i) = t_i. (The thesis stores the bits along precomputed lines
//    and reuses them, which is where its speed and its bias come from;
//    drawn afresh for one segment they take regular tracking's lookups
//    and add variance.)
// Bricks of one extinction are exact in both, as in regularTrack.
#pragma once

#include <cmath>

#include "core/rng.h"
#include "core/sampling.h"
#include "media/trackers.h"

namespace pl {

// The walk both share: over the bricks the segment crosses, empty ones
// skipped and uniform ones exact; a mixed brick's stretch [tStart, tEnd)
// and its voxels [lo, hi) go to mixed(tStart, tEnd, lo, hi, sigmaMax_perMm, T), which
// multiplies its estimate into T and returns true to end the walk (T 0).
template <class Mixed>
float trackMixedBricks(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& maj, int channel,
                       Mixed&& mixed) {
    float T = 1.0f;
    auto trackBrick = [&](const Vec3i& brick, float tStart, float tEnd, FreeFlight&) PL_ALWAYS_INLINE {
        const float sigmaMax_perMm = maj.maxSigmaT(brick, channel);
        if (sigmaMax_perMm <= 0.0f) return false;
        if (sigmaMax_perMm == maj.minSigmaT(brick, channel)) {
            T *= std::exp(-sigmaMax_perMm * (tEnd - tStart));
            return false;
        }
        Vec3i lo, hi;
        brickVoxels(brick, frame, lo, hi);
        return mixed(tStart, tEnd, lo, hi, sigmaMax_perMm, T);
    };
    trackBricks(ray, tMax_mm, frame, trackBrick);
    return T;
}

template <class LabelLookup>
float ratioTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& maj,
                 const ChannelLut& lut, int channel, LabelLookup&& labelAt, Rng& rng) {
    return trackMixedBricks(ray, tMax_mm, frame, maj, channel,
                            [&](float tStart, float tEnd, const Vec3i& lo, const Vec3i& hi, float sigmaMax_perMm, float& T) {
                                const float invMaj = 1.0f / sigmaMax_perMm;
                                for (float t = tStart;;) {
                                    t += sampleOpticalDepth(rng.uniform()) * invMaj;
                                    if (t >= tEnd) return false;
                                    T *= 1.0f - lut.sigmaT_perMm[labelAt(clampToBox(ray.voxelAt(t), lo, hi))] * invMaj;
                                    if (!(T > 0.0f)) return true;
                                }
                            });
}

template <class LabelLookup>
float pinTrack(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& maj,
               const ChannelLut& lut, int channel, LabelLookup&& labelAt, Rng& rng) {
    return trackMixedBricks(ray, tMax_mm, frame, maj, channel,
                            [&](float tStart, float tEnd, const Vec3i& lo, const Vec3i& hi, float sigmaMax_perMm, float& T) {
                                GridDda voxels(ray.o, ray.d, tStart, tEnd, lo, hi);
                                DdaSegment v;
                                while (voxels.next(v)) {
                                    const float length_mm = v.t1 - v.t0;
                                    const float c = std::exp(-sigmaMax_perMm * length_mm);
                                    if (!(c < 1.0f)) continue;
                                    const float t = std::exp(-lut.sigmaT_perMm[labelAt(v.cell)] * length_mm);
                                    if (rng.uniform() * (1.0f - c) < 1.0f - t) T *= c;
                                }
                                return false;
                            });
}

}  // namespace pl
