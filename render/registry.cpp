#include "render/registry.h"

#include <stdexcept>

#include "integrators/diffusion.h"
#include "integrators/learned.h"
#include "io/learned_model_io.h"

namespace pl {

namespace {
// The refusal of an estimator that traces no re-entry.
std::string refusalWithoutReentry(const char* name, const RenderSettings& s) {
    return s.volpath.reentry ? std::string(name) + " does not trace re-entry; the scene asks for \"reentry\": true"
                             : std::string();
}
}  // namespace

const std::vector<IntegratorKind>& integratorKinds() {
    static const std::vector<IntegratorKind> kinds = {
        {"volpath", [](const RenderSettings& s) { return SceneNeeds{false, s.volpath.clearanceFirst}; },
         [](const RenderSettings&) { return std::string(); },
         [](const RenderSettings&) { return true; },
         [](const Scene& scene, const Sensor&, const RenderSettings& s,
            std::shared_ptr<HalfSpaceMeans>) -> std::unique_ptr<Integrator> {
             return std::make_unique<VolPath>(scene, s.volpath);
         }},
        {"printpt",
         [](const RenderSettings& s) {
             return SceneNeeds{s.printpt.nee, s.printpt.clearance || s.printpt.ballWalks};
         },
         [](const RenderSettings& s) { return refusalWithoutReentry("printpt", s); },
         // Next-event estimation is single-channel: it keeps separate passes.
         [](const RenderSettings& s) { return !s.printpt.nee; },
         [](const Scene& scene, const Sensor&, const RenderSettings& s,
            std::shared_ptr<HalfSpaceMeans> controlMeans) -> std::unique_ptr<Integrator> {
             return std::make_unique<PrintPt>(scene, s.printpt, s.seed, std::move(controlMeans));
         }},
        {"lighttrace", [](const RenderSettings& s) { return SceneNeeds{s.printpt.nee, true}; },
         [](const RenderSettings& s) { return refusalWithoutReentry("lighttrace", s); },
         // Particles walk one channel: separate passes.
         [](const RenderSettings&) { return false; },
         [](const Scene& scene, const Sensor& sensor, const RenderSettings& s,
            std::shared_ptr<HalfSpaceMeans> controlMeans) -> std::unique_ptr<Integrator> {
             return std::make_unique<LightTrace>(scene, sensor, s.lighttrace, s.volpath, s.printpt, s.majorants, s.seed,
                                                 std::move(controlMeans));
         }},
        // Deterministic: one sample per pixel says all it has.
        {"diffusion", [](const RenderSettings&) { return SceneNeeds{false, false}; },
         [](const RenderSettings& s) { return refusalWithoutReentry("diffusion", s); },
         // Its bias bound goes with single-channel samples (sharedError).
         [](const RenderSettings&) { return false; },
         [](const Scene& scene, const Sensor& sensor, const RenderSettings&,
            std::shared_ptr<HalfSpaceMeans>) -> std::unique_ptr<Integrator> {
             return std::make_unique<Diffusion>(scene, sensor);
         },
         true},
        {"learned", [](const RenderSettings&) { return SceneNeeds{false, false}; },
         // Its model is read up front; whether it was trained for the
         // scene's materials and voxels is known once the scene is loaded.
         [](const RenderSettings& s) {
             std::string why = refusalWithoutReentry("learned", s);
             if (why.empty()) try {
                     loadLearnedModel(s.learnedModel);
                 } catch (const std::exception& e) {
                     why = e.what();
                 }
             return why;
         },
         [](const RenderSettings&) { return false; },
         [](const Scene& scene, const Sensor& sensor, const RenderSettings& s,
            std::shared_ptr<HalfSpaceMeans>) -> std::unique_ptr<Integrator> {
             return std::make_unique<Learned>(scene, sensor, loadLearnedModel(s.learnedModel));
         },
         true},
    };
    return kinds;
}

const IntegratorKind* findIntegratorKind(const std::string& name) {
    for (const IntegratorKind& k : integratorKinds())
        if (name == k.name) return &k;
    return nullptr;
}

const IntegratorKind& integratorKindOf(const RenderSettings& settings) {
    const IntegratorKind* kind = findIntegratorKind(settings.integrator);
    if (!kind) throw std::invalid_argument("unknown integrator '" + settings.integrator + "'");
    return *kind;
}

std::string integratorNames() {
    std::string names;
    const auto& kinds = integratorKinds();
    for (size_t i = 0; i < kinds.size(); ++i)
        names += (i == 0 ? "" : i + 1 == kinds.size() ? " or " : ", ") + std::string(kinds[i].name);
    return names;
}

}  // namespace pl
