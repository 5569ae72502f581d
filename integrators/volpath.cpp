#include "integrators/volpath.h"

#include "core/fresnel.h"
#include "core/sampling.h"

namespace pl {

float VolPath::Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                  PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float Le = scene_.environment[channel];
    const float lift = geometry.surfaceLift_mm();
    float beta = 1.0f;          // path throughput
    int64_t depth = 0;          // scattering events
    int64_t bounces = 0;        // boundary events since the last scattering event
    bool spawnedInside = false; // only for counting numerical leaks
    stats.paths += 1;

    for (;;) {
        // Which side the ray is on follows from the boundary it reaches
        // next, never from a remembered state: a ray that round-off put on
        // the other side stays consistent.
        auto hit = geometry.intersect(ray);
        if (!hit) {
            if (spawnedInside) stats.leaks += 1;
            return beta * Le;  // escapes to the environment
        }
        bool fromInside = dot(ray.d, hit->ng) > 0;

        if (fromInside) {
            // Medium: delta tracking up to the boundary.
            FreeFlight ff = medium.sampleFreeFlight(ray, hit->t, channel, rng);
            if (ff.scattered) {
                // Real collision: absorb by throughput Russian roulette.
                stats.scatterEvents += 1;
                bounces = 0;
                beta *= lut.albedo[ff.label];
                if (beta < 1.0f) {
                    if (rng.uniform() >= beta) return 0.0f;
                    beta = 1.0f;
                }
                if (options_.maxDepth >= 0 && ++depth > options_.maxDepth) return 0.0f;
                float u0 = rng.uniform(), u1 = rng.uniform();
                PhaseSample ps = sampleHG(ray.d, lut.g[ff.label], u0, u1);
                // Keep the vertex strictly inside: a collision within float
                // round-off of the boundary could otherwise land outside.
                // (By the surface lift only: a rayEpsilon here would move
                // collisions a mean free path deep at sigma_t 1e4/mm.)
                float cosine = std::max(std::abs(dot(ray.d, hit->ng)), 1.0f / 16.0f);
                float t = std::max(0.0f, std::min(ff.t_mm, hit->t - lift / cosine));
                ray = {ray.at(t), ps.dOut};
                spawnedInside = true;
                continue;
            }
        }
        // Light that only ever meets the boundary (total internal reflection
        // in a lossless region) would bounce forever: give up after a very
        // long run without scattering; it never reaches the environment.
        if (++bounces > kMaxBoundaryBounces) {
            stats.trapped += 1;
            return 0.0f;
        }

        // Smooth dielectric: reflect with probability F (1 under total
        // internal reflection), else refract to the other side.
        float eta = fromInside ? 1.0f / scene_.ior : scene_.ior;
        Vec3f n = fromInside ? -hit->ns : hit->ns;  // facing against the ray
        float F = fresnelDielectric(-dot(ray.d, n), eta);
        bool reflected = rng.uniform() < F;
        bool nowOutside = fromInside != reflected;
        // Without re-entry, light that leaves the object is done.
        if (nowOutside && !options_.reentry) return beta * Le;
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
    }
}

}  // namespace pl
