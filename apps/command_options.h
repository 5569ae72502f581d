// Options several commands share: --threads (a TBB limit for the command's
// lifetime), the render overrides --spp, --seed, --channel,
// --channel-sampling and --integrator, and the rendering intent.
#pragma once

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "apps/arguments.h"
#include "prepare/rendering_intent.h"
#include "render/registry.h"
#include "render/render.h"
#include "render/scene_io.h"

namespace pl {

// The options several commands take, declared once.
inline const Option kThreadsOption{"--threads", "N", "worker threads (default: every core)"};
inline const Option kSppOption{"--spp", "N", "samples per pixel (overrides the scene's)"};
inline const Option kSeedOption{"--seed", "S", "random seed (overrides the scene's); same seed, same bits"};
inline const Option kChannelOption{"--channel", "r|g|b|rgb", "colour channels to render"};
inline const Option kChannelSamplingOption{"--channel-sampling", "separate|hero|spectral",
                                           "how rgb is sampled (docs/scene-format.md)"};
inline Option integratorOption() { return {"--integrator", "NAME", "the estimator: " + integratorNames()}; }
inline const Option kQuietOption{"--quiet", "", "no progress or summary on stderr"};
inline const Option kIntentOption{"--intent", "colorimetric|perceptual",
                                  "how colours the printer cannot show become printable: the nearest printable colour "
                                  "(colorimetric, the default) or the whole of sRGB compressed into the gamut, keeping "
                                  "hue and the order of lightness (perceptual)"};

// --threads N (default: all cores) for as long as this object lives.
class ThreadLimit {
public:
    explicit ThreadLimit(const Arguments& args)
        : count(int(args.integer("--threads", 1, 1024).value_or(tbb::info::default_concurrency()))),
          control_(tbb::global_control::max_allowed_parallelism, size_t(count)) {}
    const int count;

private:
    tbb::global_control control_;
};

// --intent, if given (prepare/rendering_intent.h).
inline std::optional<RenderingIntent> intentOption(const Arguments& args) {
    const std::optional<std::string> name = args.value("--intent");
    if (!name) return std::nullopt;
    const std::optional<RenderingIntent> intent = parseEnum(kRenderingIntentNames, *name);
    if (!intent) throw UsageError("--intent must be " + enumNames(kRenderingIntentNames));
    return intent;
}

// Sets the estimator an option names, or says why it cannot run.
inline void chooseIntegrator(RenderSettings& r, const std::string& name, const std::string& option) {
    if (!findIntegratorKind(name)) throw UsageError(option + " must be " + integratorNames());
    if (name != r.integrator) setIntegrator(r, name);
    if (std::string why = refusalOf(r); !why.empty()) throw UsageError(why);
    if (capabilitiesOf(r).deterministic) r.spp = 1;
}

// A render-block option from the command line, checked by the scene file
// key's own table entry (integrators/render_settings.cpp): one range.
inline void applyRenderOption(const Arguments& args, const char* option, const char* key, RenderSettings& r) {
    const std::optional<double> value = args.number(option);
    if (!value) return;
    if (std::string problem = setOption(renderParameters(), r, key, *value); !problem.empty())
        throw UsageError(std::string(option) + " " + problem);
}

// Applies those of the render overrides the command line holds (a command
// that does not accept one never has it).
inline void applyRenderOptions(const Arguments& args, RenderSettings& r) {
    applyRenderOption(args, "--spp", "spp", r);
    applyRenderOption(args, "--seed", "seed", r);
    if (auto ch = args.value("--channel")) {
        auto channels = parseChannels(*ch);
        if (!channels) throw UsageError("--channel must be r, g, b or rgb");
        r.channels = *channels;
    }
    if (auto cs = args.value("--channel-sampling")) {
        auto sampling = parseChannelSampling(*cs);
        if (!sampling) throw UsageError("--channel-sampling must be " + enumNames(kChannelSamplingNames));
        r.channelSampling = *sampling;
    }
    // The scene's estimator unless the command line names one: checked,
    // and one sample if it is deterministic.
    chooseIntegrator(r, args.value("--integrator").value_or(r.integrator), "--integrator");
}

}  // namespace pl
