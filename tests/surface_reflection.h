// The smallest estimator, as an example of adding one (docs/architecture.md,
// "Adding an integrator"): the light the object's surface mirrors, alone.
// A camera ray's radiance is the environment times the Fresnel reflectance
// where it first meets the object, or the environment where it misses; no
// light that entered comes back. Deterministic, so one sample says all.
#pragma once

#include <memory>

#include "integrators/integrator.h"

namespace pl::test {

class SurfaceReflection : public PixelIntegrator {
public:
    explicit SurfaceReflection(const Scene& scene) : scene_(scene) {}

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
};

}  // namespace pl::test
