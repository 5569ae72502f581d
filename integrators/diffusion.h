// diffusion: the fast approximate predictor (issue 30; method and bias in
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
// A ray reads the value of the surface voxel it hits, after Fresnel, plus
// the surroundings' mirror reflection. The sample's sharedError is the
// predictor's bias bound (its error is bias, not noise).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "core/sensors.h"
#include "integrators/integrator.h"
#include "media/beam_diffusion.h"

namespace pl {

class Diffusion : public Integrator {
public:
    Diffusion(const Scene& scene, const Sensor& sensor);
    ~Diffusion() override;

    ChannelSample Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                     PathStats& stats) const override;
    RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Sampler& medium, Rng& rng,
              PathStats& stats) const override;

    // Per surface element (the patches' pixels): the light that leaves
    // along the normal per unit light transmitted in, by single and by
    // multiple scattering.
    const std::vector<RGB>& singleScattering() const { return single_; }
    const std::vector<RGB>& multipleScattering() const { return multiple_; }

private:
    // The radiance along -ray.d at ray.o, and its bias bound.
    RGB radiance(const Ray& ray, int reflectionsLeft, RGB* biasBound) const;

    const Scene& scene_;
    std::unique_ptr<SurfaceVoxelSensor> ownSurface_;  // when the sensor has no patches
    const SurfaceVoxelSensor* surface_ = nullptr;
    std::vector<RGB> single_, multiple_;
};

}  // namespace pl
