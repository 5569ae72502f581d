#include "integrators/photons/bb1d.h"

#include <cmath>

#include "core/sampling.h"
#include "integrators/photons/clear_region.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/render_settings.h"
#include "integrators/volume_walk.h"

namespace pl {

std::unique_ptr<Integrator> Bb1d::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Bb1d>(scene, sensor, readOptions(beamParameters(), s.parameters), s.majorants, s.seed);
}

namespace {
// Beams closer to parallel than this (sin^2 of the angle, a cone of 1e-3
// rad) are left out: a small bias, against 1 / sin's round-off.
constexpr float kLeastSin2 = 1e-6f;
}  // namespace

ChannelSample Bb1d::Li(const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                       int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float r2 = map.radius_mm() * map.radius_mm();
    const float reach_mm = clearReach_mm(scene_, map.radius_mm());
    TwoRadii gathered;
    auto onFlight = [&](const Ray& flight, float tEnd_mm, const SingleChannelPath& path) {
        thread_local BeamSum sum;
        sum.clear();
        ClearAlong clear(scene_, flight, reach_mm, map.radius_mm());
        map.forEachNearSegment(flight, tEnd_mm, [&](uint32_t i) {
            const PhotonBeam& b = map.beam(i);
            // The closest points of the two lines: flight.at(t), b.o + s b.d.
            const Vec3f w = flight.o - b.o;
            const float c = dot(flight.d, b.d);
            const float sin2 = 1.0f - c * c;
            if (!(sin2 > kLeastSin2)) return;
            const float dw = dot(b.d, w), uw = dot(flight.d, w);
            const float t = (c * dw - uw) / sin2;
            if (t < 0.0f || t > tEnd_mm) return;
            const float s = dw + c * t;
            if (s < 0.0f || s > b.length_mm) return;
            const Vec3f between = w + flight.d * t - b.d * s;
            const float d2 = dot(between, between);
            if (!(d2 < r2) || !clear.at(t)) return;
            const Label l = medium.labelAt(scene_.medium->voxelAt(flight.at(t)));
            const double sigmaS_perMm = double(lut.sigmaT_perMm[l]) * lut.albedo[l];
            sum.add(i, lineBiweight(d2, map.radius_mm()) * (sigmaS_perMm / std::sqrt(double(sin2)) *
                                                             hgPhase(dot(b.d, -flight.d), lut.g[l]) * double(b.power)));
        });
        gathered += sum.total() * double(path.beta);
    };
    // The flights up to the first clear collision gathered all that lies
    // beyond it; before, the walk goes on as volpath's.
    auto onCollision = [&](const Point3f& x, const Vec3f&, Label, const SingleChannelPath&) {
        return isClear(scene_, x, reach_mm);
    };
    SingleChannelPath path{&lut, channel, scene_.environment[channel]};
    const float escaped = walkVolume(scene_, VolPathOptions{}, /*reentry=*/false, ray, path, medium, rng, stats,
                                     onFlight, onCollision, &entry);
    return kernelSample(escaped, gathered * insideToOutside(scene_));
}

}  // namespace pl
