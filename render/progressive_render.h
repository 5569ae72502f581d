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
// left out (previews).
double medianRelativeError(const Film& film, const Sensor& sensor, const RadianceImage* ref, bool skipExact = false);

// Rounds of samples with one integrator, made once (its census and means
// serve every round): each round renders some samples of some pixels into
// one film, sample s of pixel p the same path in any round, so rounds give
// the bits of a render in one go. Across MPI ranks each rank renders its
// share of a round's pixels and rank 0 gathers them after each round (and
// sends the whole film to every rank, if asked: the ranks then decide
// alike). The progressive render and the prediction API's adaptive
// sampling decide their rounds with it.
class RenderRounds {
public:
    // acrossRanks: every rank makes the same calls, in step.
    RenderRounds(const Scene& scene, const Sensor& sensor, const RenderSettings& settings, bool acrossRanks,
                 bool filmOnEveryRank = false);
    ~RenderRounds();
    // Samples [first, first + count) of these pixels (all: none). Rank 0's
    // film and statistics hold the rounds so far (every rank's, with
    // filmOnEveryRank); a failure on any rank stops them all.
    void render(const std::vector<uint32_t>* pixels, uint32_t first, uint32_t count);
    // Where each pixel's paths go in the rounds from now on is added here
    // (in one process; the estimator must record footprints).
    void recordFootprints(PathFootprints* footprints) { footprints_ = footprints; }
    // The rounds from now on render pairs of samples (CoupledSampling).
    void renderPairs(const CoupledSampling* coupled) { coupled_ = coupled; }
    RenderResult& result() { return result_; }
    // The statistics over the ranks (the result's are this rank's own).
    const PathStats& stats() const { return stats_; }
    bool acrossRanks() const { return share_.acrossRanks; }

private:
    const Scene& scene_;
    const Sensor& sensor_;
    const RenderSettings& settings_;
    const PixelShare share_;
    const bool filmOnEveryRank_;
    std::unique_ptr<Integrator> integrator_;
    RenderResult result_;
    PathStats stats_;
    PathFootprints* footprints_ = nullptr;
    const CoupledSampling* coupled_ = nullptr;
};

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
