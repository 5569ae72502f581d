// The configurations printlight bench compares: every registered estimator
// by its name, with the scene's keys it reads, and named variants, each an
// estimator and its overrides. A configuration is a name and overrides
// after slashes, e.g. "printpt/k=1/rr_threshold=0.2/nee=1",
// "lighttrace/particles_per_pixel=2", "pb2d/beams_radius_voxels=4",
// "printpt-hero/majorants=global" (docs/performance.md, "What bench does").
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "integrators/render_settings.h"
#include "scene/scene.h"

namespace pl {

// The settings of configuration `spec`: the scene's (`base`), its keys
// that the estimator reads (setIntegrator) and the overrides; nullopt for an unknown name,
// UsageError for an override the estimator does not take.
std::optional<RenderSettings> parseConfiguration(const std::string& spec, const RenderSettings& base);

// The names bench knows: the estimators' and the variants'.
std::vector<std::string> configurationNames();

// The configurations a list names ("a,b,..."), and what the scene must
// load for them.
struct ChosenConfigurations {
    std::vector<std::string> names;
    std::map<std::string, RenderSettings> settings;
    SceneNeeds needs;
};
// UsageError for an unknown name, listing the known ones.
ChosenConfigurations chooseConfigurations(const std::string& list, const RenderSettings& base);

}  // namespace pl
