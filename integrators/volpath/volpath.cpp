#include "integrators/volpath/volpath.h"

#include "integrators/render_settings.h"
#include "integrators/volume_walk.h"

namespace pl {

const std::vector<OptionParameter<VolPathOptions>>& volPathParameters() {
    using O = VolPathOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"max_depth", &O::maxDepth, -1e9, 1e9, false, "must be a whole number in -1e9..1e9",
         "scattering events per path; negative: unlimited"},
        {"clearance_first", &O::clearanceFirst, 0, 0, false, "",
         "flights look for the clearance before the boundary (false: every flight starts with a boundary query)"},
    };
    return parameters;
}

IntegratorCapabilities VolPath::capabilities(const RenderSettings& settings) {
    IntegratorCapabilities c;
    c.needs = {false, readOptions(volPathParameters(), settings.parameters).clearanceFirst};
    c.threeChannelsInOnePath = true;
    c.recordsFootprints = true;
    return c;
}

std::unique_ptr<Integrator> VolPath::create(const Scene& scene, const Sensor&, const RenderSettings& settings) {
    return std::make_unique<VolPath>(scene, readOptions(volPathParameters(), settings.parameters), settings.reentry);
}

ChannelSample VolPath::Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                          PathStats& stats) const {
    // The entry, asked once: the walk starts from it, and it names the pool.
    const std::optional<SurfaceHit> entry = scene_.geometry->intersect(ray);
    ChannelSample sample{
        traceOneChannel(scene_, channel, [&](auto path) { return trace(ray, path, medium, rng, stats, &entry); })};
    poolByEntry(sample, scene_, ray, entry, channel, medium);
    return sample;
}

RGB VolPath::LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
                   PathStats& stats) const {
    return traceThreeChannels(scene_, sampling, hero, [&](auto path) { return trace(ray, path, medium, rng, stats); });
}

template <class Path>
typename Path::Value VolPath::trace(Ray ray, Path path, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats,
                                    const std::optional<SurfaceHit>* firstHit) const {
    return walkVolume(
        scene_, options_, reentry_, ray, path, medium, rng, stats, [](const Ray&, float, const Path&) {},
        [](const Point3f&, const Vec3f&, Label, const Path&) {}, firstHit);
}

}  // namespace pl
