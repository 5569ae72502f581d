// combined: volpath and pp3d under one multiple-importance weighting, the
// way UPBP (Krivanek et al. 2014) combines its estimators, restricted to
// these two: full paths (volpath's walk, its light where it leaves) and
// merging at one vertex (pp3d's photons gathered in a ball at the camera
// path's first real collision x_k whose ball stays inside).
//
// Both techniques make the same paths; a path's pdf differs between them
// only at their ends, and the ratio of pdfs telescopes to the merging
// vertex. Along a path x_1 .. x_n in the medium, the camera side samples
// x_{i+1} with phase f_i x sigma_t(x_{i+1}) T / d^2, the light side x_i
// with f_{i+1} x sigma_t(x_i) T / d^2 (the transmittance, the distance,
// and the Fresnel choices at internal reflections are the same both ways).
// The photons enter uniformly over the area A with cosine-weighted
// directions (inside: n^2 cos / pi per steradian). So merging N photons in
// a ball of volume V at x_k, against the walk that went on from x_k:
//   p_merge / p_path = q = n^2 N V sigma_t(x_k) / (pi A f_k),
// with f_k the phase at x_k between the camera's flight and the next one
// (the photon's, reversed, when merging). The balance heuristic weights a
// merged photon by q / (1 + q) and the light the walk brings out after x_k
// by 1 / (1 + q). (The Fresnel factor where the light path entered and the
// roulettes are left out of q: the weights still sum to one for every
// path, so the combination stays unbiased up to the kernel's bias.)
//
// In these dense resins q is large (75-250 at an isotropic phase on the
// 3 mm cubes at pp3d's defaults: some 2000 photons per mm^2, sigma_t of
// 6-20 per mm, a ball of 2 voxels), so the merge takes almost all of the
// weight where it may gather, and the walk after x_k goes on only with
// probability 1 / (1 + q), weighted up by its inverse (roulette at the
// next collision): its light stays in the estimate at a fraction of the
// cost. The options are pp3d's (its photons, radius and schedule);
// the reported error covers the kernel's bias from two radii as pp3d's.
// Separate channel passes only.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "integrators/integrator.h"
#include "integrators/photons/photon_map.h"
#include "integrators/photons/photon_parts.h"
#include "integrators/photons/pp3d.h"
#include "integrators/photons/progressive_radius.h"

namespace pl {

class Combined : public Integrator {
public:
    Combined(const Scene& scene, const Sensor& sensor, Pp3dOptions options, Majorants majorants, uint64_t seed);

    static std::vector<ParameterInfo> parameters() { return describe(pp3dParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("combined", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;

    float radiusAt_mm(uint32_t iteration) const { return radius_.at_mm(iteration); }
    // The merges' pdfs over the walk's at a vertex x of extinction sigma_t
    // and phase f: q_point = point_mm sigma_t / f (point_mm = n^2 N V /
    // (pi A), the ball's V) and q_beam = beam / f (beam = n^2 N r^2 / A).
    struct MergeRatios {
        double point_mm;
        double beam;
    };
    MergeRatios mergeRatios(float radius_mm) const;
    // Where a merge may be: no boundary within the radius and the lift.
    float clearReach_mm(float radius_mm) const { return radius_mm + scene_.geometry->surfaceLift_mm(); }
    // The radiance arriving along -ray.d at ray.o (a ray from outside;
    // entry: where it meets the object, or none), with the kernel's bias.
    ChannelSample Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry, int channel,
                     LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const;

private:
    const Scene& scene_;
    PhotonSource photons_;
    ProgressiveRadius radius_;
};

}  // namespace pl
