// pb2d: photon beams gathered at points (UPBP's point-beam estimator with a
// 2D kernel; Krivanek et al. 2014, Brecka 2021, 3.7.1), on the short beams
// of integrators/photons/photon_beams.h. A camera path walks as volpath's
// to its first real collision x at least r from the boundary (the surface
// clearance) and gathers there, over every beam that passes within the
// radius r of x (x's projection on the beam between its ends):
//   throughput after the albedo x phase(beam direction -> camera)
//   x beam power x K2(distance from the beam),
// with K2 the biweight kernel over the disc across the beam,
// 3 / (pi r^2) (1 - d^2 / r^2)^2; the light its walk brought out before
// is volpath's. Nearer the boundary the disc would reach past it, where no
// beam lies, and the estimate falls short (30-50 % on slabs whose mean free
// path is a tenth of the radius, gathering at the first collision). The
// radius' square shrinks as (i + alpha) / (i + 1).
#pragma once

#include "integrators/photons/photon_beams.h"

namespace pl {

class Pb2d : public PhotonBeamEstimator {
public:
    Pb2d(const Scene& scene, const Sensor& sensor, BeamOptions options, Majorants majorants, uint64_t seed)
        : PhotonBeamEstimator(scene, sensor, options, 2, majorants, seed) {}

    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("pb2d", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    ChannelSample Li(const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry, int channel,
                     LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const override;
};

}  // namespace pl
