// The deterministic predictors' common part (diffusion, learned): each
// surface element (a patch pixel: the sensor's, or the label grid's for a
// camera) holds the light it sends out along its normal per unit light
// transmitted in under uniform surroundings, and a bound on that value's
// error. A ray reads the value of the element it hits, after Fresnel,
// plus the surroundings' mirror reflection; the sample's sharedError is
// the bound (the error is bias, not noise).
#pragma once

#include <memory>
#include <vector>

#include "core/sensors.h"
#include "integrators/integrator.h"

namespace pl {

// A surface element's patch: its area-weighted centre and outward normal.
struct SurfacePoint {
    Point3f p;
    Vec3f normal;
    float area_mm2;
};
SurfacePoint surfacePointOf(const SurfaceVoxelSensor& surface, size_t pixel);

class SurfaceResponse : public PixelIntegrator {
public:
    // Deterministic; single-channel passes (the error bound goes with
    // single-channel samples, as their sharedError).
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    ~SurfaceResponse() override;

    ChannelSample Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                     PathStats& stats) const override;
    RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
              PathStats& stats) const override;

    // Per element: the response and its error bound.
    const std::vector<RGB>& response() const { return response_; }
    const std::vector<RGB>& errorBound() const { return errorBound_; }
    // Elements over nearly clear resin, whose error is the whole range.
    size_t elementsOverClearResin() const { return elementsOverClearResin_; }

protected:
    SurfaceResponse(const Scene& scene, const Sensor& sensor);

    // The elements: a surface-voxel sensor with every surface voxel's patch.
    const SurfaceVoxelSensor& surface() const { return *surface_; }
    size_t elementCount() const { return surface_->pixelCount(); }
    SurfacePoint surfacePoint(size_t i) const { return surfacePointOf(*surface_, i); }

    // Called by each predictor once it has filled its elements. Light
    // that crosses clear resin scatters far from where it entered, which
    // neither predictor models: an element whose first mm along -normal
    // has an optical depth under 1 in some channel gets the whole range
    // as its error (under uniform surroundings a response lies in [0, 1]).
    void coverElementsOverClearResin();

    const Scene& scene_;
    std::vector<RGB> response_, errorBound_;  // filled by the predictor

private:
    // The radiance along -ray.d at ray.o, and its error bound.
    RGB radiance(const Ray& ray, int reflectionsLeft, RGB* bound) const;

    std::unique_ptr<SurfaceVoxelSensor> ownSurface_;  // when the sensor has no patches
    size_t elementsOverClearResin_ = 0;
    const SurfaceVoxelSensor* surface_ = nullptr;
};

}  // namespace pl
