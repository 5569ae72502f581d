#include "surface_reflection.h"

#include <cmath>

#include "core/fresnel.h"

namespace pl::test {

IntegratorCapabilities SurfaceReflection::capabilities(const RenderSettings&) {
    IntegratorCapabilities c;
    c.threeChannelsInOnePath = true;
    c.deterministic = true;
    return c;
}

std::unique_ptr<Integrator> SurfaceReflection::create(const Scene& scene, const Sensor&, const RenderSettings&) {
    return std::make_unique<SurfaceReflection>(scene);
}

RGB SurfaceReflection::mirrored(const Ray& ray, PathStats& stats) const {
    ++stats.paths;
    const std::optional<SurfaceHit> hit = scene_.geometry->intersect(ray);
    if (!hit) return scene_.environment;
    const float reflectance = fresnelDielectric(std::abs(dot(ray.d, hit->ns)), scene_.ior);
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
