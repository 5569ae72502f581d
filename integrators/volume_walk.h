// The volumetric random walk volpath traces, written once: delta tracking
// for distances, HG phase sampling, Fresnel choosing reflection or
// refraction at random, throughput Russian roulette. Light tracing walks
// its particles with it and scores through two hooks:
//  - onFlight(ray, tEnd_mm, path): every flight through the medium, from
//    ray.o to ray.at(tEnd_mm) (a real collision or the boundary; the ray
//    starts at the surface where the walk spawned it there, so the medium
//    before a spawned ray's origin counts), with the throughput the
//    particle carries along it;
//  - onCollision(y, dIn, label, path): every real collision, after the
//    albedo and before the roulette. A hook that returns a bool ends the
//    path where it returns true (it estimated the rest itself: pb2d's
//    gather).
#pragma once

#include <cstdint>
#include <optional>
#include <type_traits>

#include "core/fresnel.h"
#include "core/sampling.h"
#include "integrators/integrator.h"

namespace pl {

struct VolPathOptions {
    int64_t maxDepth = -1; // scattering events per path; < 0: unlimited (unbiased)
    // After a real collision, sample the flight up to the surface clearance
    // (a lower bound of the distance to the boundary) before asking Embree:
    // a collision within it needs no boundary query. False: every flight
    // starts with one (the textbook order; the same estimate, other bits).
    bool clearanceFirst = true;
};

// Walks `ray` (from outside, or spawned inside) and returns the
// environment light the path gathers. firstHit: where the caller already
// asked the geometry along `ray` (the answer, a hit or none), not asked again.
template <class Path, class OnFlight, class OnCollision>
typename Path::Value walkVolume(const Scene& scene, const VolPathOptions& options, bool reentry, Ray ray, Path& path,
                                LabelMedium::Tracker& medium, Rng& rng, PathStats& stats, OnFlight&& onFlight,
                                OnCollision&& onCollision, const std::optional<SurfaceHit>* firstHit = nullptr) {
    const Geometry& geometry = *scene.geometry;
    const float lift = geometry.surfaceLift_mm();
    typename Path::Value L{};   // radiance gathered (only at the end of the path)
    int64_t depth = 0;          // scattering events
    int64_t bounces = 0;        // boundary events since the last scattering event
    bool spawnedInside = false; // only for counting numerical leaks
    bool afterCollision = false; // the ray starts at a real collision, strictly inside
    auto track = [&](const Ray& r, float tMax) { return path.track(medium, r, tMax, rng); };
    stats.paths += 1;

    for (;;) {
        // After a collision: the flight up to the clearance first (less the
        // lift, for round-off). A collision there is inside for sure.
        float cleared_mm = 0.0f;
        FreeFlight ff;
        if (afterCollision && options.clearanceFirst && scene.clearance) {
            cleared_mm = std::max(0.0f, scene.clearance->at(ray.o) - lift);
            if (cleared_mm > 0.0f) ff = track(ray, cleared_mm);
        }
        // Otherwise the boundary: which side the ray is on follows from the
        // boundary it reaches next, never from a remembered state (a ray
        // that round-off put on the other side stays consistent).
        std::optional<SurfaceHit> hit;
        if (!ff.scattered) {
            hit = firstHit ? *firstHit : geometry.intersect(ray);
            firstHit = nullptr;
            if (!hit && spawnedInside) hit = geometry.exitBeforeTMin(ray);
            if (!hit) {
                if (spawnedInside) stats.leaks += 1;
                path.addLight(L, 1.0f);  // escapes to the environment
                return L;
            }
        }
        bool fromInside = !hit || dot(ray.d, hit->ng) > 0;

        if (fromInside) {
            // Medium: delta tracking up to the boundary (the rest of it
            // beyond the cleared part: free flights are memoryless).
            if (hit && cleared_mm > 0.0f) {
                ff = track(Ray{ray.at(cleared_mm), ray.d}, std::max(0.0f, hit->t - cleared_mm));
                if (ff.scattered) ff.t_mm += cleared_mm;
            } else if (hit) {
                ff = flightFromSurface(ray, hit->t, track);
            }
            // The flight as the hook sees it: from the surface for a ray the
            // walk spawned there (flightFromSurface tracks that stretch too).
            const Ray flight{ray.o - ray.d * ray.mediumBefore_mm, ray.d};
            if (!ff.scattered) onFlight(flight, hit->t + ray.mediumBefore_mm, path);
            if (ff.scattered) {
                // Keep the vertex strictly inside: a collision within float
                // round-off of the boundary could otherwise land outside.
                // (By the surface lift only: a rayEpsilon here would move
                // collisions a mean free path deep at sigma_t 1e4/mm.)
                float t = ff.t_mm;
                if (hit) {
                    const float cosine = std::max(std::abs(dot(ray.d, hit->ng)), 1.0f / 16.0f);
                    t = std::max(0.0f, std::min(ff.t_mm, hit->t - lift / cosine));
                }
                onFlight(flight, t + ray.mediumBefore_mm, path);
                // Real collision: absorb by throughput Russian roulette.
                stats.scatterEvents += 1;
                bounces = 0;
                path.collide(ff.label);
                const Point3f y = ray.at(t);
                if constexpr (std::is_same_v<decltype(onCollision(y, ray.d, ff.label, path)), bool>) {
                    if (onCollision(y, ray.d, ff.label, path)) return L;
                } else {
                    onCollision(y, ray.d, ff.label, path);
                }
                float q = path.rouletteValue();
                if (q < 1.0f) {
                    if (!(rng.uniform() < q)) return L;
                    path.scale(1.0f / q);
                }
                if (options.maxDepth >= 0 && ++depth > options.maxDepth) return L;
                Vec3f dOut = path.samplePhase(ff.label, ray.d, rng);
                ray = {y, dOut};
                spawnedInside = true;
                afterCollision = true;
                continue;
            }
        }
        // Light that only ever meets the boundary (total internal reflection
        // in a lossless region) would bounce forever: give up after a very
        // long run without scattering; it never reaches the environment.
        if (++bounces > kMaxBoundaryBounces) {
            stats.trapped += 1;
            return L;
        }

        // Smooth dielectric: reflect with probability F (1 under total
        // internal reflection), else refract to the other side.
        float eta = fromInside ? 1.0f / scene.ior : scene.ior;
        Vec3f n = fromInside ? -hit->ns : hit->ns;  // facing against the ray
        float F = fresnelDielectric(-dot(ray.d, n), eta);
        bool reflected = rng.uniform() < F;
        bool nowOutside = fromInside != reflected;
        // Without re-entry, light that leaves the object is done.
        if (nowOutside && !reentry) {
            path.addLight(L, 1.0f);
            return L;
        }
        Vec3f d;
        if (reflected) {
            d = reflectOnSide(ray.d, *hit);
        } else {
            auto t = refract(ray.d, n, eta);
            d = t ? *t : ray.d;
        }
        // Shading normals must not send the ray to the wrong side.
        float side = nowOutside ? 1.0f : -1.0f;
        if (dot(d, hit->ng) * side <= 0) d = hit->ng * side;
        ray = geometry.spawnRay(hit->p, hit->ng, d);
        spawnedInside = !nowOutside;
        afterCollision = false;
    }
}

// A particle from the environment entering at `entry`: a cosine-weighted
// direction from outside (pdf cos / pi, which a particle power of Le pi A
// cancels), the Fresnel transmission in as its path weight, then the walk
// inside (no re-entry). Takes two uniform numbers before the walk's.
template <class OnFlight, class OnCollision>
void walkParticleIn(const Scene& scene, const VolPathOptions& options, const SurfaceHit& entry, SingleChannelPath& path,
                    LabelMedium::Tracker& medium, Rng& rng, PathStats& stats, OnFlight&& onFlight,
                    OnCollision&& onCollision) {
    const float w0 = rng.uniform(), w1 = rng.uniform();
    const Vec3f d = -Frame(entry.ng).toWorld(sampleCosineHemisphere(w0, w1).d);
    path.beta = 1.0f - fresnelDielectric(-dot(d, entry.ns), scene.ior);
    if (!(path.beta > 0.0f)) return;
    const Ray ray = enteringRay(scene, Ray{entry.p - d, d}, entry);
    walkVolume(scene, options, /*reentry=*/false, ray, path, medium, rng, stats, onFlight, onCollision);
}

}  // namespace pl
