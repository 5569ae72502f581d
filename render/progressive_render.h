// A render that stops when it is good enough: rounds of 1, 1, 2, 4, ...
// samples per pixel (each sample the path a one-go render takes, so N
// samples in rounds are the bits of `--spp N`) until the settings' spp
// (the most), their time budget or their target error, whichever comes
// first. Previews refine on screen (the caller writes the image after each
// round) and stop at a noise level a person chose.
#pragma once

#include <functional>
#include <string>

#include "render/render.h"

namespace pl {

struct RadianceImage;

// Whole-image quality: per channel the median over pixels of a pixel's
// relative error, the largest over the channels. Self-variance (no ref):
// the pixel's standard error over its mean; against a reference: |mean -
// ref| over ref, divided by 0.6745 (the median of |N(0,1)|), so that both
// estimate the same for an unbiased estimator. A dark pixel (mean or
// reference <= 0) counts as infinitely far. skipExact: pixels whose
// estimate has no variance (background that sees the environment) are
// left out (previews), under self-variance.
double medianRelativeError(const Film& film, const Sensor& sensor, const RadianceImage* ref, bool skipExact = false);

struct ProgressiveRender {
    RenderResult result;
    uint32_t spp = 0;                  // samples per pixel rendered
    double medianRelativeError = 0;    // of the pixels whose estimate varies
    std::string stoppedBy;             // "spp", "time" or "target error"
};

// onRound(result, spp) after each round (across ranks its statistics
// are rank 0's own until the end; the film is whole). acrossRanks: every MPI rank
// renders its share of the pixels; rank 0 gathers them after each round,
// calls onRound and decides the next round for all (the other ranks
// return their share, without calling onRound).
ProgressiveRender renderProgressively(const Scene& scene, const Sensor& sensor, const RenderSettings& settings,
                                      const std::function<void(const RenderResult&, uint32_t)>& onRound,
                                      bool acrossRanks = false);

}  // namespace pl
