// volpath: the plain reference volumetric path tracer (the walk of
// integrators/volume_walk.h), no depth cap unless asked. It is the
// oracle every specialised estimator is checked against: keep it simple.
#pragma once

#include <cstdint>

#include "core/option_table.h"
#include "integrators/integrator.h"
#include "integrators/volume_walk.h"

namespace pl {

// volpath's options by their scene-file names (core/option_table.h).
const std::vector<OptionParameter<VolPathOptions>>& volPathParameters();

class VolPath : public PixelIntegrator {
public:
    // Three channels from one path; the clearance if flights look for it first.
    static std::vector<ParameterInfo> parameters() { return describe(volPathParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);
    // reentry: trace light that leaves the object back against it.
    VolPath(const Scene& scene, VolPathOptions options, bool reentry)
        : scene_(scene), options_(options), reentry_(reentry) {}

    ChannelSample Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                     PathStats& stats) const override;
    RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
              PathStats& stats) const override;

private:
    // firstHit: the geometry's answer along `ray`, if the caller has it.
    template <class Path>
    typename Path::Value trace(Ray ray, Path path, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats,
                               const std::optional<SurfaceHit>* firstHit = nullptr) const;

    const Scene& scene_;
    VolPathOptions options_;
    bool reentry_;
};

}  // namespace pl
