#include "integrators/volpath.h"

#include "core/fresnel.h"
#include "core/sampling.h"

namespace pl {

namespace {
// Reflection/refraction about the shading normal, falling back to the
// geometric normal when the shading normal would send the ray to the wrong side.
Vec3f reflectOnSide(const Vec3f& d, const SurfaceHit& hit) {
    Vec3f r = reflect(d, hit.ns);
    if (dot(r, hit.ng) * dot(d, hit.ng) > 0) r = reflect(d, hit.ng);
    return r;
}
}  // namespace

float VolPath::Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                  PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float Le = scene_.environment[channel];
    const float eps = geometry.rayEpsilon_mm();
    float beta = 1.0f;  // path throughput
    int64_t depth = 0;
    stats.paths += 1;

    for (;;) {
        // Outside: find the object or escape to the environment.
        auto entry = geometry.intersect(ray);
        if (!entry) return beta * Le;

        // Enter through the smooth dielectric: reflect with probability F.
        float cosIn = -dot(ray.d, entry->ns);
        float F = fresnelDielectric(cosIn, scene_.ior);
        if (rng.uniform() < F) {
            Vec3f r = reflectOnSide(ray.d, *entry);
            if (!options_.reentry) return beta * Le;  // leaves the object for good
            ray = spawnRay(entry->p, entry->ng, r, eps);
            continue;
        }
        auto t = refract(ray.d, entry->ns, scene_.ior);
        ray = spawnRay(entry->p, entry->ng, t ? *t : ray.d, eps);
        if (dot(ray.d, entry->ng) >= 0) ray.d = -entry->ng;  // shading-normal mishap

        // Inside: random walk until the path leaves the object or dies.
        for (;;) {
            auto exit = geometry.intersect(ray);
            if (!exit) {
                // Numerically outside an open mesh: count it and leave.
                stats.leaks += 1;
                return beta * Le;
            }
            FreeFlight ff = medium.sampleFreeFlight(ray, exit->t, channel, rng);
            if (ff.scattered) {
                // Real collision: absorb by throughput Russian roulette.
                stats.scatterEvents += 1;
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
                float t = std::max(0.0f, std::min(ff.t_mm, exit->t - eps));
                ray = {ray.at(t), ps.dOut};
                continue;
            }

            // Reached the boundary from inside: reflect with probability F
            // (always under total internal reflection), else leave.
            float cosOut = dot(ray.d, exit->ns);
            float Fout = fresnelDielectric(cosOut, 1.0f / scene_.ior);
            if (rng.uniform() < Fout) {
                ray = spawnRay(exit->p, exit->ng, reflectOnSide(ray.d, *exit), eps);
                if (dot(ray.d, exit->ng) >= 0) ray.d = -exit->ng;
                continue;
            }
            if (!options_.reentry) return beta * Le;
            auto tOut = refract(ray.d, -exit->ns, 1.0f / scene_.ior);
            Vec3f dOut = tOut ? *tOut : ray.d;
            if (dot(dOut, exit->ng) <= 0) dOut = exit->ng;
            ray = spawnRay(exit->p, exit->ng, dOut, eps);
            break;  // outside again
        }
    }
}

}  // namespace pl
