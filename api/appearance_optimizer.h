// A scattering-aware compensation loop on the surface shell, in the spirit
// of Elek et al. 2017, steered by the printer's characterisation
// (prepare/printer_gamut.h): predict the surface colour, compare it with
// the target as the eye sees it, move each surface voxel's requested colour
// in CIELAB, print the mixture that shows it, repeat.
//  - Targets are per surface voxel, linear RGB reflectance (white = 1).
//    They are first mapped into the printer's gamut by a rendering intent
//    (prepare/rendering_intent.h): by default each to the colour of the
//    mixture nearest it in CIELAB (colorimetric: minimum Delta E clipping,
//    the identity inside the gamut), or compressed as a whole (perceptual).
//    The loop aims at them; where it finds the print at the printer's
//    limit (edges, thin walls, fine detail), the targets it is judged
//    against become what the print can show there (api/printers_reach.h).
//    The mapping loss (as given -> judged against) is reported apart.
//  - The shell is every object voxel within shellDepth_mm of a surface
//    voxel; each takes the mixture of its nearest surface voxel, halftoned
//    by prepare's 3D vector error diffusion; only changed voxels go to the
//    predictor.
//  - First the mapped targets' own mixtures are printed. After each
//    prediction, the error (mapped target - prediction, both averaged over
//    the eye's footprint, in CIELAB) moves each request by `step` times the
//    error over the request's measured gain (a secant estimate per voxel:
//    how far the prediction moved for the last move of the request) and
//    over 1 + the times its error turned back (Kesten's rule: the moves
//    follow the error while it keeps its direction, then average the
//    predictions' noise), the error first shrunk by James-Stein's rule
//    against the predictions' noise; the request then goes back to the
//    nearest printable colour (no clamping, no wind-up outside the gamut).
//  - Scores: mean and 95th percentile of CIEDE2000 between prediction and
//    mapped target over the eye's footprint (compare/surface_colour_error.h),
//    per voxel, and over three footprints (the wide score, whose noise is
//    small enough to show what the loop still changes). When the wide score
//    has not fallen 2 % below its best for `patience` iterations, the
//    predictions' samples go up 4x (to mostSpp: less noise, finer
//    corrections; once more where their noise is still above its target);
//    past that, or after maxIterations or its time budget, the loop stops
//    and ends on the labels of its best wide score.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "api/predictor.h"
#include "compare/surface_colour_error.h"
#include "prepare/printer_gamut.h"
#include "prepare/rendering_intent.h"

namespace pl {

struct OptimizeSettings {
    int maxIterations = 16;
    double timeBudget_s = 0;  // > 0: no new iteration past this wall time (the loop's)
    int patience = 2;         // iterations without a significant new best before it stops (0: never)
    // The Monte Carlo predictions' most samples per pixel: where the score
    // stops falling with fewer, they go up 4x (to at most this) before the
    // loop stops (on the white cube's muted colour, 8 spp's predictions end
    // at half the error of 2 spp's, where their noise stalls the loop).
    uint32_t mostSpp = 8;
    // Where the predictions' own noise over the eye's footprint is still
    // above this at mostSpp (dark colours: 3.2 on the white cube's dark
    // grey at 8 spp, against 1.0 on saturated ones), the samples go up 4x
    // once more when the loop stalls again.
    double noiseTargetDeltaE = 2.0;
    float shellDepth_mm = 1.0f;
    // How the shell's mixtures become labels (prepare/halftone.h).
    HalftoneMethod halftone = HalftoneMethod::ErrorDiffusion;
    // By thresholds after the first print: a voxel keeps its material
    // while that material's share comes within this of its threshold
    // (prepare/halftone.h), so requests that wander by the predictions'
    // noise relabel little.
    float hysteresis = 0.0f;
    // Predictions that carry over (api/predictor.h, CarryOver): by kept
    // samples (one seed for the loop, each prediction adding the settings'
    // spp to the samples its changes did not reach) or by control
    // variates (a new seed each iteration, as without). None: a new seed
    // and a prediction afresh each iteration.
    std::optional<CarryOver::Method> carryOver;
    // Keep each iteration's label changes (OptimizeResult::changes).
    bool recordChanges = false;
    float step = 0.8f;  // share of the error one iteration corrects, at the measured gain
    // The error is averaged with a Gaussian of this sigma on the surface, by
    // default the eye's footprint: detail finer than the eye sees is left
    // alone, and so is most of the noise (0: per voxel).
    float updateFootprint_mm = kEyeFootprint_mm;
    bool gamutMap = true;  // false: aim at the targets as given (clipped by the inverse)
    // How targets become printable colours (prepare/rendering_intent.h).
    RenderingIntent intent = RenderingIntent::Colorimetric;
    // Where the loop finds the print at the printer's limit (edges,
    // corners, thin walls, fine detail: api/printers_reach.h), judge it
    // against what it can show there. false: against the flat-face gamut's
    // colours throughout.
    bool spatialGamutMap = true;
    // A fast predictor (an integrator's name, e.g. "diffusion") for the
    // first iterations: the loop predicts with it while its own score falls
    // by at least switchBelowDeltaE per iteration, then with the
    // predictor's settings (Monte Carlo). Empty: none.
    std::string fastPredictor;
    double switchBelowDeltaE = 0.25;
    // The judge: the final labels rendered apart (this integrator, empty:
    // the predictor's settings') in two independent halves, scored against
    // the mapped targets per voxel and over the eye's footprint, its noise
    // measured by the halves' disagreement (compare/surface_colour_error.h,
    // splitRenderError). judgeSpp > 0: that many samples in all; 0: rounds
    // until the noise over the footprint is under judgeNoiseDeltaE, at
    // most judgeMostSpp. The predictor must have loaded what the judge needs.
    // judgeFootprints > 0: only that many of the eye's footprints, a
    // stratified random sample (compare/footprint_sample.h), each rendered
    // with its whole neighbourhood; the means over them estimate the whole
    // surface's, with 95 % intervals. 0: every surface voxel (and the
    // judged colours on the model).
    bool judge = false;
    size_t judgeFootprints = 64;
    std::string judgeIntegrator;
    uint32_t judgeSpp = 0;
    double judgeNoiseDeltaE = 0.5;
    uint32_t judgeMostSpp = 256;
    uint64_t judgeSeed = 99;
};

struct OptimizeIteration {
    int iteration = 0;        // 0: the labels as given
    double meanDeltaE = 0;    // CIEDE2000 over the eye's footprint, prediction against mapped target
    double p95DeltaE = 0;
    double noiseDeltaE = 0;   // what the prediction's own noise adds to meanDeltaE
    // Over three footprints (its noise a tenth): what decides the best
    // iteration and when the loop stops.
    double meanDeltaEWide = 0;
    double meanDeltaEPerVoxel = 0, p95DeltaEPerVoxel = 0;  // the same per voxel (noise included)
    double seconds = 0;       // prediction plus update
    size_t changedVoxels = 0;
    // Carrying over: the surface voxels some of whose samples this
    // iteration's prediction traced again (Predictor::carryOver), and the
    // mean samples a voxel held.
    size_t retracedVoxels = 0;
    double meanSamples = 0;
    // Share of the surface voxels whose request, after this prediction,
    // lay more than 1 Delta E*ab from the nearest printable colour found
    // for it: where the print would need colours the printer cannot show.
    double outsideShare = 0;
    std::string predictor;    // the integrator that made this iteration's prediction
    uint32_t spp = 0;         // and its samples per pixel
};

struct OptimizeJudgement {
    std::string integrator;
    uint32_t spp = 0;  // in all, the two halves together
    int rounds = 0;
    uint64_t seed = 0;
    size_t footprints = 0;      // sampled footprints (0: the whole surface)
    size_t renderedVoxels = 0;  // the surface voxels it rendered
    double meanDeltaE = 0, p95DeltaE = 0;                  // CIEDE2000 per voxel
    double meanDeltaEFiltered = 0, p95DeltaEFiltered = 0;  // over the eye's footprint
    // With sampled footprints: the 95 % interval of the whole surface's
    // mean over the footprint (mean +- half width), and of the root mean
    // square below.
    double meanDeltaEFilteredHalfWidth95 = 0, rmsLow95 = 0, rmsHigh95 = 0;
    // The mean over the footprint from the same renders against the
    // flat-face gamut's targets (without the printer's limits the loop
    // found: api/printers_reach.h).
    double meanDeltaEFilteredFlatFace = 0;
    // The mean CIEDE2000 the judge's own noise makes, per voxel and over
    // the footprint (part of the errors above).
    double noiseDeltaE = 0, noiseDeltaEFiltered = 0;
    // Root mean square CIEDE2000 over the footprint with the judge's noise
    // taken out (at least the mean it would have without noise).
    double rmsDeltaEFilteredNoiseRemoved = 0;
    double seconds = 0;
    // Per surface voxel over the eye's footprint (the whole surface's
    // judge only): the judged colours and their CIEDE2000 from the mapped
    // targets (what the print shows, with the judge's small noise rather
    // than the loop's).
    std::vector<RGB> judgedSeen;
    std::vector<float> deltaESeen;
};

struct OptimizeResult {
    std::vector<OptimizeIteration> iterations;
    int bestIteration = 0;  // whose labels the predictor ends with
    std::string stoppedBecause;
    // Target as given -> what the loop aimed at in the end (CIEDE2000, per
    // voxel and over the eye's footprint): what the printer cannot show,
    // its limits at edges and detail included; and the part of it the
    // flat-face gamut alone accounts for.
    SurfaceColourError mappingLoss, mappingLossFlatFace;
    // Per surface voxel, what the loop aimed at in the end (linear sRGB
    // reflectance): the judge's reference.
    std::vector<RGB> aimedAt;
    // Per surface voxel over the eye's footprint: the target as given, as
    // aimed at in the end, the best iteration's prediction, and CIEDE2000
    // between the last two.
    std::vector<RGB> targetSeen, mappedSeen, predictedSeen;
    std::vector<float> deltaESeen;
    // Per surface voxel: whether the print is at the printer's limit there
    // (its target re-mapped; without the spatial gamut map, whether the
    // request behind the best labels lay more than 1 Delta E*ab beyond the
    // gamut).
    std::vector<uint8_t> atPrintersLimit;
    std::optional<OptimizeJudgement> judgement;  // with judge
    // With recordChanges: the changes after each prediction but the last,
    // in order (bench --loop replays them).
    std::vector<std::vector<LabelGrid::Change>> changes;
};

// The judge alone (settings' judge fields, its integrator the predictor's
// if none): the predictor's labels against `mapped` (reflectance per
// surface voxel). The predictor's settings are left as the judge set them.
OptimizeJudgement judgeLabels(Predictor& predictor, const OptimizeSettings& settings, const std::vector<RGB>& mapped);

// targets: per surface voxel in the predictor's order. The predictor ends
// holding the best labels, its settings as they were. onIteration is called
// after each prediction.
OptimizeResult optimizeAppearance(Predictor& predictor, const PrinterGamut& gamut, const std::vector<RGB>& targets,
                                  const OptimizeSettings& settings,
                                  const std::function<void(const OptimizeIteration&)>& onIteration);

}  // namespace pl
