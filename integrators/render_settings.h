// What a render is asked for: the estimator by name and its options, the
// samples (or a time budget, or a target error), seed, channels and how
// they are sampled. Read from a scene's "render" block (render/scene_io.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/option_table.h"
#include "integrators/photons/bre.h"
#include "integrators/lighttrace/lighttrace.h"
#include "integrators/photons/photon_beams.h"
#include "integrators/printpt/printpt.h"
#include "integrators/volpath/volpath.h"

namespace pl {

struct RenderSettings {
    std::string integrator = "volpath";  // a name of integratorKinds() (render/registry.h)
    static constexpr int64_t kMostSpp = int64_t(1) << 24;
    uint32_t spp = 16;           // with a time budget or a target error: the most
    double timeBudget_s = 0;     // > 0: stop at this wall time (render/progressive_render.h)
    double targetRelativeError = 0;  // > 0: stop at this median per-pixel relative error
    uint64_t seed = 1;
    // Trace light that leaves the object back against it (the object sees
    // itself): a statement about the whole scene, which every estimator
    // traces (volpath) or refuses. Surface prediction leaves it off.
    bool reentry = false;
    std::vector<int> channels{0, 1, 2};  // rendered channels
    // How all three channels are sampled (a subset is always one pass per
    // channel). Separate passes won on the test set (docs/performance.md).
    ChannelSampling channelSampling = ChannelSampling::Separate;
    // Free flights against per-brick majorants, or the textbook tracker's
    // one global majorant (single-channel paths; for measurements).
    Majorants majorants = Majorants::PerBrick;
    VolPathOptions volpath;
    PrintPtOptions printpt;
    LightTraceOptions lighttrace;
    BreOptions bre;
    BeamOptions beams;  // pb2d and bb1d
    // The learned predictor's model (io/learned_model_io.h): by default the
    // one beside the scene's material table.
    std::filesystem::path learnedModel;
    bool showProgress = false;
};

// The render block's own numeric and boolean options by their scene-file
// names (core/option_table.h); integrator, channel, channel_sampling,
// majorants and learned_model are names and paths (render/scene_io).
const std::vector<OptionParameter<RenderSettings>>& renderParameters();

}  // namespace pl
