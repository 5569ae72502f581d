// combined: volpath and pp3d (and, with combined_beams, bre's queries)
// under one multiple-importance weighting, the way UPBP (Krivanek et al.
// 2014) combines its estimators, restricted to these, each merging at the
// camera path's first clear vertex x_k (a real collision, or a point of a
// flight, with no boundary within the radius: clear_region.h):
//  - path: volpath's walk goes on from x_k, its light where it leaves;
//  - point: the photons in a ball around x_k, a collision (pp3d's);
//  - beam (combined_beams): the photons in a disc around a flight before
//    any clear collision, at its clear points up to where the flight ends
//    (a short beam: it reaches t with probability T(t), bre's
//    transmittance).
//
// The techniques make the same paths, and their pdfs differ only at x_k:
// the ratios telescope. Along a path x_1 .. x_n in the medium, the camera
// side samples x_{i+1} with phase f_i x sigma_t(x_{i+1}) T / d^2, the light
// side x_i with f_{i+1} x sigma_t(x_i) T / d^2 (the transmittance, the
// distance and the Fresnel choices at internal reflections are the same
// both ways). The photons enter uniformly over the area A with
// cosine-weighted directions (inside: n^2 cos / pi per steradian). With N
// photons an iteration, a ball of volume V and a disc of radius r:
//   q_point = p_point / p_path = n^2 N V sigma_t(x_k) / (pi A f_k),
//   q_beam  = p_beam / p_path  = n^2 N r^2 / (A f_k),
// f_k the phase at x_k between the camera's flight and the next one (the
// photon's, reversed, when merging). The balance heuristic weights each
// merge by q / (1 + q_point + q_beam) and the walk's light after x_k by
// 1 / (1 + q_point + q_beam). (The Fresnel factor where the light path
// entered and the roulettes are left out of q: the weights still sum to
// one for every path, so the combination stays unbiased up to the
// kernels' bias.) Every technique takes x_k, and its resin, at the
// camera's point (the collision, or the flight's point nearest the
// photon), as the walk finds its first clear collision: so each path has
// one x_k whichever technique made it.
//
// The merges take most of the weight where they may gather in these dense
// resins (q_point is 10 or more), so the walk after x_k goes on only with
// its weight's probability, weighted up by its inverse (a roulette at its
// next collision): its light stays in the estimate at a fraction of the
// cost. One radius for ball and disc, shrinking as pp3d's; the reported
// error covers the kernels' bias from two radii as pp3d's. Separate
// channel passes only. Measured in docs/particle-methods.md.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/option_table.h"
#include "integrators/integrator.h"
#include "integrators/photons/photon_map.h"
#include "integrators/photons/photon_parts.h"
#include "integrators/photons/progressive_radius.h"

namespace pl {

struct CombinedOptions {
    // Photons traced per iteration for each sensor pixel.
    float photonsPerPixel = 4.0f;
    // The first iteration's kernel radius, in the smallest voxel side.
    float radius_voxels = 2.0f;
    // How fast the radius shrinks (0 < alpha < 1; 1 keeps it).
    float alpha = 0.75f;
    // Also bre's queries along the camera's flights (short beams).
    bool beams = false;
};
// Its options by their scene-file names (core/option_table.h).
const std::vector<OptionParameter<CombinedOptions>>& combinedParameters();

class Combined : public Integrator {
public:
    Combined(const Scene& scene, const Sensor& sensor, CombinedOptions options, Majorants majorants, uint64_t seed);

    static std::vector<ParameterInfo> parameters() { return describe(combinedParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("combined", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;

    float radiusAt_mm(uint32_t iteration) const { return radius_.at_mm(iteration); }
    // The merges' pdfs over the walk's at a vertex of extinction sigma_t
    // and phase f, but for those: q_point = ballPerExtinction_mm sigma_t / f
    // (n^2 N V / (pi A), V the ball's volume) and q_beam = discTimesPhase / f
    // (n^2 N r^2 / A; 0 without the beams).
    struct MergeRatios {
        double ballPerExtinction_mm;
        double discTimesPhase;
    };
    MergeRatios mergeRatios(float radius_mm) const;

    // The radiance arriving along -ray.d at ray.o (a ray from outside;
    // entry: where it meets the object, or none), with the kernel's bias.
    ChannelSample Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry, int channel,
                     LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const;

private:
    const Scene& scene_;
    PhotonSource photons_;
    ProgressiveRadius radius_;
    bool beams_;
};

}  // namespace pl
