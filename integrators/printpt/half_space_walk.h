// printpt's control variate: the same walk in a half-space of one
// homogeneous material under a flat Fresnel boundary. Its mean, the light a
// normally incident walk brings back out, depends only on the albedo, g
// and the index of refraction (sigma_t only scales the walk), so it is
// estimated once for each such triple with many cheap walks. A surface
// walk that shares its random numbers with a half-space walk from its entry
// point (same optical depths, phase and roulette numbers) mostly scatters
// where the other does; the estimate f - g + mean(g) keeps the mean of f
// and loses the variance they share. Near an edge of the object the
// control is a wedge instead: the half-space cut by a second plane, the
// side face, at right angles; its mean also depends on the distance from
// the entry to the edge, so it is tabulated over that distance. Under a
// convex curved surface it is the region under a paraboloid with the
// surface's two principal curvatures at the entry, tabulated over both
// (in units of the mean free path); the control takes the nearest
// tabulated pair, so its mean is known exactly (no interpolation), and the
// walks part where the real surface and the tabulated one differ.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <tuple>

#include "core/rng.h"
#include "core/vecmath.h"

namespace pl {

struct HalfSpace {
    Point3f origin;  // a point of the boundary plane
    Vec3f normal;    // outward unit normal of the plane
    float sigmaT_perMm = 0, albedo = 0, g = 0;
    float etaOut = 1;  // relative index seen from inside (1 / ior)
    // The side face of an edge, if any: the region is then the wedge below
    // both planes (sideNormal outward, at right angles to normal).
    bool hasSide = false;
    Point3f sideOrigin{0, 0, 0};
    Vec3f sideNormal{0, 0, 0};
    // Curved (no side face then): the region below the paraboloid
    // z = -(kappaS u^2 + kappaT v^2) / 2, with z along normal and u, v along
    // the principal directions axisS, axisT from origin; curvatures >= 0 (1/mm).
    bool curved = false;
    Vec3f axisS{0, 0, 0}, axisT{0, 0, 0};
    float kappaS_perMm = 0, kappaT_perMm = 0;

    // A lower bound of the distance from x inside to the region's boundary
    // (mm; exact for the planes).
    float depth(const Point3f& x) const {
        if (curved) return curvedDepth(x);
        float d = dot(origin - x, normal);
        return hasSide ? std::min(d, dot(sideOrigin - x, sideNormal)) : d;
    }
    // Curved: where the ray from x inside along d leaves the region; none
    // if it never does.
    struct Exit {
        float t_mm;      // distance along d
        Vec3f outward;   // the boundary's outward normal there
    };
    std::optional<Exit> exit(const Point3f& x, const Vec3f& d) const;

private:
    float curvedDepth(const Point3f& x) const {
        // Within rho of x the boundary's height falls by at most
        // |grad h| rho + kappaMax rho^2 / 2 and x rises by at most rho: the
        // ball is inside while that stays below the vertical gap.
        const Vec3f r = x - origin;
        const float u = dot(r, axisS), v = dot(r, axisT);
        const float gap = -(kappaS_perMm * u * u + kappaT_perMm * v * v) * 0.5f - dot(r, normal);
        if (gap <= 0.0f) return 0.0f;
        const float gradU = kappaS_perMm * u, gradV = kappaT_perMm * v;
        const float b = 1.0f + std::sqrt(gradU * gradU + gradV * gradV);
        const float kappaMax = std::max(kappaS_perMm, kappaT_perMm);
        return 2.0f * gap / (b + std::sqrt(b * b + 2.0f * kappaMax * gap));
    }
};

// The curvatures (in 1 / mean free path) at which curved controls are
// tabulated: 0 (flat that way), then 0.004 x 1.2^(step - 1), up to about 2.
constexpr int kCurvatureSteps = 36;
inline float curvature_perMfp(int step) {
    return step == 0 ? 0.0f : 0.004f * std::pow(1.2f, float(step - 1));
}
// The step nearest to kappa (1 / mfp) in ratio, or -1 beyond the table.
inline int nearestCurvatureStep(float kappa_perMfp) {
    if (kappa_perMfp < 0.004f / std::sqrt(1.2f)) return 0;
    int step = 1 + int(std::lround(std::log(kappa_perMfp / 0.004f) / std::log(1.2f)));
    return step < kCurvatureSteps ? step : -1;
}
// Index of the unordered pair of steps, 0 .. kCurvaturePairs - 1.
constexpr int kCurvaturePairs = kCurvatureSteps * (kCurvatureSteps + 1) / 2;
inline int curvaturePairIndex(int i, int j) {
    if (i < j) std::swap(i, j);
    return i * (i + 1) / 2 + j;
}

// The distances from the entry to the edge (mean free paths) at which wedge
// controls are tabulated: every quarter up to 4, then 6.25 % apart (to 61). The
// control's side plane is put at the tabulated distance nearest the real
// edge's (its mean is known there); the walks part where the two differ.
constexpr int kEdgeSteps = 61;
inline float edgeDistance_mfp(int step) {
    return step <= 16 ? 0.25f * float(step) : 4.0f * std::pow(1.0625f, float(step - 16));
}
// The step nearest to d_mfp, or -1 beyond the table.
inline int nearestEdgeStep(float d_mfp) {
    int step = d_mfp <= 4.0f ? int(std::lround(std::max(0.0f, d_mfp) * 4.0f))
                             : 16 + int(std::lround(std::log(d_mfp / 4.0f) / std::log(1.0625f)));
    return step < kEdgeSteps ? step : -1;
}

// A walk in the half-space: position, direction, throughput.
struct HalfSpaceWalker {
    Point3f x;
    Vec3f d;
    float weight = 1;
};

// Russian roulette as printpt plays it: survival min(cap, weight / threshold).
struct RouletteRule {
    float threshold = 0.25f, cap = 1.0f;
    float survival(float weight) const { return std::min(cap, weight / threshold); }
};

// Moves the walker by a free flight of the given optical depth: to a
// collision (weight x albedo; returns true) or to the nearer plane it
// reaches, where the
// transmitted part (1 - F) x weight is added to light and the walker is
// reflected with weight x F (returns false).
bool halfSpaceFlight(const HalfSpace& hs, HalfSpaceWalker& w, float opticalDepth, float& light);

// Light leaving the half-space from the walker's state on, with its own
// random numbers; `atCollision`: the walker has just collided (roulette and
// phase sampling are due). `collisions` counts the scattering events.
float finishHalfSpaceWalk(const HalfSpace& hs, HalfSpaceWalker w, bool atCollision, const RouletteRule& roulette,
                          float ballMinMfp, Rng& rng, int64_t& collisions);

struct HalfSpaceMean {
    double mean = 0, standardError = 0;
};

// The mean light a walk entering the half-space along -normal (at depth 0)
// brings back out, from `walks` independent walks seeded by `seed`; the same
// for any thread count.
HalfSpaceMean estimateHalfSpaceMean(const HalfSpace& hs, const RouletteRule& roulette, float ballMinMfp,
                                    int64_t walks, uint64_t seed);
// Means of control regions, each estimated once and kept for the life of
// this object. Each mean is a function of its key alone (the region, the
// walk's rules, the walks and the seed), so one cache serves the process
// (ofProcess): renders of the same materials, the prediction API's
// iterations among them, estimate each once. Thread-safe: a second thread
// asking for a mean being estimated waits for it, and different means are
// estimated side by side.
class HalfSpaceMeans {
public:
    static HalfSpaceMeans& ofProcess();
    HalfSpaceMean get(const HalfSpace& hs, const RouletteRule& roulette, float ballMinMfp, int64_t walks,
                      uint64_t seed);

private:
    using Key = std::tuple<float, float, float, float, float, float, float, float, float, float, int64_t, uint64_t>;
    std::mutex mutex_;
    std::map<Key, std::shared_future<HalfSpaceMean>> known_;
};

// The rotation taking unit vector a to unit vector b (a != -b), applied to v.
inline Vec3f rotateAtoB(const Vec3f& a, const Vec3f& b, const Vec3f& v) {
    Vec3f k = cross(a, b);
    float c = dot(a, b);
    return v * c + cross(k, v) + k * (dot(k, v) / (1.0f + c));
}

}  // namespace pl
