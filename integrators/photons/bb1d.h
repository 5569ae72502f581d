// bb1d: photon beams gathered along query beams (UPBP's beam-beam estimator
// with a 1D kernel; Jarosz et al. 2011, Krivanek et al. 2014, Brecka 2021,
// 3.7.1), on the short beams of integrators/photons/photon_beams.h. A camera
// path walks as volpath's up to its first clear collision (no boundary
// within r: clear_region.h), and its flights are short query beams (each
// point of a flight is reached with probability its transmittance, so none
// is tracked); each gathers, where the flight's closest point is clear,
// every photon beam whose closest approach lies within the radius r, at
// points inside both segments:
//   throughput x sigma_s x phase(beam direction -> camera) x beam power
//   x K1(distance) / sin(angle between them),
// K1 being the biweight disc kernel of pb2d integrated along a line,
// 16 / (5 pi r) (1 - d^2 / r^2)^(5/2), and sigma_s that of the voxel at
// the camera segment's closest point. The flights up to the first clear
// collision gather every path that has a clear vertex; the walk's escapes
// bring the light of those that have none. Near the boundary the kernel
// would reach where no beam lies, and fall short by more than two radii
// show. The radius shrinks as (i + alpha) / (i + 1).
#pragma once

#include "integrators/photons/photon_beams.h"

namespace pl {

class Bb1d : public PhotonBeamEstimator {
public:
    Bb1d(const Scene& scene, const Sensor& sensor, BeamOptions options, Majorants majorants, uint64_t seed)
        : PhotonBeamEstimator(scene, sensor, options, 1, majorants, seed) {}

    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("bb1d", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    ChannelSample Li(const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry, int channel,
                     LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const override;
};

}  // namespace pl
