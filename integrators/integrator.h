// What the render driver asks of an estimator: the radiance arriving along
// a camera ray, in one colour channel or in all three, from one path (or a
// few branches).
#pragma once

#include <cstdint>
#include <vector>

#include "core/film.h"
#include "core/fresnel.h"
#include "core/path_stats.h"
#include "core/rng.h"
#include "integrators/channel_paths.h"
#include "scene/scene.h"

namespace pl {

class Sensor;

// Boundary events in a row, without scattering, after which a path counts
// as trapped (lossless total internal reflection) and ends.
constexpr int64_t kMaxBoundaryBounces = 10000000;

// Mirror reflection about the shading normal, falling back to the geometric
// normal when the shading normal would send the ray through the surface.
inline Vec3f reflectOnSide(const Vec3f& d, const SurfaceHit& hit) {
    Vec3f r = reflect(d, hit.ns);
    if (dot(r, hit.ng) * dot(d, hit.ng) > 0) r = reflect(d, hit.ng);
    return r;
}

// The free flight from ray.o, counting the medium a ray spawned into the
// object has between the surface and its origin (Ray::mediumBefore_mm): a
// collision there happens at the origin (surely inside; it moves by a few
// float ulps), and none is lost. track(ray, tMax) samples the flight.
template <class Track>
FreeFlight flightFromSurface(const Ray& ray, float tMax, Track&& track) {
    if (!(ray.mediumBefore_mm > 0.0f)) return track(ray, tMax);
    const Ray fromSurface{ray.o - ray.d * ray.mediumBefore_mm, ray.d};
    FreeFlight ff = track(fromSurface, tMax + ray.mediumBefore_mm);
    if (ff.scattered) ff.t_mm = std::max(0.0f, ff.t_mm - ray.mediumBefore_mm);
    return ff;
}

// The ray reflected back inside at an inner boundary hit (straight in
// along the geometric normal where the mirror direction would leave).
inline Ray reflectedInside(const Geometry& geometry, const Vec3f& d, const SurfaceHit& hit) {
    Vec3f r = reflectOnSide(d, hit);
    if (dot(r, hit.ng) >= 0) r = -hit.ng;
    return geometry.spawnRay(hit.p, hit.ng, r);
}

// The refracted ray that enters the object at `entry`, a hit of the camera
// ray from outside (straight in along the geometric normal where
// refraction fails).
inline Ray enteringRay(const Scene& scene, const Ray& camera, const SurfaceHit& entry) {
    Vec3f n = dot(camera.d, entry.ng) < 0 ? entry.ns : -entry.ns;
    auto t = refract(camera.d, n, scene.ior);
    Vec3f d = t ? *t : camera.d;
    if (dot(d, entry.ng) >= 0) d = -entry.ng;
    return scene.geometry->spawnRay(entry.p, entry.ng, d);
}

// The key under which samples without a control are pooled where a
// pixel's samples are all equal (ChannelSample::poolWhereFlat): the
// channel and the label just inside the entry. Above every control's key.
inline int32_t entryPoolKey(int channel, Label entryLabel) {
    return (int32_t(1) << 24) + int32_t(channel) * 256 + int32_t(entryLabel);
}
// The same for a part of a sample that must not pool with whole samples
// (light tracing's camera side, whose light side is estimated apart).
inline int32_t entryPoolKeyOfPart(int channel, Label entryLabel) {
    return (int32_t(1) << 25) + int32_t(channel) * 256 + int32_t(entryLabel);
}

// The path an estimator traces for one channel, or for all three with the
// chosen sampling: trace(path) returns the radiance it gathers.
template <class Trace>
auto traceOneChannel(const Scene& scene, int channel, Trace&& trace) {
    return trace(SingleChannelPath{&scene.medium->lut(channel), channel, scene.environment[channel]});
}
template <class Trace>
RGB traceThreeChannels(const Scene& scene, ChannelSampling sampling, int hero, Trace&& trace) {
    if (sampling == ChannelSampling::Spectral) return trace(SpectralPath{&scene.medium->luts(), scene.environment});
    return trace(HeroPath{&scene.medium->luts(), scene.environment, hero});
}

// One block of light paths' scores per pixel. The block's particles are
// independent, so the variance of a pixel's score is the sum of each
// particle's, which the sum of the particles' squared scores (each
// particle's whole score in the pixel, squared) estimates, without bias for
// particles that enter anywhere with one density and conservatively where
// entries are stratified (it also counts each particle's mean squared).
// It rests on every particle that reached the pixel, not on a few blocks.
struct LightBlockScores {
    std::vector<double> score, scoreSq;
    void assign(size_t pixels) {
        score.assign(pixels, 0.0);
        scoreSq.assign(pixels, 0.0);
    }
};

class Integrator {
public:
    virtual ~Integrator() = default;
    // Radiance arriving along -ray.d at ray.o (a point outside the object).
    virtual ChannelSample Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                             PathStats& stats) const = 0;
    // All three channels from one path: Hero (the driver draws the hero
    // channel uniformly) or Spectral sampling (channel_paths.h).
    virtual RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
                      PathStats& stats) const = 0;
    // Called once before rendering the sensor's pixels in these channels
    // (single-channel passes): a chance to look at all entries first.
    virtual void preprocess(const Sensor& /*sensor*/, const std::vector<int>& /*channels*/) {}

    // Estimators that also trace paths from the light (lighttrace) score,
    // for sample `sample` of a channel's pass, one block of light paths into
    // every pixel: block.score[p] (zeroed by the caller) is added to pixel
    // p's camera sample, and block.scoreSq[p], the block's own estimate of
    // that score's variance, goes with it (LightBlockScores).
    virtual bool scoresLightPaths() const { return false; }
    virtual void scoreLightBlock(int /*channel*/, uint32_t /*sample*/, LightBlockScores& /*block*/,
                                 PathStats& /*stats*/) const {}
    // With light paths: the camera's share of pixel p's sample, what the
    // light paths do not score there.
    virtual ChannelSample cameraSide(size_t /*pixel*/, Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                                     PathStats& stats) const {
        return Li(ray, channel, medium, rng, stats);
    }
};

}  // namespace pl
