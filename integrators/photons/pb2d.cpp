#include "integrators/photons/pb2d.h"

#include "core/sampling.h"
#include "integrators/render_settings.h"
#include "integrators/volume_walk.h"

namespace pl {

std::unique_ptr<Integrator> Pb2d::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Pb2d>(scene, sensor, readOptions(beamParameters(), s.parameters), s.majorants, s.seed);
}

ChannelSample Pb2d::Li(const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                       int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float r2 = map.radius_mm() * map.radius_mm();
    TwoRadii gathered;
    // Only where the kernel's disc cannot reach past the boundary (no beam
    // lies beyond it: a disc cut there would miss their share): the block's
    // clearance, or else the nearest surface point; elsewhere the path
    // walks on as volpath's.
    const float reach_mm = map.radius_mm() + scene_.geometry->surfaceLift_mm();
    auto onCollision = [&](const Point3f& x, const Vec3f& dIn, Label label, const SingleChannelPath& path) {
        const bool clear = (scene_.clearance && scene_.clearance->at(x) >= reach_mm) ||
                           !scene_.geometry->closestPoint(x, reach_mm);
        if (!clear) return false;
        thread_local BeamSum sum;
        sum.clear();
        const float g = lut.g[label];
        map.forEachNearPoint(x, [&](uint32_t i) {
            const PhotonBeam& b = map.beam(i);
            const Vec3f v = x - b.o;
            const float s = dot(v, b.d);
            if (s < 0.0f || s > b.length_mm) return;
            const Vec3f across = v - b.d * s;  // not |v|^2 - s^2: that cancels on long beams (clear resin)
            const float d2 = dot(across, across);
            if (!(d2 < r2)) return;
            sum.add(i, discBiweight(d2, r2) * (hgPhase(dot(b.d, -dIn), g) * double(b.power)));
        });
        gathered += sum.total() * double(path.beta);
        return true;
    };
    SingleChannelPath path{&lut, channel, scene_.environment[channel]};
    const float escaped = walkVolume(scene_, VolPathOptions{}, /*reentry=*/false, ray, path, medium, rng, stats,
                                     [](const Ray&, float, const SingleChannelPath&) {}, onCollision, &entry);
    return kernelSample(escaped, gathered * insideToOutside());
}

}  // namespace pl
