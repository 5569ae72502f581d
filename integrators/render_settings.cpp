#include "integrators/render_settings.h"

namespace pl {

const std::vector<OptionParameter<RenderSettings>>& renderParameters() {
    using R = RenderSettings;
    static const std::vector<OptionParameter<R>> parameters = {
        {"spp", &R::spp, 1, double(R::kMostSpp), false, "must be in 1..16777216",
         "samples per pixel and channel; with a time budget or a target error, the most"},
        {"time_budget_s", &R::timeBudget_s, 0, 1e9, false, "must be in [0, 1e9] (seconds)",
         "stop at this wall time (progressive rounds); 0: none"},
        {"target_relative_error", &R::targetRelativeError, 0, 10, false, "must be in [0, 10]",
         "stop at this median per-pixel relative standard error; 0: none"},
        {"seed", &R::seed, 0, double(R::kMostSeed), false, "must be a whole number in 0..2^53",
         "seed of the random streams, each path's keyed by (seed, pixel, sample, channel)"},
        {"reentry", &R::reentry, 0, 0, false, "", "trace light that leaves the object back against it"},
    };
    return parameters;
}

std::string majorantsRefusal(const RenderSettings& settings) {
    // Whatever the channels asked now: optimize asks for all three later.
    if (settings.majorants == Majorants::Decomposition && settings.channelSampling != ChannelSampling::Separate)
        return "decomposition tracks one channel a flight: with channel_sampling 'separate' only";
    return "";
}

}  // namespace pl
