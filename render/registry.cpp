#include "render/registry.h"

#include <stdexcept>

#include "integrators/photons/bb1d.h"
#include "integrators/photons/bre.h"
#include "integrators/photons/combined.h"
#include "integrators/diffusion/diffusion.h"
#include "integrators/learned/learned.h"
#include "integrators/lighttrace/lighttrace.h"
#include "integrators/photons/pb2d.h"
#include "integrators/photons/pp3d.h"
#include "integrators/printpt/printpt.h"
#include "integrators/volpath/volpath.h"

namespace pl {

namespace {
std::deque<IntegratorKind>& kinds() {
    static std::deque<IntegratorKind> all = {
        {"volpath", factoryOf<VolPath>()},
        {"printpt", factoryOf<PrintPt>()},
        {"lighttrace", factoryOf<LightTrace>()},
        {"diffusion", factoryOf<Diffusion>()},
        {"learned", factoryOf<Learned>()},
        {"bre", factoryOf<Bre>()},
        {"pp3d", factoryOf<Pp3d>()},
        {"pb2d", factoryOf<Pb2d>()},
        {"bb1d", factoryOf<Bb1d>()},
        {"combined", factoryOf<Combined>()},
    };
    return all;
}
}  // namespace

const std::deque<IntegratorKind>& integratorKinds() { return kinds(); }

void registerIntegrator(const IntegratorKind& kind) {
    if (findIntegratorKind(kind.name))
        throw std::invalid_argument(std::string("an integrator named '") + kind.name + "' exists already");
    kinds().push_back(kind);
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

void setIntegrator(RenderSettings& settings, const std::string& name) {
    settings.integrator = name;
    settings.parameters.keepOnly(integratorKindOf(settings).factory.parameters());
}

std::string refusalOf(const RenderSettings& settings) {
    const IntegratorKind& kind = integratorKindOf(settings);
    if (auto problem = checkParameters(kind.factory.parameters(), settings.parameters, kind.name))
        return "render." + problem->key + ": " + problem->what;
    if (std::string why = majorantsRefusal(settings); !why.empty()) return "render.majorants: " + why;
    return kind.factory.refusal(settings);
}

std::string integratorNames() {
    std::string names;
    const auto& all = integratorKinds();
    for (size_t i = 0; i < all.size(); ++i)
        names += (i == 0 ? "" : i + 1 == all.size() ? " or " : ", ") + std::string(all[i].name);
    return names;
}

}  // namespace pl
