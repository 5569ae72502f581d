// Sampling routines. Each returns the sampled value together with its pdf.
#pragma once

#include <cmath>
#include <optional>

#include "core/rng.h"
#include "core/vecmath.h"

namespace pl {

// Henyey-Greenstein phase function with propagation-direction convention:
// cosTheta = dot(dIn, dOut), so g > 0 scatters forward.
inline float hgPhase(float cosTheta, float g) {
    float denom = 1.0f + g * g - 2.0f * g * cosTheta;
    return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(std::max(denom, 1e-30f)));
}

struct PhaseSample {
    Vec3f dOut;   // new propagation direction (unit)
    float value;  // phase function value p(dIn, dOut)
    float pdf;    // solid-angle pdf of dOut (equal to value for HG)
};

// Inverts the HG cdf in cosTheta; uniform azimuth around dIn.
inline PhaseSample sampleHG(const Vec3f& dIn, float g, float u0, float u1) {
    float cosTheta;
    if (std::abs(g) < 1e-4f) {
        cosTheta = 1.0f - 2.0f * u0;
    } else {
        float sqrTerm = (1.0f - g * g) / (1.0f - g + 2.0f * g * u0);
        cosTheta = (1.0f + g * g - sqrTerm * sqrTerm) / (2.0f * g);
    }
    cosTheta = std::clamp(cosTheta, -1.0f, 1.0f);
    float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    float phi = 2.0f * kPi * u1;
    Vec3f local(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
    Vec3f dOut = normalize(Frame(dIn).toWorld(local));
    float p = hgPhase(cosTheta, g);
    return {dOut, p, p};
}

// von Mises-Fisher lobe around the unit vector mu with concentration kappa
// (> 0): pdf(w) = kappa / (2 pi (1 - exp(-2 kappa))) exp(kappa (mu.w - 1)).
inline float vmfPdf(const Vec3f& mu, float kappa, const Vec3f& w) {
    return kappa / (2.0f * kPi * -std::expm1(-2.0f * kappa)) * std::exp(kappa * (dot(mu, w) - 1.0f));
}

struct DirectionSample {
    Vec3f d;
    float pdf;
};

// Inverts the cdf of mu.w in a numerically stable form (Jakob 2012).
inline DirectionSample sampleVMF(const Vec3f& mu, float kappa, float u0, float u1) {
    float w = 1.0f + std::log(u0 + (1.0f - u0) * std::exp(-2.0f * kappa)) / kappa;
    w = std::clamp(w, -1.0f, 1.0f);
    float s = std::sqrt(std::max(0.0f, 1.0f - w * w));
    float phi = 2.0f * kPi * u1;
    Vec3f d = normalize(Frame(mu).toWorld({s * std::cos(phi), s * std::sin(phi), w}));
    return {d, vmfPdf(mu, kappa, d)};
}

// A point uniform by area on a triangle (b0 v0 + b1 v1 + b2 v2; pdf 1 /
// area), by the square-root parametrisation: its barycentrics.
struct TriangleSample {
    float b0, b1, b2;
};
inline TriangleSample sampleUniformTriangle(float u0, float u1) {
    const float s = std::sqrt(u0);
    return {1.0f - s, s * (1.0f - u1), s * u1};
}

// A direction about +z with pdf cos(theta) / pi (Malley's method).
inline DirectionSample sampleCosineHemisphere(float u0, float u1) {
    const float r = std::sqrt(u0), phi = 2.0f * kPi * u1;
    const float z = std::sqrt(std::max(0.0f, 1.0f - u0));
    return {{r * std::cos(phi), r * std::sin(phi), z}, z / kPi};
}

// Exponential free-flight distance with rate sigma (1/mm): value and pdf.
struct DistanceSample {
    float t;
    float pdf;
};
// An Exp(1) variate from u in [0, 1): the optical depth a free flight
// crosses before its collision.
inline float sampleOpticalDepth(float u) { return -std::log(1.0f - u); }

inline DistanceSample sampleExponential(float sigma, float u) {
    float t = -std::log1p(-u) / sigma;
    return {t, sigma * std::exp(-sigma * t)};
}

// Russian roulette with survival probability q (q >= 1: no roulette). False
// if the walk ends; else survive(q) rescales what the walk carries by 1/q.
template <class Survive>
bool playRoulette(float q, Rng& rng, Survive&& survive) {
    if (q >= 1.0f) return true;
    if (!(rng.uniform() < q)) return false;
    survive(q);
    return true;
}

}  // namespace pl
