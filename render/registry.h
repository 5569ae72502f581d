// The integrators by name: the one place that knows which exist, makes
// them, and says what each needs and refuses. Adding an integrator is its
// own file pair (the Integrator interface, its options in RenderSettings)
// and one entry in integratorKinds() (registry.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace pl {

struct IntegratorKind {
    const char* name;
    // What the scene must load for these settings.
    SceneNeeds (*needs)(const RenderSettings&);
    // Why these settings cannot run (one line, naming the scene key), or "".
    std::string (*refusal)(const RenderSettings&);
    // Whether it can take all three channels from one path (else a pass
    // per channel).
    bool (*threeChannelsInOnePath)(const RenderSettings&);
    std::unique_ptr<Integrator> (*make)(const Scene&, const Sensor&, const RenderSettings&,
                                        std::shared_ptr<HalfSpaceMeans>);
    // Whether every sample of a pixel is the same (a deterministic
    // predictor): one sample says all, and its error is bias, which more
    // time does not reduce.
    bool deterministic = false;
};

const std::vector<IntegratorKind>& integratorKinds();
// The kind of that name, or none.
const IntegratorKind* findIntegratorKind(const std::string& name);
// The settings' kind (settings.integrator must name one).
const IntegratorKind& integratorKindOf(const RenderSettings& settings);
// "volpath or printpt": for messages about a name that is none of them.
std::string integratorNames();
// What the scene must load for these settings' integrator.
inline SceneNeeds sceneNeedsOf(const RenderSettings& settings) { return integratorKindOf(settings).needs(settings); }

}  // namespace pl
