#include "apps/bench_loop.h"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "api/predictor.h"
#include "compare/surface_colour_error.h"

namespace pl {

namespace {
struct LoopStep {
    double noiseDeltaE = 0, seconds = 0;
    size_t retracedVoxels = 0;
};

std::vector<LoopStep> replay(const SceneDescription& desc, const RenderSettings& settings,
                             const LabelChangeHistory& changes, const std::string& method, uint64_t seed) {
    Predictor predictor(desc, settings);
    predictor.carryOver().enabled = method != "none";
    predictor.carryOver().method =
        method == "kept" ? CarryOver::Method::KeptSamples : CarryOver::Method::ControlVariates;
    const SurfaceGaussian eye(predictor.surfacePoints_mm(), kEyeFootprint_mm);
    const RGB environment = predictor.environment();
    std::vector<LoopStep> steps;
    for (size_t it = 0; it <= changes.size(); ++it) {
        predictor.settings().seed = method == "kept" ? seed : seed + it;
        const SurfacePrediction p = predictor.predict();
        LoopStep step;
        step.seconds = p.updateSeconds + p.renderSeconds;
        step.retracedVoxels = p.retracedVoxels;
        step.noiseDeltaE =
            noiseColourError(eye, reflectance(p.radiance, environment), reflectance(p.standardError, environment))
                .meanFiltered;
        steps.push_back(step);
        std::fprintf(stderr, "bench --loop: %s, iteration %zu: noise %.3f, %.1f s\n", method.c_str(), it,
                     step.noiseDeltaE, step.seconds);
        if (it < changes.size()) predictor.changeLabels(changes[it]);
    }
    return steps;
}
}  // namespace

std::string loopTable(const SceneDescription& desc, const RenderSettings& settings, const LabelChangeHistory& changes,
                      const std::vector<std::string>& methods, uint64_t seed) {
    std::vector<std::vector<LoopStep>> runs;
    for (const std::string& m : methods) runs.push_back(replay(desc, settings, changes, m, seed));
    std::ostringstream md;
    md << "The loop's predictions on " << changes.size() << " recorded iterations of label changes, "
       << settings.integrator << " at " << settings.spp
       << " spp: per method the noise over the eye's footprint (CIEDE2000), the seconds, the surface voxels traced "
          "again\n\n| iteration |";
    for (const std::string& m : methods) md << ' ' << m << " |";
    md << "\n|---|";
    for (size_t k = 0; k < methods.size(); ++k) md << "---|";
    md << '\n';
    for (size_t it = 0; it <= changes.size(); ++it) {
        md << "| " << it << " | ";
        for (const auto& run : runs) {
            char cell[96];
            std::snprintf(cell, sizeof cell, "%.3f, %.1f s, %zu | ", run[it].noiseDeltaE, run[it].seconds,
                          run[it].retracedVoxels);
            md << cell;
        }
        md << '\n';
    }
    return md.str();
}

}  // namespace pl
