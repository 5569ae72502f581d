#include "apps/bench_configurations.h"

#include <array>
#include <optional>
#include <stdexcept>

#include "apps/arguments.h"
#include "apps/commands.h"
#include "render/registry.h"
#include "render/scene_io.h"

namespace pl {

namespace {

// The variants: a name and the configuration it stands for.
const std::vector<std::pair<const char*, const char*>> kVariants = {
    // Every flight starts with a boundary query (no clearance first).
    {"volpath-geometry-first", "volpath/clearance_first=0"},
    // The thesis' Russian roulette: survival min(0.99, throughput) at every collision.
    {"printpt-brecka", "printpt/rr_cap=0.99/rr_threshold=1/rr_threshold_absorbing=1"},
    {"printpt-analog", "printpt/rr_threshold=1/rr_threshold_absorbing=1"},
    {"printpt-k1", "printpt/branches=1"},
    {"printpt-k16", "printpt/branches=16"},
    {"printpt-geometry-first", "printpt/medium_first=0"},
    {"printpt-no-clearance", "printpt/clearance=0"},
    {"printpt-no-balls", "printpt/ball_walks=0"},
    {"printpt-random-fresnel", "printpt/fresnel_weighting=0"},
    {"printpt-nee", "printpt/nee=1"},
    // Light tracing (the sensor must have the patch footprint): the light
    // side scoring into every pixel (no hybrid), scoring at collisions,
    // along tracks at other spacings, more particles per block.
    {"lighttrace-no-hybrid", "lighttrace/lighttrace_hybrid=0"},
    {"lighttrace-collisions", "lighttrace/lighttrace_scoring=collisions"},
    {"lighttrace-tracks-0.5", "lighttrace/lighttrace_track_spacing_mfp=0.5"},
    {"lighttrace-tracks-2", "lighttrace/lighttrace_track_spacing_mfp=2"},
    {"lighttrace-p4", "lighttrace/particles_per_pixel=4"},
    {"lighttrace-p16", "lighttrace/particles_per_pixel=16"},
    // The textbook tracker: one majorant for the whole grid instead of one per brick.
    {"volpath-global-majorant", "volpath/majorants=global"},
    {"printpt-global-majorant", "printpt/majorants=global"},
    // Decomposition tracking: each brick's least extinction sampled analytically.
    {"volpath-decomposition", "volpath/majorants=decomposition/channel_sampling=separate"},
    {"printpt-decomposition", "printpt/majorants=decomposition/channel_sampling=separate"},
    // Three channels: one pass per channel, or one path for all three.
    {"volpath-separate", "volpath/channel_sampling=separate"},
    {"volpath-hero", "volpath/channel_sampling=hero"},
    {"volpath-spectral", "volpath/channel_sampling=spectral"},
    {"printpt-separate", "printpt/channel_sampling=separate"},
    {"printpt-hero", "printpt/channel_sampling=hero"},
    {"printpt-spectral", "printpt/channel_sampling=spectral"},
};

// The enum's value of that name, into `out`.
template <class Enum, size_t N>
void setChoice(const std::string& key, const std::array<EnumName<Enum>, N>& names, const std::string& value,
               Enum& out) {
    const std::optional<Enum> parsed = parseEnum(names, value);
    if (!parsed) throw std::invalid_argument(key + ": must be " + enumNames(names));
    out = *parsed;
}

// One override of a configuration: a render-block name (majorants,
// channel_sampling) or a key of the estimator's own, as the scene file
// spells it ("k" is printpt's branches).
void applyOverride(RenderSettings& s, std::string key, const std::string& value) {
    if (key == "k") key = "branches";
    if (key == "majorants") return setChoice(key, kMajorantsNames, value, s.majorants);
    if (key == "channel_sampling") return setChoice(key, kChannelSamplingNames, value, s.channelSampling);
    const ParameterInfo* info = findParameter(integratorKindOf(s).factory.parameters(), key);
    if (info && info->isText()) {
        s.parameters.setText(key, value);
        return;
    }
    try {
        s.parameters.set(key, value == "true" ? 1.0 : value == "false" ? 0.0 : std::stod(value));
    } catch (const std::exception&) {
        throw std::invalid_argument(key + ": needs a number");
    }
}

}  // namespace

std::optional<RenderSettings> parseConfiguration(const std::string& spec, const RenderSettings& base) {
    std::vector<std::string> parts = splitList(spec, '/');
    if (parts.empty()) return std::nullopt;
    for (const auto& [name, variant] : kVariants)
        if (parts[0] == name) {
            std::vector<std::string> own = splitList(variant, '/');
            parts.erase(parts.begin());
            parts.insert(parts.begin(), own.begin(), own.end());
            break;
        }
    if (!findIntegratorKind(parts[0])) return std::nullopt;
    RenderSettings s = base;
    setIntegrator(s, parts[0]);  // the scene's keys that this estimator reads
    s.reentry = false;
    for (size_t i = 1; i < parts.size(); ++i) {
        const size_t eq = parts[i].find('=');
        if (eq == std::string::npos) throw UsageError("configuration '" + spec + "': overrides are key=value");
        try {
            applyOverride(s, parts[i].substr(0, eq), parts[i].substr(eq + 1));
        } catch (const std::invalid_argument& e) {
            throw UsageError("configuration '" + spec + "': " + e.what());
        }
    }
    const IntegratorKind& kind = integratorKindOf(s);
    if (auto problem = checkParameters(kind.factory.parameters(), s.parameters, kind.name))
        throw UsageError("configuration '" + spec + "': " + problem->key + ": " + problem->what);
    if (std::string why = majorantsRefusal(s); !why.empty())
        throw UsageError("configuration '" + spec + "': majorants: " + why);
    return s;
}

std::vector<std::string> configurationNames() {
    std::vector<std::string> names;
    for (const IntegratorKind& k : integratorKinds()) names.push_back(k.name);
    for (const auto& v : kVariants) names.push_back(v.first);
    return names;
}

ChosenConfigurations chooseConfigurations(const std::string& list, const RenderSettings& base) {
    ChosenConfigurations chosen;
    chosen.names = splitList(list);
    for (const std::string& n : chosen.names) {
        auto s = parseConfiguration(n, base);
        if (!s) {
            std::string known;
            for (const std::string& k : configurationNames()) known += " " + k;
            throw UsageError("unknown configuration '" + n + "'; known:" + known + " (each takes /key=value overrides)");
        }
        chosen.settings[n] = *s;
        chosen.needs |= sceneNeedsOf(*s);
    }
    return chosen;
}

}  // namespace pl
