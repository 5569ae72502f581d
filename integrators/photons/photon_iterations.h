// The pass of a progressive photon estimator (bre, pp3d, pb2d, bb1d, combined): each
// sample is one iteration, whose photons are traced first and then serve
// every pixel's camera ray. A pixel's samples whose camera rays enter at
// one label are pooled, as volpath's are (poolByEntry).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "core/film.h"
#include "integrators/integrator.h"

namespace pl {

// makeMap(sample): the iteration's photons; sampleOf(map, ray, entry,
// medium, rng, stats): a pixel's sample from them, where entry is where the
// camera ray meets the object (or none) and rng has drawn the ray's two
// numbers. Separate channel passes only.
template <class MakeMap, class SampleOf>
void renderPhotonIterations(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress,
                            const std::string& estimator, MakeMap&& makeMap, SampleOf&& sampleOf) {
    if (pass.channel < 0) throw std::logic_error(estimator + ": one channel per pass only");
    const PixelShare& share = pass.share;
    const Scene& scene = pass.scene;
    for (uint32_t s = pass.firstSample; s < pass.firstSample + pass.count; ++s) {
        const auto map = makeMap(s);
        renderPixelTiles(pass, stats, progress, 1, [&](size_t i, LabelMedium::Tracker& medium, PathStats& tileStats) {
            const size_t p = share.pixel(i);
            Rng rng = Rng::forPath(pass.seed, p, s, uint64_t(pass.channel));
            const float u0 = rng.uniform(), u1 = rng.uniform();
            const Ray ray = pass.sensor.generateRay(p, u0, u1);
            const std::optional<SurfaceHit> entry = scene.geometry->intersect(ray);
            ChannelSample sample = sampleOf(map, ray, entry, medium, rng, tileStats);
            poolByEntry(sample, scene, ray, entry, pass.channel, medium);
            film.add(share.filmPixel(i), pass.channel, sample);
        });
    }
}

}  // namespace pl
