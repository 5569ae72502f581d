// A simple scattering-aware compensation loop on the surface shell, in the
// spirit of Elek et al. 2017: predict the surface colour, compare it with
// the target, push the shell's requested colours against the error,
// re-halftone, repeat.
//  - Targets are per surface voxel, linear RGB reflectance (white = 1). By
//    default they are first mapped into what the printer can show: between
//    the mean predicted reflectance of a shell all black and all white
//    (two calibration predictions), per channel.
//  - The shell is every object voxel within shellDepth_mm of a surface
//    voxel; each takes the requested colour of its nearest surface voxel.
//  - Scores: mean and 95th percentile of CIEDE2000 between prediction and
//    target, both averaged over a small surface neighbourhood (scoreRadius),
//    and per voxel.
//  - Requested colours start at the targets; after each prediction they
//    move by step x (target - prediction), the error averaged over the
//    surface voxels within smoothRadius voxels (the prediction is noisy),
//    clamped to [0, 1]. Then the shell is halftoned again (prepare's vector
//    error diffusion over fractionsForColor) and only the voxels whose
//    label changed go to the predictor.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "api/predictor.h"
#include "compare/surface_colour_error.h"

namespace pl {

struct OptimizeSettings {
    int iterations = 8;
    float shellDepth_mm = 1.0f;
    float step = 0.5f;
    int smoothRadius = 1;
    // > 0: the error is averaged instead with a Gaussian of this sigma on
    // the surface, by default the eye's footprint: detail finer than the
    // eye sees is left alone, and so is most of the noise (on the greek
    // cube the judged error over the footprint fell from 12.8 to 4.8;
    // docs/api.md).
    float updateFootprint_mm = kEyeFootprint_mm;
    // Colours are compared after averaging prediction and target over the
    // surface voxels within this many voxels (0: per voxel). Per voxel, the
    // Monte Carlo noise of a few samples dominates CIEDE2000.
    int scoreRadius = 1;
    bool gamutMap = true;
    // A fast predictor (an integrator's name, e.g. "diffusion") for the
    // first iterations: the loop predicts with it while its own score falls
    // by at least switchBelowDeltaE per iteration (past that the predictor's
    // bias is larger than what a step changes), then with the predictor's
    // settings (Monte Carlo). The calibrations use the latter. Empty: none.
    std::string fastPredictor;
    double switchBelowDeltaE = 0.25;
    // The judge: the final labels rendered independently (this integrator,
    // empty: the predictor's settings'; spp and seed) and scored against
    // the targets mapped by its own calibration, per voxel and over the
    // eye's footprint (compare/surface_colour_error.h). 0 spp: none. The
    // predictor must have loaded what the judge needs (Predictor's alsoNeeds).
    std::string judgeIntegrator;
    uint32_t judgeSpp = 0;
    uint64_t judgeSeed = 99;
};

struct OptimizeIteration {
    int iteration = 0;       // 0: the labels as given
    double meanDeltaE = 0;   // CIEDE2000, prediction against (mapped) target, at scoreRadius
    double p95DeltaE = 0;
    double meanDeltaEPerVoxel = 0, p95DeltaEPerVoxel = 0;  // the same per voxel (noise included)
    double seconds = 0;      // prediction plus update
    size_t changedVoxels = 0;
    std::string predictor;  // the integrator that made this iteration's prediction
};

struct OptimizeJudgement {
    std::string integrator;
    uint32_t spp = 0;
    uint64_t seed = 0;
    double meanDeltaE = 0, p95DeltaE = 0;                  // CIEDE2000 per voxel
    double meanDeltaEFiltered = 0, p95DeltaEFiltered = 0;  // over the eye's footprint
    // The mean CIEDE2000 the judge's own noise makes, per voxel and over
    // the footprint (compare/surface_colour_error.h, noiseColourError).
    double noiseDeltaE = 0, noiseDeltaEFiltered = 0;
    // The estimate takes each voxel's noise as its own: with samples shared
    // between voxels (light tracing) the footprint averages less of it out,
    // and the estimate is a lower bound.
    bool noiseIsLowerBound = false;
    double seconds = 0;
};

struct OptimizeResult {
    std::vector<OptimizeIteration> iterations;
    RGB gamutBlack{0, 0, 0}, gamutWhite{1, 1, 1};  // reflectance of the calibration shells
    // The last iteration per surface voxel, as it was scored (over
    // scoreRadius): predicted and (mapped) target reflectance, CIEDE2000.
    std::vector<RGB> finalPredicted, finalTarget;
    std::vector<float> finalDeltaE;
    std::optional<OptimizeJudgement> judgement;  // with judgeSpp > 0
};

// targets: per surface voxel in the predictor's order. The predictor ends
// holding the final labels, its settings as they were. onIteration is called after each prediction.
OptimizeResult optimizeAppearance(Predictor& predictor, const std::vector<RGB>& targets,
                                  const OptimizeSettings& settings,
                                  const std::function<void(const OptimizeIteration&)>& onIteration);

}  // namespace pl
