// The render driver: makes the integrator, opens the film's channels, has
// the integrator render each pass (Integrator::render) and settles each
// channel as its pass ends; across MPI ranks it shares out the pixels and
// gathers the film. All three channels come from one path per sample
// unless channelSampling is Separate (or the render asks for fewer
// channels, or the integrator cannot): then one pass per channel.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/film.h"
#include "core/sensors.h"
#include "integrators/integrator.h"
#include "integrators/render_settings.h"
#include "runtime/pixel_share.h"
#include "scene/scene.h"

namespace pl {

struct RenderResult {
    Film film;
    PathStats stats{};
    double seconds = 0;
    // Per channel, the time of its own pass (separate passes only; zero
    // for three channels from one path).
    RGB passSeconds{0, 0, 0};
    // Across MPI ranks, on rank 0: each rank's share of the render's time
    // spent communicating, waiting for the others included (the load
    // imbalance and the cost of the exchange).
    std::vector<double> communicationShare{};
};

// acrossRanks: every MPI rank renders its share of the pixels and rank 0
// gathers the result (the others return a film of no pixels).
RenderResult render(const Scene& scene, const Sensor& sensor, const RenderSettings& settings, bool acrossRanks = false);

// The integrator the settings name, made for this scene and sensor and
// ready to render them (printpt has surveyed the sensor): it lives as long
// as they do, across rounds of renderSamples.
std::unique_ptr<Integrator> makeIntegrator(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

// True if the render takes all three channels from one path per sample.
bool rendersChannelsInOnePass(const RenderSettings& settings);

// Adds samples [firstSample, firstSample + count) of the share's pixels to
// result.film, for every channel of the settings. Sample s of pixel p is
// the same path whichever call (or rank) renders it, so a render in rounds
// or across ranks gives the bits of a render in one go. lastSamples: no
// call adds more, so each channel's pass is settled as soon as it ends
// (Film::settleChannel; in one process): one channel's accumulators alive
// at a time, and the same values as pooling them all at the end.
// footprints: where each pixel's paths went is added there (an estimator
// whose capabilities say recordsFootprints).
void renderSamples(const Integrator& integrator, const Scene& scene, const Sensor& sensor,
                   const RenderSettings& settings, const PixelShare& share, uint32_t firstSample, uint32_t count,
                   RenderResult& result, bool lastSamples = false, PathFootprints* footprints = nullptr,
                   const CoupledSampling* coupled = nullptr);

// A share across MPI ranks: rank 0's film receives every rank's pixels
// (and pools the errors over them all, with the sensor's neighbourhoods;
// a film of the share alone, settled already: a whole film, settled);
// the returned statistics are summed over the ranks on rank 0 (this
// rank's elsewhere). Collective.
// Otherwise: the result's statistics.
PathStats gatherShares(RenderResult& result, const PixelShare& share, const Sensor& sensor);

}  // namespace pl
