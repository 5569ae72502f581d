#include "integrators/volpath.h"

#include "integrators/volume_walk.h"

namespace pl {

ChannelSample VolPath::Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                          PathStats& stats) const {
    return {traceOneChannel(scene_, channel, [&](auto path) { return trace(ray, path, medium, rng, stats); })};
}

RGB VolPath::LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Sampler& medium, Rng& rng,
                   PathStats& stats) const {
    return traceThreeChannels(scene_, sampling, hero, [&](auto path) { return trace(ray, path, medium, rng, stats); });
}

template <class Path>
typename Path::Value VolPath::trace(Ray ray, Path path, LabelMedium::Sampler& medium, Rng& rng,
                                    PathStats& stats) const {
    return walkVolume(scene_, options_, ray, path, medium, rng, stats, [](const Point3f&, const Vec3f&, Label, const Path&) {});
}

}  // namespace pl
