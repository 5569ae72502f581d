// The integrators by name: the one place that knows which exist. Each entry
// is a name and the estimator's factory, read from the class's own static
// members (integrators/integrator.h): what it declares for a render's
// settings, why it refuses some, and how it is made. Adding an integrator
// is its own file pair and one line in the list in registry.cpp;
// docs/architecture.md, "Adding an integrator".
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "integrators/render_settings.h"
#include "scene/scene.h"

namespace pl {

struct IntegratorFactory {
    // The render keys the estimator reads (RenderSettings::parameters).
    std::vector<ParameterInfo> (*parameters)();
    IntegratorCapabilities (*capabilities)(const RenderSettings&);
    // Why these settings cannot run (one line, naming the scene key), or "".
    std::string (*refusal)(const RenderSettings&);
    std::unique_ptr<Integrator> (*create)(const Scene&, const Sensor&, const RenderSettings&);
};

// The factory of estimator class E.
template <class E>
IntegratorFactory factoryOf() {
    return {&E::parameters, &E::capabilities, &E::refusal, &E::create};
}

struct IntegratorKind {
    const char* name;
    IntegratorFactory factory;
};

// A deque: the kinds stay where they are when one is registered.
const std::deque<IntegratorKind>& integratorKinds();
// Adds a kind after the built-in ones (an estimator outside the library,
// e.g. a test's); its name must be new.
void registerIntegrator(const IntegratorKind& kind);
// The kind of that name, or none.
const IntegratorKind* findIntegratorKind(const std::string& name);
// The settings' kind (settings.integrator must name one).
const IntegratorKind& integratorKindOf(const RenderSettings& settings);
// Names the estimator of these settings (one of integratorKinds()): the
// parameters it does not read, another estimator's, are dropped.
void setIntegrator(RenderSettings& settings, const std::string& name);
// "volpath, printpt or lighttrace": for messages about a name that is none of them.
std::string integratorNames();
// What the settings' integrator declares for them.
inline IntegratorCapabilities capabilitiesOf(const RenderSettings& settings) {
    return integratorKindOf(settings).factory.capabilities(settings);
}
// What the scene must load for these settings' integrator.
inline SceneNeeds sceneNeedsOf(const RenderSettings& settings) { return capabilitiesOf(settings).needs; }
// Why the settings' integrator cannot run them, or "": a parameter it
// does not read or out of its range ("render.KEY: what"), or its own refusal.
std::string refusalOf(const RenderSettings& settings);

}  // namespace pl
