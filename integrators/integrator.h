// What the render driver asks of an estimator: the samples of one pass,
// rendered as the estimator needs, and what it declares of itself. Most
// estimators are per-pixel: the radiance arriving along a camera ray, in one
// colour channel or in all three, from one path (or a few branches).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/estimator_parameters.h"
#include "core/film.h"
#include "core/fresnel.h"
#include "core/path_stats.h"
#include "core/rng.h"
#include "integrators/channel_paths.h"
#include "integrators/coupled_samples.h"
#include "integrators/path_footprints.h"
#include "runtime/pixel_share.h"
#include "runtime/interrupt.h"
#include "runtime/progress.h"
#include "runtime/scheduler.h"
#include "scene/scene.h"

namespace pl {

class Sensor;
struct RenderSettings;

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
// Keys a sample without a control by the label its camera ray enters, so
// that a pixel whose samples are all equal takes the variance pooled over
// that key (Film, ChannelSample::poolWhereFlat): a walk's sample is Le or
// 0 (or a roulette weight), a kernel's 0 where no photon came near, and a
// pixel's few equal samples' spread says nothing. `entry`: the camera
// ray's first hit.
inline void poolByEntry(ChannelSample& sample, const Scene& scene, const Ray& ray,
                        const std::optional<SurfaceHit>& entry, int channel, LabelMedium::Tracker& medium) {
    if (!entry || !(dot(ray.d, entry->ng) < 0)) return;
    const Point3f inside = entry->p - entry->ng * scene.geometry->rayEpsilon_mm();
    sample.poolKey = entryPoolKey(channel, medium.labelAt(scene.medium->voxelAt(inside)));
    sample.residual = sample.value;
    sample.poolWhereFlat = true;
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

// What an estimator declares of itself for a render's settings, before it
// is made: the render driver, the scene loader and the memory check ask
// this rather than the estimator's name.
struct IntegratorCapabilities {
    SceneNeeds needs;  // what the scene must load
    // It can take all three channels from one path (else a pass per channel).
    bool threeChannelsInOnePath = false;
    // Every sample of a pixel is the same (a deterministic predictor): one
    // sample says all, and its error is bias, which more time does not
    // reduce.
    bool deterministic = false;
    // A sample's light paths score into every pixel: across MPI ranks each
    // rank renders a fixed share of the pixels in step with the others
    // (no work stealing) and its film holds that share alone.
    bool lightPathsServeEveryPixel = false;
    // Its paths read the labels through the tracker's free flights and
    // labelAt alone, and it adds where they went to RenderPass::footprints
    // (the prediction API then keeps the samples a change cannot reach).
    bool recordsFootprints = false;
    // The sensors it takes (the scene parser refuses others).
    SensorKinds sensors = kEverySensorKind;
};

// One pass of a render: samples [firstSample, firstSample + count) of the
// share's pixels in one channel, or in all three (channel -1, sampled as
// channelSampling says). Sample s of pixel p is the same path whichever
// call (or rank) renders it.
struct RenderPass {
    const Scene& scene;
    const Sensor& sensor;
    const PixelShare& share;
    uint32_t firstSample, count;
    int channel;
    uint64_t seed;
    Majorants majorants;
    ChannelSampling channelSampling;
    // Where each pixel's paths went is added here, if wanted (estimators
    // whose capabilities say recordsFootprints).
    PathFootprints* footprints = nullptr;
    // Pairs of samples with the previous labels, if wanted (single-channel
    // passes of estimators that record footprints).
    const CoupledSampling* coupled = nullptr;
};

// An estimator: it renders passes, each in the way it needs (one camera
// path per pixel sample, or light paths shared by every pixel). Each class
// also declares, as static members the registry reads (render/registry.h):
//   static std::vector<ParameterInfo> parameters();  (the render keys it reads)
//   static IntegratorCapabilities capabilities(const RenderSettings&);
//   static std::unique_ptr<Integrator> create(const Scene&, const Sensor&,
//       const RenderSettings&);
// and, if some settings cannot run, refusal (inherited: none). Each reads
// its options from RenderSettings::parameters (readOptions) itself.
class Integrator {
public:
    virtual ~Integrator() = default;
    // Called once before rendering the sensor's pixels in these channels
    // (single-channel passes): a chance to look at all entries first.
    virtual void preprocess(const Sensor& /*sensor*/, const std::vector<int>& /*channels*/) {}
    // Adds the pass's samples of each pixel of its share to the film (at
    // share.filmPixel), what its paths did to stats, and advances progress
    // by each pixel's samples as they are done. Stops early on Ctrl-C
    // (runtime/interrupt.h). Across ranks with light paths, collective.
    virtual void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const = 0;

    // Why these settings cannot run (one line, naming the scene key), or "".
    static std::string refusal(const RenderSettings& /*settings*/) { return {}; }
    // The render keys it reads (inherited: none).
    static std::vector<ParameterInfo> parameters() { return {}; }
};

// The pass's pixels in tiles on the scheduler, each tile by one thread:
// perTile(begin, end, tileStats) renders positions [begin, end) of the
// share with the tile's path statistics (added to `stats` as the tile
// ends) and returns false if Ctrl-C stopped it (checked before each
// pixel). Progress advances by unitsPerPixel a pixel of a finished tile.
template <class PerTile>
void renderTiles(const RenderPass& pass, PathStats& stats, ProgressBar& progress, uint64_t unitsPerPixel,
                 PerTile&& perTile) {
    std::mutex statsMutex;
    parallelForTiles(pass.share.size(pass.sensor.pixelCount()), 64, [&](size_t begin, size_t end) {
        PathStats tileStats;
        if (!perTile(begin, end, tileStats)) return;
        progress.advance((end - begin) * unitsPerPixel);
        std::lock_guard<std::mutex> lock(statsMutex);
        stats += tileStats;
    });
}

// The same pixel by pixel: perPixel(i, medium, tileStats) for position i
// of the share, with the tile's tracker (perPixel returns early to end
// its own at Ctrl-C).
template <class PerPixel>
void renderPixelTiles(const RenderPass& pass, PathStats& stats, ProgressBar& progress, uint64_t unitsPerPixel,
                      PerPixel&& perPixel) {
    renderTiles(pass, stats, progress, unitsPerPixel, [&](size_t begin, size_t end, PathStats& tileStats) {
        LabelMedium::Tracker medium(*pass.scene.medium, pass.majorants);
        for (size_t i = begin; i < end; ++i) {
            if (interruptRequested()) return false;
            perPixel(i, medium, tileStats);
        }
        return true;
    });
}

// The estimators that render each pixel sample with one camera path, alone
// (volpath, printpt, the deterministic predictors): render is one loop over
// tiles of pixels, samples in order (integrator.cpp), which asks Li or
// LiRGB for each sample.
class PixelIntegrator : public Integrator {
public:
    // Radiance arriving along -ray.d at ray.o (a point outside the object).
    virtual ChannelSample Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                             PathStats& stats) const = 0;
    // All three channels from one path: Hero (the driver draws the hero
    // channel uniformly) or Spectral sampling (channel_paths.h).
    virtual RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
                      PathStats& stats) const = 0;
    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const final;

private:
    // The pass's samples of pixel p (position i of the share), in order.
    void renderPixel(const RenderPass& pass, Film& film, size_t i, size_t p, LabelMedium::Tracker& medium,
                     PathStats& tileStats) const;
    // The same in pairs (RenderPass::coupled): previous labels through `before`.
    void renderPixelPairs(const RenderPass& pass, Film& film, size_t i, size_t p, LabelMedium::Tracker& medium,
                          LabelMedium::Tracker& before, PathStats& tileStats) const;
};

// The refusal of an estimator that traces no re-entry, for a scene that
// asks for it.
std::string refusalWithoutReentry(const char* name, const RenderSettings& settings);

}  // namespace pl
