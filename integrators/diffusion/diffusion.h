// diffusion: the fast approximate predictor (method and bias in
// docs/diffusion.md). Deterministic: per surface voxel (the sensor's, or
// the label grid's for a camera), the light that uniform surroundings
// bring out of the object along its normal is
//  - single scattering, exact through the labels in the column under the
//    voxel (the halftone's detail), the column taken as laterally uniform;
//  - multiple scattering, the photon beam diffusion profile summed over
//    the surface around the voxel (a cluster tree: far clusters count as
//    one point), each pair of surface points in the medium averaged from
//    their columns' effective media (the labels' coefficients weighted
//    by e^{-z / 0.1 mm}: the layer the light enters and leaves by).
// A ray reads the result as every surface-response predictor does
// (surface_response.h); the error bound is a share of the multiple
// scattering.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "integrators/surface_response.h"
#include "media/beam_diffusion.h"

namespace pl {

class Diffusion : public SurfaceResponse {
public:
    Diffusion(const Scene& scene, const Sensor& sensor);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("diffusion", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    // Per surface element (the patches' pixels): the light that leaves
    // along the normal per unit light transmitted in, by single and by
    // multiple scattering.
    const std::vector<RGB>& singleScattering() const { return single_; }
    const std::vector<RGB>& multipleScattering() const { return multiple_; }

private:
    std::vector<RGB> single_, multiple_;
};

}  // namespace pl
