#include "integrators/printpt.h"

#include "core/fresnel.h"
#include "core/sampling.h"

namespace pl {

float PrintPt::Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                  PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const float Le = scene_.environment[channel];
    auto entry = geometry.intersect(ray);
    if (!entry) {
        stats.paths += 1;
        return Le;
    }
    // The camera ray arrives from outside: Fresnel at the entry.
    Vec3f n = dot(ray.d, entry->ng) < 0 ? entry->ns : -entry->ns;
    float F = fresnelDielectric(-dot(ray.d, n), scene_.ior);
    float L = 0.0f, beta = 1.0f;
    if (options_.fresnelWeighting) {
        // Reflected light leaves at once (no re-entry): it is Le exactly.
        L += F * Le;
        beta = 1.0f - F;
    } else if (rng.uniform() < F) {
        stats.paths += 1;
        return Le;
    }
    auto t = refract(ray.d, n, scene_.ior);
    Vec3f d = t ? *t : ray.d;
    if (dot(d, entry->ng) >= 0) d = -entry->ng;
    Ray inside = spawnRay(entry->p, entry->ng, d, geometry.rayEpsilon_mm());

    // Branching: k walks share the camera ray and the entry.
    const int k = std::max(1, options_.branches);
    float sum = 0.0f;
    for (int b = 0; b < k; ++b) sum += walk(inside, channel, medium, rng, stats);
    return L + beta * sum / float(k);
}

float PrintPt::walk(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                    PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float Le = scene_.environment[channel];
    const float eps = geometry.rayEpsilon_mm();
    const float etaOut = 1.0f / scene_.ior;
    float beta = 1.0f, L = 0.0f;
    int64_t bounces = 0;
    stats.paths += 1;

    for (;;) {
        // Distance to the next real collision, then the boundary up to it.
        FreeFlight ff;
        std::optional<SurfaceHit> hit;
        if (options_.mediumFirst) {
            ff = medium.sampleFreeFlight(ray, 1e30f, channel, rng);
            hit = geometry.intersect(ray, ff.scattered ? ff.t_mm : 1e30f);
        } else {
            hit = geometry.intersect(ray);
            if (hit) ff = medium.sampleFreeFlight(ray, hit->t, channel, rng);
        }
        if (!hit && !(options_.mediumFirst && ff.scattered)) {
            stats.leaks += 1;  // left an open mesh: count it, treat as leaving
            return L + beta * Le;
        }
        // Medium first: the boundary query only reached the collision, so a
        // hit means the boundary comes first. Geometry first: the tracking
        // only reached the boundary, so a collision means it comes first.
        bool boundaryFirst = options_.mediumFirst ? hit.has_value() : !ff.scattered;
        if (boundaryFirst && dot(ray.d, hit->ng) < 0) {
            // Round-off put the ray outside, facing the surface: it leaves.
            stats.leaks += 1;
            return L + beta * Le;
        }

        if (!boundaryFirst) {
            // Scattering: weight by the albedo, Russian roulette, phase sampling.
            stats.scatterEvents += 1;
            bounces = 0;
            beta *= lut.albedo[ff.label];
            float q = std::min(options_.rrCap, beta);
            if (!(rng.uniform() < q)) return L;
            beta /= q;
            float u0 = rng.uniform(), u1 = rng.uniform();
            PhaseSample ps = sampleHG(ray.d, lut.g[ff.label], u0, u1);
            ray = {ray.at(ff.t_mm), ps.dOut};
            continue;
        }

        // Boundary from inside.
        if (++bounces > kMaxBoundaryBounces) {
            stats.trapped += 1;
            return L;
        }
        Vec3f n = -hit->ns;  // facing against the ray
        float F = fresnelDielectric(-dot(ray.d, n), etaOut);
        if (options_.fresnelWeighting) {
            L += beta * (1.0f - F) * Le;  // the transmitted part leaves for good
            beta *= F;
            if (beta <= 0.0f) return L;
        } else if (!(rng.uniform() < F)) {
            return L + beta * Le;
        }
        Vec3f r = reflect(ray.d, hit->ns);
        if (dot(r, hit->ng) >= 0) r = reflect(ray.d, hit->ng);
        if (dot(r, hit->ng) >= 0) r = -hit->ng;
        ray = spawnRay(hit->p, hit->ng, r, eps);
    }
}

}  // namespace pl
