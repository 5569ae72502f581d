// How one path carries the colour channels it serves. The estimators
// (volpath, printpt) are written once against this small interface:
//  - SingleChannelPath: one channel with its own delta tracking (Brecka
//    renders R, G and B as three passes of these);
//  - HeroPath: all three channels from one path. Distances are sampled by
//    the hero channel's delta tracking; each channel c keeps the log of the
//    ratio p_c / p_hero of the densities with which its own tracking (and
//    phase sampling) would have produced the same path, and light reaching
//    the end is weighted by the balance heuristic over the three channels
//    as heroes (Wilkie et al. 2014; the null-collision form of Miller et
//    al. 2019): w_c = 3 r_c / sum r. The render driver draws the hero
//    uniformly, so the estimate of every channel is unbiased, and its
//    weight never exceeds 3 times what its own delta tracking would carry.
//  - SpectralPath: all three channels by spectral tracking (Kutz et al.
//    2017, media/trackers.h): one majorant, the channels' weights take the
//    ratios of the event probabilities.
// Each path holds per-channel throughputs `beta` (albedos, Fresnel factors,
// Russian roulette), the estimator multiplies the rest in through scale().
#pragma once

#include <array>
#include <cmath>

#include "core/rgb.h"
#include "core/sampling.h"
#include "media/label_medium.h"

namespace pl {

// How a render that asks for all three channels samples them.
enum class ChannelSampling {
    Separate,  // three single-channel passes
    Hero,      // one pass, hero channel + balance heuristic
    Spectral,  // one pass, spectral tracking
};

struct SingleChannelPath {
    using Value = float;
    static constexpr bool kSupportsNee = true;
    const ChannelLut* lut;
    int channel;
    float Le;  // environment radiance in this channel
    float beta = 1.0f;

    FreeFlight track(LabelMedium::Tracker& medium, const Ray& ray, float tMax_mm, Rng& rng) {
        return medium.sampleFreeFlight(ray, tMax_mm, channel, rng);
    }
    void collide(Label l) { beta *= lut->albedo[l]; }
    float g(Label l) const { return lut->g[l]; }
    // A new direction at a collision in label l (HG importance sampling).
    Vec3f samplePhase(Label l, const Vec3f& dIn, Rng& rng) {
        float u0 = rng.uniform(), u1 = rng.uniform();
        return sampleHG(dIn, lut->g[l], u0, u1).dOut;
    }
    float rouletteValue() const { return beta; }
    // The albedo that says whether a collision is in absorbing resin.
    float rouletteAlbedo(Label l) const { return lut->albedo[l]; }
    void scale(float s) { beta *= s; }
    bool alive() const { return beta > 0.0f; }
    // L += weight x throughput x environment.
    void addLight(Value& L, float weight) const { L += weight * beta * Le; }

    // Ball walks: sampled with this sigma_t; flights and collisions inside.
    bool canWalkBall(Label) const { return true; }
    float ballSigmaT(Label l) const { return lut->sigmaT_perMm[l]; }
    void ballFlight(Label, float /*t_mm*/) {}
    void ballCollision(Label) {}
};

struct HeroPath {
    using Value = RGB;
    static constexpr bool kSupportsNee = false;
    const std::array<ChannelLut, 3>* luts;
    RGB Le;
    int hero;
    RGB beta{1, 1, 1};
    RGB logRatio{0, 0, 0};  // log(p_c / p_hero); exactly 0 for the hero

    FreeFlight track(LabelMedium::Tracker& medium, const Ray& ray, float tMax_mm, Rng& rng) {
        return medium.sampleFreeFlightHero(ray, tMax_mm, hero, rng, logRatio);
    }
    void collide(Label l) {
        for (int c = 0; c < 3; ++c) beta[c] *= (*luts)[c].albedo[l];
    }
    float g(Label l) const { return (*luts)[hero].g[l]; }
    // The hero's HG lobe samples the direction; channels with another g
    // would have sampled it with their own.
    Vec3f samplePhase(Label l, const Vec3f& dIn, Rng& rng) {
        float u0 = rng.uniform(), u1 = rng.uniform();
        PhaseSample ps = sampleHG(dIn, (*luts)[hero].g[l], u0, u1);
        for (int c = 0; c < 3; ++c) {
            float gc = (*luts)[c].g[l];
            if (c != hero && gc != (*luts)[hero].g[l])
                logRatio[c] += std::log(hgPhase(dot(dIn, ps.dOut), gc) / ps.pdf);
        }
        return ps.dOut;
    }
    // Balance-heuristic weights 3 r_c / sum r, from the log ratios (the
    // largest is >= 0, the hero's, so the sum never underflows).
    RGB misWeights() const {
        float m = std::max(logRatio[0], std::max(logRatio[1], logRatio[2]));
        RGB r;
        float sum = 0.0f;
        for (int c = 0; c < 3; ++c) sum += (r[c] = std::exp(logRatio[c] - m));
        for (float& x : r) x *= 3.0f / sum;
        return r;
    }
    // The mean over the channels of what the path carries: once the other
    // channels' ratios have died away the hero's weight is 3 and this is its
    // throughput, so paths end as a single channel's would (the maximum
    // would let them run on until the throughput fell below 1/3).
    float rouletteValue() const {
        RGB w = misWeights();
        return (beta[0] * w[0] + beta[1] * w[1] + beta[2] * w[2]) / 3.0f;
    }
    float rouletteAlbedo(Label l) const { return (*luts)[hero].albedo[l]; }
    void scale(float s) {
        for (float& b : beta) b *= s;
    }
    bool alive() const { return beta[0] > 0.0f || beta[1] > 0.0f || beta[2] > 0.0f; }
    void addLight(Value& L, float weight) const {
        RGB w = misWeights();
        for (int c = 0; c < 3; ++c) L[c] += weight * beta[c] * w[c] * Le[c];
    }

    // A ball is walked with the hero's sigma_t; a flight of t_mm in it (to
    // a collision or, last, to the sphere) has channel c's ratio
    // exp(-(sigma_c - sigma_hero) t), times sigma_c / sigma_hero at a collision.
    bool canWalkBall(Label l) const {
        return (*luts)[0].g[l] == (*luts)[1].g[l] && (*luts)[1].g[l] == (*luts)[2].g[l];
    }
    float ballSigmaT(Label l) const { return (*luts)[hero].sigmaT_perMm[l]; }
    void ballFlight(Label l, float t_mm) {
        const float sigmaHero = (*luts)[hero].sigmaT_perMm[l];
        for (int c = 0; c < 3; ++c) logRatio[c] -= ((*luts)[c].sigmaT_perMm[l] - sigmaHero) * t_mm;
    }
    void ballCollision(Label l) {
        for (int c = 0; c < 3; ++c) logRatio[c] += (*luts)[c].logSigmaT[l] - (*luts)[hero].logSigmaT[l];
    }
};

struct SpectralPath {
    using Value = RGB;
    static constexpr bool kSupportsNee = false;
    const std::array<ChannelLut, 3>* luts;
    RGB Le;
    RGB beta{1, 1, 1};

    FreeFlight track(LabelMedium::Tracker& medium, const Ray& ray, float tMax_mm, Rng& rng) {
        return medium.sampleFreeFlightSpectral(ray, tMax_mm, rng, beta);
    }
    void collide(Label l) {
        for (int c = 0; c < 3; ++c) beta[c] *= (*luts)[c].albedo[l];
    }
    float g(Label l) const { return (*luts)[1].g[l]; }
    // Where the channels' lobes differ, directions come from their mixture
    // weighted by the channels' throughputs (the history-aware choice of
    // spectral tracking, for the phase function); each channel takes the
    // ratio of its lobe to the mixture's pdf.
    Vec3f samplePhase(Label l, const Vec3f& dIn, Rng& rng) {
        const RGB g{(*luts)[0].g[l], (*luts)[1].g[l], (*luts)[2].g[l]};
        float u0 = rng.uniform(), u1 = rng.uniform();
        if (g[0] == g[1] && g[1] == g[2]) return sampleHG(dIn, g[0], u0, u1).dOut;
        float total = std::abs(beta[0]) + std::abs(beta[1]) + std::abs(beta[2]);
        float pick = rng.uniform() * total;
        int lobe = pick < std::abs(beta[0]) ? 0 : (pick < std::abs(beta[0]) + std::abs(beta[1]) ? 1 : 2);
        Vec3f d = sampleHG(dIn, g[lobe], u0, u1).dOut;
        float cosTheta = dot(dIn, d), pdf = 0.0f;
        RGB value;
        for (int c = 0; c < 3; ++c) pdf += std::abs(beta[c]) / total * (value[c] = hgPhase(cosTheta, g[c]));
        for (int c = 0; c < 3; ++c) beta[c] *= value[c] / pdf;
        return d;
    }
    float rouletteValue() const { return std::max(beta[0], std::max(beta[1], beta[2])); }
    float rouletteAlbedo(Label l) const {
        return std::max((*luts)[0].albedo[l], std::max((*luts)[1].albedo[l], (*luts)[2].albedo[l]));
    }
    void scale(float s) {
        for (float& b : beta) b *= s;
    }
    bool alive() const { return beta[0] > 0.0f || beta[1] > 0.0f || beta[2] > 0.0f; }
    void addLight(Value& L, float weight) const {
        for (int c = 0; c < 3; ++c) L[c] += weight * beta[c] * Le[c];
    }
    // No ball walks: inside a ball spectral tracking would still need its
    // null events; left to the trackers.
    bool canWalkBall(Label) const { return false; }
    float ballSigmaT(Label) const { return 0.0f; }
    void ballFlight(Label, float) {}
    void ballCollision(Label) {}
};

}  // namespace pl
