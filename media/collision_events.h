// How the null-collision trackers' loop (sampleMajorantFlight,
// media/trackers.h) decides each tentative collision, for the channels a
// path carries:
//  - DeltaEvents: one channel, delta (Woodcock) tracking: samples a free
//    flight with pdf sigma_t(t) T(t);
//  - HeroEvents: three channels, distances sampled by the hero channel's
//    delta tracking; logRatio[c] += log(p_c / p_hero) of what was sampled,
//    where p_c is the density with which channel c's own delta tracking
//    would have taken the same tentative collisions, null choices and real
//    collision (or passed the segment without one). Accumulated in log
//    space: a path of hundreds of events would underflow a product of pdfs;
//  - SpectralEvents: three channels by spectral tracking (Kutz et al. 2017):
//    one majorant, the largest of the channels', and at each tentative
//    collision a real or a null event chosen with the history-aware
//    probabilities P_real ~ max_c |w_c sigma_t,c|, P_null ~ max_c |w_c
//    sigma_n,c|; the channel weights w (the path throughput) take
//    sigma / (majorant P) of the event. (Absorption stays in the caller's
//    albedo weight.)
#pragma once

#include <array>
#include <cmath>

#include "core/rgb.h"
#include "core/rng.h"
#include "media/majorant_grid.h"
#include "media/materials.h"
#include "media/trackers.h"

namespace pl {

struct DeltaEvents {
    const ChannelLut& lut;
    int channel;
    float sigmaMaj = 0.0f;
    bool everyCollisionReal = false;  // one label, or labels of one sigma_t

    PL_ALWAYS_INLINE float enter(const MajorantSegment& s) {
        sigmaMaj = s.bounds->maxSigmaT[channel];
        everyCollisionReal = s.bounds->soleLabel >= 0 || sigmaMaj == s.bounds->minSigmaT[channel];
        return sigmaMaj;
    }
    PL_ALWAYS_INLINE bool collides(float /*t*/, Label l, Rng& rng) const {
        return everyCollisionReal || rng.uniform() * sigmaMaj < lut.sigmaT_perMm[l];
    }
    PL_ALWAYS_INLINE void leave(float /*t*/) {}
};

struct HeroEvents {
    const std::array<ChannelLut, 3>& luts;
    int hero;
    RGB& logRatio;
    const MajorantSegment* segment = nullptr;
    // Null collisions' ratios sigma_n,c / sigma_n,hero, folded into the
    // logs at the segment's end or its real collision (or before the
    // product could overflow).
    std::array<double, 3> nullRatio{1, 1, 1};
    bool nulls = false;

    PL_ALWAYS_INLINE float enter(const MajorantSegment& s) {
        segment = &s;
        return s.bounds->maxSigmaT[hero];
    }
    PL_ALWAYS_INLINE bool collides(float t, Label l, Rng& rng) {
        const float heroMaj = segment->bounds->maxSigmaT[hero];
        const float heroSigma = luts[hero].sigmaT_perMm[l];
        // One label: its sigma_t is every channel's majorant, every collision real.
        if (segment->bounds->soleLabel >= 0 || rng.uniform() * heroMaj < heroSigma) {
            leave(t);
            for (int c = 0; c < 3; ++c) logRatio[c] += luts[c].logSigmaT[l] - luts[hero].logSigmaT[l];
            return true;
        }
        // Null collision: heroMaj > heroSigma here.
        const float heroNull = heroMaj - heroSigma;
        const RGB& sigmaMaj = segment->bounds->maxSigmaT;
        for (int c = 0; c < 3; ++c) nullRatio[c] *= double(sigmaMaj[c] - luts[c].sigmaT_perMm[l]) / heroNull;
        nulls = true;
        for (int c = 0; c < 3; ++c)
            if (nullRatio[c] > 1e100) foldNulls();  // rare: keep the product finite
        return false;
    }
    // Channel c would have taken no tentative collision over [tStart, t).
    PL_ALWAYS_INLINE void leave(float t) {
        const RGB& sigmaMaj = segment->bounds->maxSigmaT;
        const float heroMaj = sigmaMaj[hero];
        for (int c = 0; c < 3; ++c) logRatio[c] -= (sigmaMaj[c] - heroMaj) * (t - segment->tStart);
        foldNulls();
    }

private:
    void foldNulls() {
        if (!nulls) return;
        for (int c = 0; c < 3; ++c) logRatio[c] += float(std::log(nullRatio[c]));
        nullRatio = {1, 1, 1};
        nulls = false;
    }
};

struct SpectralEvents {
    const std::array<ChannelLut, 3>& luts;
    RGB& weight;
    float sigmaMaj = 0.0f;

    PL_ALWAYS_INLINE float enter(const MajorantSegment& s) {
        const RGB& m = s.bounds->maxSigmaT;
        return sigmaMaj = std::max(m[0], std::max(m[1], m[2]));
    }
    PL_ALWAYS_INLINE bool collides(float /*t*/, Label l, Rng& rng) {
        const RGB sigma{luts[0].sigmaT_perMm[l], luts[1].sigmaT_perMm[l], luts[2].sigmaT_perMm[l]};
        float pReal = 0.0f, pNull = 0.0f;
        for (int c = 0; c < 3; ++c) {
            pReal = std::max(pReal, std::abs(weight[c] * sigma[c]));
            pNull = std::max(pNull, std::abs(weight[c] * (sigmaMaj - sigma[c])));
        }
        const float pSum = pReal + pNull;
        if (!(pSum > 0.0f)) {
            // Nothing left to carry: end here as a real collision of weight 0.
            weight = {0, 0, 0};
            return true;
        }
        const bool real = rng.uniform() * pSum < pReal;
        const float scale = pSum / (sigmaMaj * (real ? pReal : pNull));
        for (int c = 0; c < 3; ++c) weight[c] *= (real ? sigma[c] : sigmaMaj - sigma[c]) * scale;
        return real;
    }
    PL_ALWAYS_INLINE void leave(float /*t*/) {}
};

}  // namespace pl
