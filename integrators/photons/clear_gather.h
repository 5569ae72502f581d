// Where pb2d and pp3d gather: a camera path walks as volpath's to its first
// real collision x whose kernel (a disc across the beams, a ball around the
// photons) of radius r cannot reach past the boundary, and gathers there.
// Nearer the boundary the kernel would reach where no photon lies, and the
// estimate would fall short (30-50 % on slabs whose mean free path is a
// tenth of the radius, gathering at the first collision); there the walk
// goes on as volpath's, and the light it brings out is volpath's.
#pragma once

#include <optional>

#include "core/film.h"
#include "integrators/photons/clear_region.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/two_radii.h"
#include "integrators/volume_walk.h"
#include "scene/scene.h"

namespace pl {

// The radiance arriving along -ray.d at ray.o (a ray from outside; entry:
// where it meets the object, or none). gatherAt(x, dIn, label) returns what
// the photons near x send towards -dIn, at both radii, in the photons' unit,
// per unit throughput after the albedo.
template <class GatherAt>
ChannelSample gatherWhereClear(const Scene& scene, float radius_mm, const Ray& ray,
                               const std::optional<SurfaceHit>& entry, int channel, LabelMedium::Tracker& medium,
                               Rng& rng, PathStats& stats, GatherAt&& gatherAt) {
    const ChannelLut& lut = scene.medium->lut(channel);
    const float reach_mm = clearReach_mm(scene, radius_mm);
    TwoRadii gathered;
    auto onCollision = [&](const Point3f& x, const Vec3f& dIn, Label label, const SingleChannelPath& path) {
        if (!isClear(scene, x, reach_mm)) return false;
        gathered += gatherAt(x, dIn, label) * double(path.beta);
        return true;
    };
    SingleChannelPath path{&lut, channel, scene.environment[channel]};
    const float escaped = walkVolume(scene, VolPathOptions{}, /*reentry=*/false, ray, path, medium, rng, stats,
                                     [](const Ray&, float, const SingleChannelPath&) {}, onCollision, &entry);
    return kernelSample(escaped, gathered * insideToOutside(scene));
}

}  // namespace pl
