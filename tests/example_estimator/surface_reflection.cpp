#include "surface_reflection.h"

#include <array>
#include <cmath>

#include "core/fresnel.h"
#include "integrators/render_settings.h"

namespace pl::test {

namespace {
constexpr std::array<EnumName<FresnelFactor>, 2> kFresnelNames{
    {{FresnelFactor::Exact, "exact"}, {FresnelFactor::Schlick, "schlick"}}};

// Schlick (1994): the normal-incidence reflectance ((n - 1) / (n + 1))^2
// raised toward 1 at grazing angles.
float schlick(float cosTheta, float ior) {
    const float r0 = (ior - 1) * (ior - 1) / ((ior + 1) * (ior + 1));
    return r0 + (1 - r0) * std::pow(1 - cosTheta, 5.0f);
}
}  // namespace

std::vector<ParameterInfo> SurfaceReflection::parameters() {
    return {describeChoice("fresnel", kFresnelNames, "the Fresnel factor: exact, or Schlick's approximation")};
}

IntegratorCapabilities SurfaceReflection::capabilities(const RenderSettings&) {
    IntegratorCapabilities c;
    c.threeChannelsInOnePath = true;
    c.deterministic = true;
    return c;
}

std::unique_ptr<Integrator> SurfaceReflection::create(const Scene& scene, const Sensor&,
                                                      const RenderSettings& settings) {
    return std::make_unique<SurfaceReflection>(
        scene, readChoice("fresnel", kFresnelNames, settings.parameters, FresnelFactor::Exact));
}

RGB SurfaceReflection::mirrored(const Ray& ray, PathStats& stats) const {
    ++stats.paths;
    const std::optional<SurfaceHit> hit = scene_.geometry->intersect(ray);
    if (!hit) return scene_.environment;
    const float cosTheta = std::abs(dot(ray.d, hit->ns));
    const float reflectance =
        fresnel_ == FresnelFactor::Schlick ? schlick(cosTheta, scene_.ior) : fresnelDielectric(cosTheta, scene_.ior);
    RGB L = scene_.environment;
    for (float& v : L) v *= reflectance;
    return L;
}

ChannelSample SurfaceReflection::Li(Ray ray, int channel, LabelMedium::Tracker&, Rng&, PathStats& stats) const {
    return {mirrored(ray, stats)[channel]};
}

RGB SurfaceReflection::LiRGB(Ray ray, ChannelSampling, int, LabelMedium::Tracker&, Rng&, PathStats& stats) const {
    return mirrored(ray, stats);
}

}  // namespace pl::test
