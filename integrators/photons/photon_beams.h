// Photon beams (Jarosz et al. 2011; Krivanek et al. 2014, UPBP) in
// heterogeneous label media: what pb2d and bb1d share. Each sample of a
// pass is one iteration (Knaus and Zwicker 2011):
//  - a fresh set of photons enters from the environment as bre's do
//    (uniform by area, cosine-weighted, the Fresnel transmission in) and
//    walks with volpath's walk; every flight is a *short* beam: from where
//    it starts to the next real collision (or the boundary), carrying the
//    photon's power. Delta tracking ends a flight at distance t with
//    probability exactly 1 - T(t), so a short beam's power needs no
//    transmittance along it (UPBP's short beams; Brecka 2021, 3.7.1):
//    nothing is tracked at query time, which is what makes beams cheap
//    in a halftone, where every transmittance is a walk over voxels;
//  - every pixel's camera ray walks the same way (the environment
//    reflected at the entry or seen straight through, and what the walk
//    brings out, counts as volpath's), and the estimator gathers the beams
//    near that path with the kernel radius of the iteration: pb2d at its
//    first collision at least the radius from the boundary, bb1d along its
//    flights up to its first collision.
// The radius shrinks with the kernel's dimensions (progressive_radius.h),
// so the bias vanishes as iterations go on; a pixel's reported error is the
// spread of its iterations and the bias each iteration sees between its
// radius and half of it (two_radii.h). Separate channel passes only.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/option_table.h"
#include "integrators/photons/cell_grid.h"
#include "integrators/integrator.h"
#include "integrators/photons/photon_parts.h"
#include "integrators/photons/progressive_radius.h"
#include "integrators/photons/two_radii.h"
#include "integrators/volpath/volpath.h"

namespace pl {

struct BeamOptions {
    // Photons traced per iteration for each sensor pixel (each leaves a
    // beam per flight).
    float photonsPerPixel = 1.0f;
    // The first iteration's kernel radius, in the smallest voxel side.
    float radius_voxels = 1.0f;
    // How fast the radius shrinks (0 < alpha < 1; 1 keeps it).
    float alpha = 0.75f;
};
// Its options by their scene-file names (core/option_table.h).
const std::vector<OptionParameter<BeamOptions>>& beamParameters();

struct PhotonBeam {
    Point3f o;
    Vec3f d;          // unit
    float length_mm;  // to the next real collision or the boundary
    float power;      // the photon's, along the whole beam
    Point3f at(float s_mm) const { return o + d * s_mm; }
};

// The beams of one iteration in one channel, filed in every cell of side
// the kernel radius that they cross: a query within the radius of a point
// or a segment visits the cells within one cell of it (a beam can turn up
// in several of them).
class PhotonBeamMap {
public:
    PhotonBeamMap(std::vector<PhotonBeam> beams, float radius_mm, const Point3f& origin_mm);
    float radius_mm() const { return radius_mm_; }
    size_t size() const { return beams_.size(); }
    const PhotonBeam& beam(uint32_t i) const { return beams_[i]; }
    // Calls f(index) for the beams filed in the cells around p's.
    template <class F>
    void forEachNearPoint(const Point3f& p, F&& f) const {
        thread_local std::vector<uint64_t> keys;
        grid_.cellsAround(p, keys);
        grid_.forEachItem(keys, [&](size_t, uint32_t beam) { f(beam); });
    }
    // Calls f(index) for the beams filed in the cells near ray.at([0, tMax_mm]).
    template <class F>
    void forEachNearSegment(const Ray& ray, float tMax_mm, F&& f) const {
        thread_local std::vector<uint64_t> keys;
        grid_.cellsNear(ray, tMax_mm, keys);
        grid_.forEachItem(keys, [&](size_t, uint32_t beam) { f(beam); });
    }

private:
    std::vector<PhotonBeam> beams_;
    float radius_mm_;
    CellGrid grid_;
};

// The beams' contributions found near one query, each beam's once (a beam
// in several visited cells turns up more than once): summed by beam index,
// so the sum is the same bits whatever the cells' order.
class BeamSum {
public:
    void clear() { terms_.clear(); }
    void add(uint32_t beam, const TwoRadii& value) { terms_.push_back({beam, value}); }
    TwoRadii total();

private:
    std::vector<std::pair<uint32_t, TwoRadii>> terms_;
};

// The short-beam estimators' common part: the beams of each iteration and
// the camera walks; a subclass gathers.
class PhotonBeamEstimator : public Integrator {
public:
    PhotonBeamEstimator(const Scene& scene, const Sensor& sensor, BeamOptions options, int kernelDimensions,
                        Majorants majorants, uint64_t seed);

    static std::vector<ParameterInfo> parameters() { return describe(beamParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);

    // Sample by sample, the iteration's beams, then every pixel's walk.
    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;

    // The kernel radius of iteration i (from 1).
    float radiusAt_mm(uint32_t iteration) const;
    // The beams of sample `sample` in a channel.
    PhotonBeamMap traceBeams(int channel, uint32_t sample, PathStats& stats) const;
    // The radiance arriving along -ray.d at ray.o (a ray from outside),
    // with the kernel's bias; `entry`: where the ray meets the object, or none.
    virtual ChannelSample Li(const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                             int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const = 0;

protected:
    const Scene& scene_;

private:
    PhotonSource photons_;      // a beam for every flight
    ProgressiveRadius radius_;  // over the kernel's dimensions
};

}  // namespace pl
