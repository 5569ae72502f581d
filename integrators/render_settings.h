// What a render is asked for: the estimator by name and its parameters
// (each estimator reads its own), the samples (or a time budget, or a
// target error), seed, channels and how they are sampled. Read from a
// scene's "render" block (render/scene_io.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/estimator_parameters.h"
#include "core/option_table.h"
#include "integrators/channel_paths.h"
#include "media/label_medium.h"

namespace pl {

struct RenderSettings {
    std::string integrator = "volpath";  // a name of integratorKinds() (render/registry.h)
    static constexpr int64_t kMostSpp = int64_t(1) << 24;
    // Seeds are whole numbers up to 2^53, exact in a JSON number (a double).
    static constexpr int64_t kMostSeed = int64_t(1) << 53;
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
    // Free flights against per-brick majorants, the textbook tracker's one
    // global majorant, or decomposition tracking (the last two for
    // measurements; media/label_medium.h).
    Majorants majorants = Majorants::PerBrick;
    // The render block's other keys: the estimator's own, which it reads
    // in its factory (its parameters() declare them; render/registry.h).
    EstimatorParameters parameters;
    bool showProgress = false;
};

// The render block's own numeric and boolean options by their scene-file
// names (core/option_table.h); integrator, channel, channel_sampling and
// majorants are names (render/scene_io).
const std::vector<OptionParameter<RenderSettings>>& renderParameters();

// Why the settings' majorants cannot serve their channel sampling
// (decomposition tracking follows one channel a flight), or "".
std::string majorantsRefusal(const RenderSettings& settings);

}  // namespace pl
