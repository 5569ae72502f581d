// The smallest estimator, as an example of adding one (docs/architecture.md,
// "Adding an integrator"): the light the object's surface mirrors, alone.
// A camera ray's radiance is the environment times the Fresnel reflectance
// where it first meets the object, or the environment where it misses; no
// light that entered comes back. Deterministic, so one sample says all.
// Its one key (`fresnel`) shows how an estimator's keys reach it from the
// scene file's render block.
#pragma once

#include <memory>

#include "integrators/integrator.h"

namespace pl::test {

// The Fresnel factor it mirrors with: the exact dielectric one, or
// Schlick's approximation.
enum class FresnelFactor { Exact, Schlick };

class SurfaceReflection : public PixelIntegrator {
public:
    SurfaceReflection(const Scene& scene, FresnelFactor fresnel) : scene_(scene), fresnel_(fresnel) {}

    // The render keys it reads.
    static std::vector<ParameterInfo> parameters();
    // What it declares: no fields or clearance; all three channels from one
    // ray; every sample the same. It takes every sensor (the default).
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    ChannelSample Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const override;
    RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
              PathStats& stats) const override;

private:
    RGB mirrored(const Ray& ray, PathStats& stats) const;
    const Scene& scene_;
    FresnelFactor fresnel_;
};

}  // namespace pl::test
