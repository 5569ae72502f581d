// printlight optimize: the appearance-optimisation loop as a working
// example of the prediction API (api/appearance_optimizer.h), steered by
// the printer's characterisation (api/printer_characterisation.h).
// Prints per iteration the mean and 95th-percentile CIEDE2000 between the
// predicted and the mapped target colour over the eye's footprint and the
// iteration time; writes PREFIX.csv (the same numbers), PREFIX_labels.vdb
// (the final labels) and PREFIX.html (the models and the history).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "api/appearance_optimizer.h"
#include "api/printer_characterisation.h"
#include "compare/colour_difference.h"
#include "compare/surface_colour_error.h"
#include "render/registry.h"
#include "apps/arguments.h"
#include "apps/command_options.h"
#include "runtime/distributed.h"
#include "runtime/progress.h"
#include "io/grid_io.h"
#include "io/html_report.h"
#include "io/label_changes_io.h"
#include "core/input_error.h"
#include "io/mesh_io.h"
#include "io/mesh_repair.h"
#include "io/output_file.h"
#include "render/scene_io.h"

namespace pl {

namespace {

// --target R,G,B: one linear colour.
RGB parseTargetColour(const std::string& text) {
    const Vec3f c = parseTriple("--target", text);
    for (float x : {c.x, c.y, c.z})
        if (!(x >= 0 && x <= 1)) throw UsageError("--target colour components must be in [0, 1] (linear RGB)");
    return {c.x, c.y, c.z};
}

// Per surface voxel: the colour of the textured model at the nearest point
// of its surface, or one colour for all.
// A target model is placed (and repaired) as the scene's mesh is.
std::vector<RGB> loadTargets(const std::string& target, const MeshPlacement& placement, bool repair, const Predictor& predictor,
                             const std::vector<Vec3i>& voxels) {
    std::filesystem::path file(target);
    if (!std::filesystem::exists(file)) return std::vector<RGB>(voxels.size(), parseTargetColour(target));
    MeshRepairSummary repaired;
    MeshAsset asset = loadMeshAsset(file, placement, repair ? &repaired : nullptr);
    if (!asset.appearance.hasColor()) throw InputError(file.string(), "the model has no colours to aim at");
    SurfaceAppearance look = std::move(asset.appearance);
    Geometry geometry(std::move(asset.mesh));
    const GridFrame frame = predictor.worldFrame();
    const Vec3f& h = frame.voxelSize_mm;
    const float radius_mm = 4.0f * std::max(h.x, std::max(h.y, h.z));
    std::vector<RGB> targets(voxels.size());
    size_t missed = 0;
    for (size_t i = 0; i < voxels.size(); ++i) {
        auto cp = geometry.closestPoint(frame.voxelCenter_mm(voxels[i]), radius_mm);
        if (!cp) {
            ++missed;
            continue;
        }
        targets[i] = look.colorAt(geometry.mesh(), cp->prim, cp->p);
    }
    if (missed * 100 > voxels.size())
        throw InputError(file.string(), std::to_string(missed) + " of " + std::to_string(voxels.size()) +
                                            " surface voxels are farther than " + std::to_string(radius_mm) +
                                            " mm from the model: is it the scene's model?");
    return targets;
}

// The loop's own options (api/appearance_optimizer.h).
OptimizeSettings loopSettingsOf(const Arguments& args) {
    OptimizeSettings os;
    os.maxIterations = int(args.integer("--iterations", 0, 10000).value_or(os.maxIterations));
    if (auto t = args.number("--time")) {
        if (!(*t > 0)) throw UsageError("--time must be positive (seconds)");
        os.timeBudget_s = *t;
    }
    os.gamutMap = !args.has("--no-gamut-map");
    os.spatialGamutMap = !args.has("--flat-gamut-map");
    if (auto intent = intentOption(args)) {
        if (!os.gamutMap) throw UsageError("--intent maps into the gamut: not with --no-gamut-map");
        os.intent = *intent;
    }
    if (auto s = args.number("--step")) {
        if (!(*s > 0 && *s <= 2)) throw UsageError("--step must be in (0, 2]");
        os.step = float(*s);
    }
    if (auto s = args.number("--shell-mm")) {
        if (!(*s >= 0 && *s <= 100)) throw UsageError("--shell-mm must be in [0, 100]");
        os.shellDepth_mm = float(*s);
    }
    os.recordChanges = args.has("--record-changes");
    if (auto method = args.value("--carry-over")) {
        if (*method == "kept") os.carryOver = CarryOver::Method::KeptSamples;
        else if (*method == "control-variates") os.carryOver = CarryOver::Method::ControlVariates;
        else throw UsageError("--carry-over must be kept or control-variates");
    }
    if (auto h = args.value("--halftone")) {
        const std::optional<HalftoneMethod> method = parseEnum(kHalftoneMethodNames, *h);
        if (!method) throw UsageError("--halftone must be error-diffusion, thresholds or nearest");
        os.halftone = *method;
    }
    if (auto x = args.number("--hysteresis")) {
        if (!(*x >= 0 && *x < 0.5)) throw UsageError("--hysteresis must be in [0, 0.5)");
        if (os.halftone != HalftoneMethod::Thresholds) throw UsageError("--hysteresis needs --halftone thresholds");
        os.hysteresis = float(*x);
    }
    if (auto s = args.number("--update-footprint-mm")) {
        if (!(*s >= 0 && *s <= 10)) throw UsageError("--update-footprint-mm must be in [0, 10]");
        os.updateFootprint_mm = float(*s);
    }
    const auto judgeSpp = args.integer("--judge-spp", 0, RenderSettings::kMostSpp);
    os.judge = judgeSpp.value_or(1) > 0;
    os.judgeSpp = uint32_t(judgeSpp.value_or(0));
    if (auto x = args.number("--judge-noise")) {
        if (!(*x > 0)) throw UsageError("--judge-noise must be positive (CIEDE2000)");
        if (judgeSpp) throw UsageError("optimize takes --judge-spp or --judge-noise, not both");
        os.judgeNoiseDeltaE = *x;
    }
    os.judgeSeed = uint64_t(args.integer("--judge-seed", 0, int64_t(1) << 62).value_or(int64_t(os.judgeSeed)));
    os.judgeFootprints = size_t(args.integer("--judge-footprints", 0, 1 << 24).value_or(int64_t(os.judgeFootprints)));
    if (os.judgeFootprints == 1) throw UsageError("--judge-footprints must be 0 (the whole surface) or at least 2");
    return os;
}

// Which estimators predict and judge: the predictor's settings into
// `render`, the judge's returned. The judge renders with volpath, the
// reference path tracer, whatever predicts or the scene file names
// (lighttrace's footprint noise costs ~3x its samples' time on the greek
// cube).
RenderSettings choosePredictors(const Arguments& args, const std::string& predictorName, RenderSettings& render,
                                OptimizeSettings& os) {
    render.reentry = false;  // surface prediction
    RenderSettings judge = render;
    chooseIntegrator(judge, "volpath", "the judge");
    os.judgeIntegrator = judge.integrator;
    // By default the loop's measured best (docs/api.md): volpath at 2 spp,
    // whatever the scene file renders with.
    if (!args.has("--integrator") && predictorName.empty()) {
        chooseIntegrator(render, "volpath", "optimize");
        render.spp = 2;
    }
    applyRenderOptions(args, render);
    os.mostSpp = uint32_t(args.integer("--most-spp", 1, RenderSettings::kMostSpp).value_or(os.mostSpp));
    os.mostSpp = std::max(os.mostSpp, render.spp);
    if (auto x = args.number("--noise-target")) {
        if (!(*x > 0)) throw UsageError("--noise-target must be positive (CIEDE2000)");
        os.noiseTargetDeltaE = *x;
    }
    render.channels = {0, 1, 2};
    if (predictorName == "auto") {
        os.fastPredictor = "diffusion";
        RenderSettings fast = render;
        chooseIntegrator(fast, os.fastPredictor, "--predictor auto");
    } else if (!predictorName.empty()) {
        chooseIntegrator(render, predictorName, "--predictor");
    }
    return judge;
}

// The share of the surface voxels where the print is at the printer's limit.
double shareAtPrintersLimit(const OptimizeResult& result) {
    const std::vector<uint8_t>& atLimit = result.atPrintersLimit;
    return double(std::count(atLimit.begin(), atLimit.end(), uint8_t(1))) / double(std::max<size_t>(1, atLimit.size()));
}

// The mapping loss, the loop's own score and the judge's, on stdout.
void printOutcome(const OptimizeResult& result, const OptimizeSettings& os) {
    const auto& its = result.iterations;
    const OptimizeIteration& best = its[size_t(result.bestIteration)];
    const SurfaceColourError& loss = result.mappingLoss;
    std::printf("mapping loss (the target as given -> printable colours, %s intent): mean CIEDE2000 %.3f, 95th "
                "percentile %.3f over the eye's %g mm footprint%s\n",
                enumName(kRenderingIntentNames, os.intent), loss.meanFiltered, loss.p95Filtered, kEyeFootprint_mm,
                os.gamutMap ? "" : " (not applied: --no-gamut-map)");
    if (os.gamutMap && os.spatialGamutMap)
        std::printf("  (the flat-face gamut alone: %.3f; beyond it, where the loop found the print at the printer's "
                    "limit (%.1f %% of the surface: edges, thin walls, fine detail), the targets became what it shows "
                    "there)\n",
                    result.mappingLossFlatFace.meanFiltered, 100.0 * shareAtPrintersLimit(result));
    double loopSeconds = 0;
    for (const OptimizeIteration& it : its) loopSeconds += it.seconds;
    std::printf("the loop's own score over the footprint: %.3f -> %.3f (iteration %d of %zu, best; its noise %.2f), "
                "95th percentile %.3f -> %.3f; over three footprints %.3f -> %.3f; stopped at %s; %.1f s\n",
                its.front().meanDeltaE, best.meanDeltaE, result.bestIteration, its.size() - 1, best.noiseDeltaE,
                its.front().p95DeltaE, best.p95DeltaE, its.front().meanDeltaEWide, best.meanDeltaEWide,
                result.stoppedBecause.c_str(), loopSeconds);
    if (result.bestIteration >= 2 && !(os.gamutMap && os.spatialGamutMap))
        std::printf("the best labels' requests: %.1f %% of the surface voxels asked for colours the printer cannot show "
                    "(more than 1 Delta E*ab outside its gamut): there the error is the printer's limit (its blur, "
                    "its edges), not the loop's\n",
                    100.0 * its[size_t(result.bestIteration - 1)].outsideShare);
    if (its.front().predictor != its.back().predictor)
        std::printf("(the loop's own scores: the first by %s's prediction, the last by %s's; the judge compares "
                    "like with like)\n",
                    its.front().predictor.c_str(), its.back().predictor.c_str());
    const auto& j = result.judgement;
    if (j && j->footprints > 0) {
        std::printf("judged apart on %zu footprints sampled over the surface (%s, %zu voxels, %u spp in %d round%s, "
                    "seed %llu, %.1f s): loop error (mapped target -> print) over the eye's %g mm footprint %.3f +- "
                    "%.3f (95 %% interval of the whole surface's mean), 95th percentile %.3f\n",
                    j->footprints, j->integrator.c_str(), j->renderedVoxels, j->spp, j->rounds,
                    j->rounds > 1 ? "s" : "", (unsigned long long)j->seed, j->seconds, kEyeFootprint_mm,
                    j->meanDeltaEFiltered, j->meanDeltaEFilteredHalfWidth95, j->p95DeltaEFiltered);
        std::printf("the judge's own noise (its two halves' disagreement): %.2f CIEDE2000 over the footprint; with it "
                    "taken out, the loop error's root mean square over the footprint is %.3f (95 %% interval %.3f to "
                    "%.3f)\n",
                    j->noiseDeltaEFiltered, j->rmsDeltaEFilteredNoiseRemoved, j->rmsLow95, j->rmsHigh95);
    } else if (j) {
        std::printf("judged apart (%s, %u spp in %d round%s, seed %llu, %.1f s): loop error (mapped target -> print) "
                    "over the eye's %g mm footprint %.3f, 95th percentile %.3f; per voxel %.3f, 95th percentile %.3f\n",
                    j->integrator.c_str(), j->spp, j->rounds, j->rounds > 1 ? "s" : "", (unsigned long long)j->seed,
                    j->seconds, kEyeFootprint_mm, j->meanDeltaEFiltered, j->p95DeltaEFiltered, j->meanDeltaE,
                    j->p95DeltaE);
        std::printf("the judge's own noise (its two halves' disagreement): %.2f CIEDE2000 over the footprint (%.2f per "
                    "voxel); with it taken out, the loop error's root mean square over the footprint is %.3f\n",
                    j->noiseDeltaEFiltered, j->noiseDeltaE, j->rmsDeltaEFilteredNoiseRemoved);
    }
    if (j && os.gamutMap && os.spatialGamutMap)
        std::printf("the same renders against the flat-face gamut's targets (the printer's limits counted as the "
                    "loop's): %.3f over the footprint\n",
                    j->meanDeltaEFilteredFlatFace);
}

// What optimize writes under its prefix.
struct OptimizeOutputs {
    explicit OptimizeOutputs(const std::filesystem::path& prefix) : prefix(prefix) {}
    std::filesystem::path named(const char* suffix) const { return prefix.string() + suffix; }
    std::vector<std::filesystem::path> files() const {
        return {csv, labels, targetGlb, mappedGlb, predictionGlb, errorGlb, lossGlb, givenErrorGlb, limitGlb, report};
    }
    // The history, the best labels, the best iteration on the model as the
    // eye sees it (over its footprint: the target as given and as mapped,
    // the prediction and CIEDE2000) and the page that shows them with the
    // history.
    void write(const OptimizeResult& result, const std::string& history, const Predictor& predictor,
               const SceneDescription& desc, RenderingIntent intent) const;
    const std::filesystem::path prefix;
    const std::filesystem::path csv = named(".csv"), labels = named("_labels.vdb"), targetGlb = named("_target.glb"),
                                mappedGlb = named("_mapped.glb"), predictionGlb = named("_prediction.glb"),
                                errorGlb = named("_error.glb"), lossGlb = named("_mapping_loss.glb"),
                                givenErrorGlb = named("_error_from_given.glb"), limitGlb = named("_printers_limit.glb"),
                                report = named(".html");
};

void OptimizeOutputs::write(const OptimizeResult& result, const std::string& history, const Predictor& predictor,
                            const SceneDescription& desc, RenderingIntent intent) const {
    if (!prefix.parent_path().empty()) std::filesystem::create_directories(prefix.parent_path());
    writeTextFile(csv, history);
    LabelGrid final = predictor.labels().withChanges({});
    final.placeCornerAt(predictor.worldFrame().cornerMin_mm);
    writeLabelGridVdb(final, labels);

    const TriangleMesh mesh = loadMesh(desc.meshFile, desc.meshPlacement, desc.meshRepair);
    const GridFrame frame = predictor.worldFrame();
    const std::vector<Vec3i> voxels = predictor.surfaceVoxels();
    writePredictionGlb(mesh, frame, voxels, result.targetSeen, targetGlb);
    writePredictionGlb(mesh, frame, voxels, result.mappedSeen, mappedGlb);
    // The judge's colours when there is one: its noise is far below the
    // loop's.
    const auto& judgement = result.judgement;
    const bool judgedEverywhere = judgement && judgement->footprints == 0;
    writePredictionGlb(mesh, frame, voxels, judgedEverywhere ? judgement->judgedSeen : result.predictedSeen,
                       predictionGlb);
    const std::vector<float>& deltaESeen = judgedEverywhere ? judgement->deltaESeen : result.deltaESeen;
    // The three errors side by side: the mapping loss (the printer's
    // gamut), the loop error (mapped target -> print) and the error from
    // the target as given (what a print shop sees); and where the print is
    // at the printer's limit (magenta; white elsewhere).
    const std::vector<RGB>& printSeen = judgedEverywhere ? judgement->judgedSeen : result.predictedSeen;
    const size_t n = deltaESeen.size();
    std::vector<RGB> errorColors(n), lossColors(n), givenColors(n), limitColors(n);
    double fromGiven = 0;
    for (size_t i = 0; i < n; ++i) {
        const Lab given = labFromLinearSrgb(result.targetSeen[i]);
        const double e = ciede2000(given, labFromLinearSrgb(printSeen[i]));
        errorColors[i] = deltaEColour(deltaESeen[i]);
        lossColors[i] = deltaEColour(float(ciede2000(given, labFromLinearSrgb(result.mappedSeen[i]))));
        givenColors[i] = deltaEColour(float(e));
        const bool atLimit = i < result.atPrintersLimit.size() && result.atPrintersLimit[i];
        limitColors[i] = atLimit ? RGB{0.8f, 0.05f, 0.6f} : RGB{0.9f, 0.9f, 0.9f};
        fromGiven += e / double(n);
    }
    writePredictionGlb(mesh, frame, voxels, errorColors, errorGlb);
    writePredictionGlb(mesh, frame, voxels, lossColors, lossGlb);
    writePredictionGlb(mesh, frame, voxels, givenColors, givenErrorGlb);
    writePredictionGlb(mesh, frame, voxels, limitColors, limitGlb);
    const auto& its = result.iterations;
    const OptimizeIteration& best = its[size_t(result.bestIteration)];
    const SurfaceColourError& loss = result.mappingLoss;
    HtmlReport page;
    page.title = "printlight optimize: " + desc.sceneFile.filename().string();
    char summary[700];
    std::snprintf(summary, sizeof summary,
                  "Over the eye's %g mm footprint: mapping loss %.2f (target as given -> printable, %s intent; the "
                  "flat-face gamut's %.2f); loop %.2f -> %.2f "
                  "(mapped target -> prediction, iteration %d; %s, %u spp); from the target as given %.2f (what a "
                  "print shop sees, the %s); at the printer's limit %.1f %% of the surface (where the loop "
                  "found it, the targets became what the print shows there).",
                  kEyeFootprint_mm, loss.meanFiltered, enumName(kRenderingIntentNames, intent),
                  result.mappingLossFlatFace.meanFiltered, its.front().meanDeltaE, best.meanDeltaE, result.bestIteration,
                  predictor.settings().integrator.c_str(), predictor.settings().spp, fromGiven,
                  judgedEverywhere ? "judge's colours" : "loop's best prediction", 100.0 * shareAtPrintersLimit(result));
    std::string judged = " The prediction and error views are the loop's best prediction, its noise included.";
    if (judgement && !judgedEverywhere) {
        char text[400];
        std::snprintf(text, sizeof text,
                      " Judged apart on %zu footprints sampled over the surface (%s, %u spp): loop error %.2f +- %.2f "
                      "(95 %% interval; %.2f against the flat-face gamut's targets), its noise %.2f (%.2f root mean "
                      "square with the noise taken out); the prediction and error views are the loop's best "
                      "prediction, its noise included.",
                      judgement->footprints, judgement->integrator.c_str(), judgement->spp,
                      judgement->meanDeltaEFiltered, judgement->meanDeltaEFilteredHalfWidth95,
                      judgement->meanDeltaEFilteredFlatFace, judgement->noiseDeltaEFiltered,
                      judgement->rmsDeltaEFilteredNoiseRemoved);
        judged = text;
    } else if (judgement) {
        char text[320];
        std::snprintf(text, sizeof text,
                      " Judged apart (%s, %u spp): loop error %.2f (%.2f against the flat-face gamut's targets), its "
                      "noise %.2f (%.2f root mean square with the noise taken out); the prediction and error views are "
                      "the judge's.",
                      judgement->integrator.c_str(), judgement->spp, judgement->meanDeltaEFiltered,
                      judgement->meanDeltaEFilteredFlatFace,
                      judgement->noiseDeltaEFiltered, judgement->rmsDeltaEFilteredNoiseRemoved);
        judged = text;
    }
    page.summary = summary + judged + " Error map: blue 0, green 2.5, yellow 5, red 10 or more.";
    page.models = {{"target", targetGlb},
                   {"target mapped", mappedGlb},
                   {"prediction", predictionGlb},
                   {"CIEDE2000", errorGlb},
                   {"mapping loss (CIEDE2000, given -> mapped)", lossGlb},
                   {"from the target as given (CIEDE2000)", givenErrorGlb},
                   {"at the printer's limit (magenta)", limitGlb}};
    for (const OptimizeIteration& it : its) page.history.push_back({double(it.iteration), it.meanDeltaE});
    page.historyLabel = "mean CIEDE2000 over the footprint";
    writeHtmlReport(page, report);
    std::printf("wrote %s, %s, %s_{target,mapped,prediction,error,mapping_loss,error_from_given,printers_limit}.glb "
                "and %s\n",
                csv.string().c_str(),
                labels.string().c_str(), prefix.string().c_str(), report.string().c_str());
}

}  // namespace

int optimizeCommand(const std::vector<std::string>& argv) {
    Arguments args("optimize", argv,
                   {{"--target", "MODEL|R,G,B", "the colours to match: a textured .gltf/.glb/.obj or one linear RGB"},
                    {"--iterations", "N", "the most loop iterations (default 16; it stops sooner when its score stops falling)"},
                    {"--time", "S", "no new iteration past S seconds of the loop"},
                    kSppOption,
                    {"--most-spp", "N",
                     "where the score stops falling, the predictions' samples go up 4x to at most N before the loop "
                     "stops (default 8; 4N where their noise is still above --noise-target)"},
                    {"--noise-target", "DE",
                     "the predictions' noise over the eye's footprint (CIEDE2000) above which the samples go past "
                     "--most-spp (default 2; dark colours need it)"},
                    kSeedOption,
                    {"--step", "X", "share of the error one iteration corrects, at each voxel's measured gain (0..2]"},
                    {"--shell-mm", "D", "depth of the shell whose labels change"},
                    {"--halftone", "error-diffusion|thresholds|nearest",
                     "how the shell's mixtures become labels (default error-diffusion; thresholds: a blue-noise "
                     "matrix, where a request that moves little relabels few voxels)"},
                    {"--record-changes", "FILE",
                     "write each iteration's label changes to FILE (bench --loop replays them)"},
                    {"--hysteresis", "H",
                     "with --halftone thresholds: a voxel keeps its resin while its share comes within H of its "
                     "threshold (default 0)"},
                    {"--carry-over", "kept|control-variates",
                     "predictions that carry over (volpath): keep the samples the label changes cannot reach, adding "
                     "--spp each iteration, or a running estimate by control variates (docs/api.md)"},
                    kThreadsOption,
                    integratorOption(),
                    {"--predictor", "NAME|auto",
                     "predict with that estimator (as --integrator), or auto: diffusion while its score falls, then "
                     "volpath"},
                    {"--judge-spp", "N",
                     "samples of the judge, which renders the final labels apart (volpath) and "
                     "scores them (default: until its noise is under --judge-noise, at most 256; 0: no judge)"},
                    {"--judge-noise", "DE", "the judge's noise wanted over the footprint (CIEDE2000, default 0.5)"},
                    {"--judge-seed", "S", "the judge's seed (default 99)"},
                    {"--judge-footprints", "N",
                     "judge only N of the eye's footprints, a stratified random sample, each with its whole "
                     "neighbourhood, and estimate the whole surface's mean error with a 95 % interval (default 64; 0: "
                     "every surface voxel, and the judged colours on the model)"},
                    {"--update-footprint-mm", "S",
                     "average each iteration's error with a Gaussian of this sigma on the surface (default 0.2, the "
                     "eye's footprint; 0: per voxel)"},
                    kChannelSamplingOption,
                    {"--gamut", "FILE", "the printer's characterisation (default: the material table's, made on first use)"},
                    {"--no-gamut-map", "", "aim at the target as given, not at its nearest printable colour"},
                    kIntentOption,
                    {"--flat-gamut-map", "",
                     "judge against the flat-face gamut's colours everywhere, also where the loop found the print "
                     "cannot show them (edges, thin walls, fine detail)"},
                    {"-o,--output", "PREFIX", "outputs PREFIX.csv, PREFIX_labels.vdb, PREFIX.html and its models"}});
    if (args.positional().size() != 1) throw UsageError("optimize needs exactly one SCENE.json");
    auto target = args.value("--target");
    if (!target) throw UsageError("optimize needs --target MODEL.gltf|.glb|.obj or --target R,G,B (linear)");
    OptimizeSettings os = loopSettingsOf(args);
    const std::string predictorName = args.value("--predictor").value_or("");
    if (!predictorName.empty() && args.has("--integrator"))
        throw UsageError("optimize takes --predictor or --integrator, not both");
    ThreadLimit threadLimit(args);

    auto t0 = std::chrono::steady_clock::now();
    SceneDescription desc = parseScene(args.positional()[0]);
    const OptimizeOutputs out(args.value("-o").value_or("out/" + desc.sceneFile.stem().string() + "_optimize"));
    std::vector<std::filesystem::path> inputs = desc.inputFiles();
    if (std::filesystem::exists(*target)) inputs.push_back(*target);
    else parseTargetColour(*target);  // a bad colour is refused before anything loads
    if (auto file = args.value("--gamut"); file && !std::filesystem::exists(*file))
        throw InputError(*file, "no such file (the printer's characterisation, --gamut)");
    for (const auto& file : out.files()) refuseToOverwriteInputs(file, inputs);
    if (auto file = args.value("--record-changes")) refuseToOverwriteInputs(*file, inputs);
    // Settings before the predictor loads: what it loads depends on the
    // integrator (printpt needs the surface clearance).
    const RenderSettings judge = choosePredictors(args, predictorName, desc.render, os);
    std::unique_ptr<Predictor> loaded;  // on every rank, or none (rank 0 says why)
    runOnEveryRank([&] { loaded = std::make_unique<Predictor>(desc, desc.render, sceneNeedsOf(judge)); });
    Predictor& predictor = *loaded;
    // Across MPI ranks every rank runs the loop on the same predictions
    // (each renders its share of them); rank 0 speaks and writes.
    const bool speaks = Distributed::rank() == 0;
    predictor.setAcrossRanks(Distributed::ranks() > 1);
    CharacterisationSettings cs;
    cs.voxel_mm = predictor.worldFrame().voxelSize_mm;
    cs.ior = desc.ior;
    const PrinterGamut gamut = [&] {
        auto say = [&](const std::string& line) {
            if (speaks) std::printf("%s\n", line.c_str());
        };
        if (auto file = args.value("--gamut")) return readPrinterGamutFile(*file, desc.materialsFile, cs, say);
        return printerGamutFor(desc.materialsFile, cs, say);
    }();
    const std::vector<Vec3i> voxels = predictor.surfaceVoxels();
    std::vector<RGB> targets = loadTargets(*target, desc.meshPlacement, desc.meshRepair, predictor, voxels);
    if (speaks)
        std::printf("optimize: %s: %zu surface voxels, %s, %u spp, loaded in %.2f s\n", desc.sceneFile.string().c_str(),
                voxels.size(), predictor.settings().integrator.c_str(), predictor.settings().spp, secondsSince(t0));
    const char* header =
        "iteration,mean_de2000,p95_de2000,mean_de2000_per_voxel,p95_de2000_per_voxel,seconds,changed_voxels,predictor,"
        "noise_de2000,mean_de2000_wide,outside_share,spp,retraced_voxels,mean_samples\n";
    if (speaks) std::fputs(header, stdout);
    std::ostringstream csv;
    csv << header;
    OptimizeResult result = optimizeAppearance(predictor, gamut, targets, os, [&](const OptimizeIteration& it) {
        char line[256];
        std::snprintf(line, sizeof line, "%d,%.4f,%.4f,%.4f,%.4f,%.3f,%zu,%s,%.4f,%.4f,%.4f,%u,%zu,%.1f\n",
                      it.iteration, it.meanDeltaE, it.p95DeltaE, it.meanDeltaEPerVoxel, it.p95DeltaEPerVoxel,
                      it.seconds, it.changedVoxels, it.predictor.c_str(), it.noiseDeltaE, it.meanDeltaEWide,
                      it.outsideShare, it.spp, it.retracedVoxels, it.meanSamples);
        if (speaks) {
            std::fputs(line, stdout);
            std::fflush(stdout);
        }
        csv << line;
    });
    if (!speaks) return 0;
    printOutcome(result, os);
    out.write(result, csv.str(), predictor, desc, os.intent);
    if (auto file = args.value("--record-changes")) {
        writeLabelChanges(*file, result.changes);
        std::printf("wrote %s (the label changes of %zu iterations)\n", file->c_str(), result.changes.size());
    }
    return 0;
}

}  // namespace pl
