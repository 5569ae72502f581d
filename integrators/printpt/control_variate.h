// printpt's control variate (docs/printpt.md, "The control variate"): for
// the branches that enter the object along a refracted ray, the region of
// one homogeneous material (a half-space, a wedge at a right-angled edge,
// or the region under a paraboloid) whose walk shares their random
// numbers, and that walk's mean. It lives as long as the integrator: the
// means are computed at first use and kept, and the census of the
// sensor's survey decides which costly controls run.
//
// Each branch's walk shares its random numbers with a walk in the region
// below the plane across the refracted ray (same optical depths, phase and
// roulette numbers; its flights are sampled by inverting the optical
// depth, so the two collide at the same places wherever the media agree).
// Until their events part (one collides where the other leaves, or the
// surface walk collides in another material), they add the same light;
// after that the region's walk finishes on its own (as the mean of
// `controlContinuations` independent walks). The estimate is f - g + E[g].
// For the half-space E[g] is exact: a deterministic radiative-transfer
// solve (media/slab_transport.h); for wedges and curved regions it is
// estimated with Monte Carlo walks seeded by the render's seed, and its
// standard error goes into every sample that uses it
// (ChannelSample::sharedError). Only for entry materials that scatter
// (albedo in [kAbsorbingAlbedo, 0.999]) and where probes find the resin one
// material and the surface flat over the walk's reach (fit); within
// `controlEdgeReach` of a right-angled edge the region is the wedge under
// both faces, with the mean tabulated over the distance to the edge; under
// convex curved surfaces (`controlCurved`) it is the region under a
// paraboloid fitted to the surface, with the mean tabulated over its two
// principal curvatures. Before a render the sensor's view is surveyed (a
// fixed set of rays, whatever its resolution) and wedges and curved
// regions that too little of it shares for the cost of their means are
// left out.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "integrators/channel_paths.h"
#include "integrators/printpt/half_space_walk.h"
#include "integrators/integrator.h"
#include "integrators/printpt/printpt_options.h"

namespace pl {

class Sensor;

class ControlVariate {
public:
    // seed: the render's, which seeds the Monte Carlo means; those are kept
    // for the life of the process (HalfSpaceMeans::ofProcess: the
    // prediction API's iterations share them).
    ControlVariate(const Scene& scene, const PrintPtOptions& options, uint64_t seed);

    // The control of the branches entering along `inside`: its region, its
    // mean and the mean's standard error (per unit environment radiance
    // times the path's), which kind it is and its key (the channel,
    // material and shape: the same key, the same mean).
    struct EntryControl {
        HalfSpace region;
        float mean = 0.0f, meanError = 0.0f;
        ControlKind kind = ControlKind::HalfSpace;
        int32_t key = 0;
    };
    // None where the entry material has none, or where too few entries
    // share it (controlMeanWalksPerEntry). Remembered per thread for the
    // last entry and channel (the samples of a pixel repeat them).
    std::optional<EntryControl> forEntry(const Ray& inside, const SingleChannelPath& path,
                                         LabelMedium::Tracker& medium) const;
    // Counts the sensor's survey rays (Sensor::surveyRay) per control, for
    // the channels of single-channel passes; until then every control runs.
    void survey(const Sensor& sensor, const std::vector<int>& channels);

private:
    // The side face of a right-angled edge within reach_mm of the control's
    // entry, set as its second plane at the tabulated distance nearest the
    // edge's; none (and the control left a half-space) where there is no
    // such face, or another face lies within ignore_mm.
    struct Edge {
        int step;           // the tabulated distance the side plane is at
        float distance_mm;  // the real edge's distance from the entry
    };
    std::optional<Edge> findEdge(HalfSpace& control, float reach_mm, float ignore_mm) const;
    // Which tabulated control a branch has: the half-space, a wedge or a
    // curved region (steps of half_space_walk.h).
    struct Shape {
        int edgeStep = -1;             // >= 0: the wedge with its edge at this step
        int curveS = -1, curveT = -1;  // >= 0: the paraboloid with these curvature steps
        int index() const {
            return edgeStep >= 0 ? 1 + edgeStep
                   : curveS >= 0 ? 1 + kEdgeSteps + curvaturePairIndex(curveS, curveT)
                                 : 0;
        }
        ControlKind kind() const {
            return edgeStep >= 0 ? ControlKind::Wedge : curveS >= 0 ? ControlKind::Curved : ControlKind::HalfSpace;
        }
    };
    // The control that fits the entry along `inside`: its region, the
    // entry material and the tabulated shape; none where none fits.
    struct Fit {
        HalfSpace region;
        Label label = 0;
        Shape shape;
    };
    std::optional<Fit> fit(const Ray& inside, const SingleChannelPath& path, LabelMedium::Tracker& medium) const;
    // Whether the bricks sampled below the entry, over reach_mm, hold only
    // material l (or void).
    bool materialBelow(const Ray& inside, Label l, float reach_mm, const HalfSpace& control) const;
    // Whether the control of material l under the entry plane may run:
    // the flatness probes over reach_mm (fit). Sets the control's
    // side plane and the shape where it is a wedge.
    bool flatFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control, Shape& shape) const;
    // Whether the surface over reach_mm is, within a quarter of a mean free
    // path, a convex paraboloid with tabulated curvatures; sets the control
    // to the region under it and the shape.
    bool curvedFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control, Shape& shape) const;
    // Whether the object holds the ball of radius_mm around centre (no
    // surface within 0.9 radius_mm).
    bool holdsBall(const Point3f& centre, float radius_mm) const;
    // The one label of p's majorant brick, or MajorantGrid::kSeveralLabels / kOnlyVoid.
    int solidLabelAt(const Point3f& p) const;

    const Scene& scene_;
    PrintPtOptions options_;
    uint64_t seed_;
    // The decision for the last entry each thread saw (forEntry): the
    // surface-voxel sensor repeats a pixel's ray for every sample.
    struct LastEntry {
        int channel = -1;  // -1: none yet
        Ray inside;
        std::optional<EntryControl> control;
    };
    mutable tbb::enumerable_thread_specific<LastEntry> lastEntry_;
    // Per channel, label and shape (Shape::index): the control's
    // mean, computed at first use, and its standard error (for the
    // half-space, the solver's error and float round-off).
    static constexpr float kUnknown = -1.0f;
    static constexpr int kShapes = 1 + kEdgeSteps + kCurvaturePairs;
    static size_t key(int channel, Label label, int shape) {
        return (size_t(channel) * 256 + label) * kShapes + size_t(shape);
    }
    struct ControlMean {
        float mean, standardError;
    };
    ControlMean meanOf(int channel, Label label, const Shape& shape) const;
    // The walks that estimate the mean of a control of this shape.
    int64_t meanWalks(const Shape& shape) const;
    std::unique_ptr<std::atomic<float>[]> means_, meanErrors_;
    // Entries of the sensor's survey per control, counted by survey();
    // until then every control is used.
    std::unique_ptr<std::atomic<uint32_t>[]> entries_;
    bool surveyed_ = false;
};

}  // namespace pl
