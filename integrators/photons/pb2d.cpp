#include "integrators/photons/pb2d.h"

#include "core/sampling.h"
#include "integrators/photons/clear_gather.h"
#include "integrators/render_settings.h"

namespace pl {

std::unique_ptr<Integrator> Pb2d::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Pb2d>(scene, sensor, readOptions(beamParameters(), s.parameters), s.majorants, s.seed);
}

ChannelSample Pb2d::Li(const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                       int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float r2 = map.radius_mm() * map.radius_mm();
    auto gatherAt = [&](const Point3f& x, const Vec3f& dIn, Label label) {
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
        return sum.total();
    };
    return gatherWhereClear(scene_, map.radius_mm(), ray, entry, channel, medium, rng, stats, gatherAt);
}

}  // namespace pl
