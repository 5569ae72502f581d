// Smooth dielectric boundary: unpolarised Fresnel reflectance and refraction.
#pragma once

#include <cmath>
#include <optional>

#include "core/vecmath.h"

namespace pl {

// Reflectance for a ray arriving with cosThetaI (> 0) on the side of index 1,
// entering a medium of relative index eta = n_t / n_i. Returns 1 under total
// internal reflection.
inline float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
    float sin2ThetaT = (1.0f - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1.0f) return 1.0f;
    float cosThetaT = std::sqrt(1.0f - sin2ThetaT);
    float rParl = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerp = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5f * (rParl * rParl + rPerp * rPerp);
}

// Mirror direction of d about the normal n.
inline Vec3f reflect(const Vec3f& d, const Vec3f& n) { return d - n * (2.0f * dot(d, n)); }

// Refracted propagation direction for d hitting a surface with normal n
// facing against d (dot(d, n) < 0), relative index eta = n_t / n_i.
// Empty under total internal reflection.
inline std::optional<Vec3f> refract(const Vec3f& d, const Vec3f& n, float eta) {
    float cosThetaI = -dot(d, n);
    float sin2ThetaT = (1.0f - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1.0f) return std::nullopt;
    float cosThetaT = std::sqrt(1.0f - sin2ThetaT);
    return normalize(d / eta + n * (cosThetaI / eta - cosThetaT));
}

}  // namespace pl
