// bre: progressive photon mapping with the beam radiance estimate (Jarosz
// et al. 2008; Brecka 2021, 3.7.2) in heterogeneous label media, for any
// sensor. Each sample of a pass is one iteration (Knaus and Zwicker 2011):
//  - a fresh set of photons enters from the environment, uniform by area
//    over the mesh with cosine-weighted directions (each carries Le pi A /
//    N, times the Fresnel transmission in), walks with volpath's walk and
//    is stored at each real scattering event with its power after the
//    albedo;
//  - every pixel's camera ray takes the environment mirrored at its entry,
//    refracts in and, along each straight segment inside (internal
//    reflections followed with their Fresnel weight), gathers the photons
//    within the iteration's radius of it: kernel x transmittance from the
//    entry x phase function towards the camera x power, converted from the
//    radiance inside to the path tracers' unit (1 / n^2); the environment
//    that comes straight through is added by its transmittance.
// Transmittance along a query comes from one regular-tracking pass over
// the voxels (a vector of constant-density segments), cut where it falls
// below 1 % (the photons beyond are left out, a small bias). The radius
// shrinks as r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), so the bias vanishes
// as iterations go on; a pixel's reported error is the spread of its
// iterations and the bias each iteration sees between its radius and half
// of it (integrators/photons/two_radii.h). Separate channel passes only.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/option_table.h"
#include "integrators/integrator.h"
#include "integrators/photons/photon_map.h"
#include "integrators/photons/photon_parts.h"
#include "integrators/photons/progressive_radius.h"
#include "integrators/photons/two_radii.h"
#include "integrators/volpath/volpath.h"

namespace pl {

struct BreOptions {
    // Photons traced per iteration for each sensor pixel.
    float photonsPerPixel = 4.0f;
    // The first iteration's kernel radius, in the smallest voxel side.
    float radius_voxels = 1.0f;
    // How fast the radius shrinks (0 < alpha < 1: the bias and the variance
    // both fall; near 1 the variance falls faster).
    float alpha = 0.75f;
};
// Its options by their scene-file names (core/option_table.h).
const std::vector<OptionParameter<BreOptions>>& breParameters();

class Bre : public Integrator {
public:
    Bre(const Scene& scene, const Sensor& sensor, BreOptions options, Majorants majorants, uint64_t seed);

    static std::vector<ParameterInfo> parameters() { return describe(breParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("bre", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    // Sample by sample, the iteration's photons, then every pixel's query.
    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;

    // The kernel radius of iteration i (from 1).
    float radiusAt_mm(uint32_t iteration) const;
    // The photons of sample `sample` in a channel.
    PhotonMap tracePhotons(int channel, uint32_t sample, PathStats& stats) const;
    // The radiance arriving along -ray.d at ray.o (a ray from outside;
    // entry: where it meets the object, or none), gathered from the map,
    // with the kernel's bias (integrators/photons/two_radii.h).
    ChannelSample gather(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                         int channel, LabelMedium::Tracker& medium) const;

private:
    // The photons gathered along one straight segment inside, from its
    // origin up to tEnd_mm, and the transmittance over the whole segment
    // (0 where the 1 % cut-off fell short of it).
    struct SegmentGather {
        TwoRadii radiance;  // inside the medium, in the photons' units
        float transmittance;
    };
    SegmentGather gatherSegment(const PhotonMap& map, const Ray& ray, float tEnd_mm, int channel,
                                LabelMedium::Tracker& medium) const;

    const Scene& scene_;
    PhotonSource photons_;     // each stored at every real collision
    ProgressiveRadius radius_;  // over a disc
};

}  // namespace pl
