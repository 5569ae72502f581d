// pp3d: photons as points gathered at points (UPBP's point-point estimator
// with a 3D kernel; Krivanek et al. 2014, Brecka 2021, 3.7): the photons of
// an iteration are bre's (stored at every real collision with their power
// after the albedo), and a camera path walks as volpath's to its first real
// collision x where a ball of radius r cannot reach past the boundary
// (integrators/photons/clear_gather.h). There it gathers every photon y
// within r:
//   throughput after the albedo x phase(photon's direction -> camera)
//   x power / sigma_s(y) x K3(|x - y|),
// with K3 the biweight over the ball, 105 / (32 pi r^3) (1 - d^2 / r^2)^2.
// A photon's power over sigma_s where it was stored is its share of the
// fluence (collisions come at sigma_t times the fluence, and the power is
// after the albedo), so the kernel blurs only the fluence, not the
// halftone's jumps in sigma_s. The radius' cube shrinks as
// (i + alpha) / (i + 1); a pixel's reported error is the spread of its
// iterations and the bias each sees between its radius and half of it
// (two_radii.h). Separate channel passes only.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/option_table.h"
#include "core/sampling.h"
#include "integrators/integrator.h"
#include "integrators/photons/photon_map.h"
#include "integrators/photons/photon_parts.h"
#include "integrators/photons/progressive_radius.h"
#include "integrators/photons/two_radii.h"

namespace pl {

// The photons within the map's radius of x, gathered in the ball at both
// radii: the sum over photons y of K3(|x - y|) x weightedPhase(f) x power /
// sigma_s(y), f the phase (asymmetry g, x's) between the photon's direction
// and -dIn. pp3d weights f by 1; combined by its merge weight.
template <class WeightedPhase>
TwoRadii gatherBall(const PhotonMap& map, const ChannelLut& lut, const Point3f& x, const Vec3f& dIn, float g,
                    WeightedPhase&& weightedPhase) {
    const float r2 = map.radius_mm() * map.radius_mm();
    TwoRadii sum;
    map.forEachNearPoint(x, [&](const PhotonMap::Photon& ph) {
        const Vec3f v = ph.p - x;
        const float d2 = dot(v, v);
        const double sigmaS_perMm = double(lut.sigmaT_perMm[ph.label]) * lut.albedo[ph.label];
        if (!(d2 < r2) || !(sigmaS_perMm > 0.0)) return;
        const double f = hgPhase(dot(ph.dIn, -dIn), g);
        sum += ballBiweight(d2, r2) * (weightedPhase(f) * double(ph.power) / sigmaS_perMm);
    });
    return sum;
}

struct Pp3dOptions {
    // Photons traced per iteration for each sensor pixel.
    float photonsPerPixel = 4.0f;
    // The first iteration's kernel radius, in the smallest voxel side.
    float radius_voxels = 2.0f;
    // How fast the radius shrinks (0 < alpha < 1; 1 keeps it).
    float alpha = 0.75f;
};
// Its options by their scene-file names (core/option_table.h).
const std::vector<OptionParameter<Pp3dOptions>>& pp3dParameters();

class Pp3d : public Integrator {
public:
    Pp3d(const Scene& scene, const Sensor& sensor, Pp3dOptions options, Majorants majorants, uint64_t seed);

    static std::vector<ParameterInfo> parameters() { return describe(pp3dParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("pp3d", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    // Sample by sample, the iteration's photons, then every pixel's walk.
    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;

    // The kernel radius of iteration i (from 1).
    float radiusAt_mm(uint32_t iteration) const { return radius_.at_mm(iteration); }
    // The radiance arriving along -ray.d at ray.o (a ray from outside;
    // entry: where it meets the object, or none), with the kernel's bias.
    ChannelSample Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry, int channel,
                     LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const;

private:
    const Scene& scene_;
    PhotonSource photons_;      // each stored at every real collision
    ProgressiveRadius radius_;  // over a ball
};

}  // namespace pl
