// printpt: the path tracer specialised for surface-radiance prediction
// (Brecka 2021, 3.6 and 4.3). Each feature is a switch so that it can be
// measured against volpath:
//  - no re-entry: light that leaves the object is done (always on);
//  - medium first: delta tracking runs before the boundary is looked for,
//    and the boundary query only reaches as far as the sampled collision;
//    with `clearance` it is skipped altogether when the collision is closer
//    than the boundary can be (core/surface_clearance.h);
//  - Fresnel weighting: at the entry and at inner boundary hits both the
//    reflected and the transmitted part are kept as weights instead of
//    choosing one at random;
//  - Russian roulette on the throughput with survival probability
//    min(rrCap, throughput / rrThreshold) (no roulette while that is >= 1):
//    a threshold of 1 is analog absorption; a lower one carries the
//    albedo as a weight until the throughput falls below it; collisions in
//    absorbing resin use rrThresholdAbsorbing instead;
//  - ball walks: deep inside one material (a ball around the walk's
//    position that the surface clearance and the one-label cells
//    (media/uniform_regions.h) show to hold one label only) collisions are
//    sampled in a plain homogeneous loop, without grid lookups or boundary
//    queries, until a free flight would leave the ball; tracking restarts
//    where it crosses the sphere (exact: free flights are memoryless);
//  - branching: k independent walks from the entry point, weight 1/k each;
//  - control variate (single channel, no NEE): each branch's walk shares
//    its random numbers with a walk in the half-space of the entry voxel's
//    material below the plane across the refracted ray (same optical
//    depths, phase and roulette numbers; its flights are sampled by
//    inverting the optical depth, so the two collide at the same places
//    wherever the media agree). Until their events part (one collides where
//    the other leaves, or the surface walk collides in another material),
//    they add the same light; after that the half-space walk finishes on
//    its own (as the mean of `controlContinuations` independent walks).
//    The estimate is f - g + E[g]. For the half-space E[g] is exact: a
//    deterministic radiative-transfer solve (media/slab_transport.h); for
//    wedges and curved regions it is estimated with Monte Carlo walks
//    seeded by the render's seed, and its standard error goes into every
//    sample that uses it (ChannelSample::sharedError). Only for entry materials that scatter
//    (albedo in [kAbsorbingAlbedo, 0.999]) and where probes find the resin
//    one material and the surface flat over the walk's reach (controlFor);
//    within `controlEdgeReach` of a right-angled edge the control is the
//    wedge under both faces, with the mean tabulated over the distance to
//    the edge; under convex curved surfaces (`controlCurved`) it is the
//    region under a paraboloid fitted to the surface, with the mean
//    tabulated over its two principal curvatures; before a render the
//    sensor's view is surveyed (a fixed set of rays, whatever its
//    resolution) and wedges and curved regions that too little of it
//    shares for the cost of their means are left out;
//  - next-event estimation towards the nearest surface (needs the `normal`
//    and `sdf` grids of a prepared .vdb): at each collision a direction is
//    drawn from a von Mises-Fisher lobe around the surface normal there, the
//    transmittance to the boundary comes from regular tracking, and light
//    leaving through it (times 1 - F) is combined with the phase-sampled
//    path's first boundary hit by the balance heuristic. The lobe's
//    concentration is the optical depth to the surface, clamped to
//    [1, neeMaxKappa]. Deep vertices, whose light is unlikely to get out,
//    are pruned by Russian roulette: NEE runs with probability
//    min(1, neePruneScale exp(-optical depth)) (at least neeMinProbability)
//    and the MIS weights count that probability, so nothing is biased.
#pragma once

#include <atomic>
#include <memory>
#include <optional>

#include "integrators/half_space_walk.h"
#include "integrators/integrator.h"

namespace pl {

struct PrintPtOptions {
    static constexpr float kAbsorbingAlbedo = 0.5f;
    bool mediumFirst = true;
    bool fresnelWeighting = true;
    float rrCap = 1.0f;  // Brecka: 0.99, which lets weights grow as (albedo / 0.99)^n
    int branches = 4;
    bool nee = false;
    float neeMaxKappa = 50.0f;
    float neePruneScale = 4.0f;
    float neeMinProbability = 0.05f;
    // Russian roulette on the NEE transmittance past this optical depth
    // (unbiased; trackers.h TransmittanceRoulette); 100: exact.
    float neeRouletteDepth = 2.0f;  // measured: docs/performance.md
    float rrThreshold = 0.25f;  // measured best on the test set (docs/performance.md)
    bool clearance = true;
    bool ballWalks = true;
    float ballMinMfp = 1.0f;  // smallest ball worth it, in mean free paths (docs/performance.md)
    // The threshold at collisions in absorbing resin (albedo below
    // kAbsorbingAlbedo in the path's channel: the inks and black).
    float rrThresholdAbsorbing = 1.0f;
    bool controlVariate = true;  // measured: docs/performance.md
    // Monte Carlo walks behind the mean of a wedge (a quarter of this) or
    // of a curved region (a 32nd); the half-space's mean is exact.
    int64_t controlWalks = int64_t(1) << 17;
    float controlProbe = 0.5f;  // diffusion lengths (see controlFor; measured in docs/performance.md)
    // Where that fails: a second try over this reach, if the body is a
    // diffusion length thick below the entry (curved surfaces); 0: none.
    float controlProbeShort = 0.0f;
    // How far (diffusion lengths) an edge is looked for; 0: half-space controls only.
    float controlEdgeReach = 6.0f;
    // Under convex curved surfaces that fail the flat probes: the control
    // under a paraboloid with the surface's principal curvatures (tabulated).
    bool controlCurved = true;
    // ... where the object holds a ball this many diffusion lengths deep
    // (and wide) below the entry (measured: docs/performance.md).
    float controlCurvedThickness = 2.0f;
    // ... and where the tabulated paraboloid follows the surface within this
    // many mean free paths at all 16 probes (measured: docs/performance.md).
    float controlCurvedTolerance = 1.0f;
    // Where the two walks part, the control's remainder is the mean of this
    // many independent continuations from its state (an unbiased estimate
    // of the remainder's expectation: less of its variance, more walks;
    // measured in docs/performance.md).
    int controlContinuations = 4;
    // Before a render, the sensor's survey rays (Sensor::surveyRay) are
    // counted by the control they would use; a wedge or curved control
    // (material, channel, shape) whose mean is a Monte Carlo estimate is
    // used only where its mean's walks come to at most this many per
    // surveyed entry that shares it (wedges: 512 entries, curved: 64):
    // otherwise they cost more than it saves (measured:
    // docs/performance.md). 0: every control is used. Half-space controls
    // have exact means and always run.
    int64_t controlMeanWalksPerEntry = 64;
};

class PrintPt : public Integrator {
public:
    // seed: the render's, which seeds the Monte Carlo control means.
    PrintPt(const Scene& scene, PrintPtOptions options, uint64_t seed);

    ChannelSample Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                     PathStats& stats) const override;
    // One path for three channels: as Li, without next-event estimation
    // (single-channel only), and with ball walks for hero sampling only.
    RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Sampler& medium, Rng& rng,
              PathStats& stats) const override;
    // Counts the sensor's survey entries per control (controlMeanWalksPerEntry).
    void prepare(const Sensor& sensor, const std::vector<int>& channels) override;

private:
    // A sample's radiance and, with a control, the standard error it shares
    // through the control's mean, the control's key (controlIndex) and the
    // sample's residual (its walks' f - g, weighted as in L).
    template <class Value>
    struct Traced {
        Value L{};
        float sharedError = 0.0f;
        int32_t controlKey = -1;
        float residual = 0.0f;
    };
    // Camera ray to entry, Fresnel there, and the branches' walks.
    template <class Path>
    Traced<typename Path::Value> trace(Ray ray, const Path& path, LabelMedium::Sampler& medium, Rng& rng,
                                       PathStats& stats) const;
    // Radiance leaving the object back along -ray.d, for a ray that starts
    // inside, with the path's throughput.
    template <class Path, bool kNee, bool kMediumFirst, bool kFresnelWeighting>
    typename Path::Value walk(Ray ray, Path path, LabelMedium::Sampler& medium, Rng& rng, PathStats& stats) const;
    template <class Path>
    using WalkFunction = typename Path::Value (PrintPt::*)(Ray, Path, LabelMedium::Sampler&, Rng&, PathStats&) const;
    // The walk compiled for the scene's switches.
    template <class Path>
    WalkFunction<Path> selectWalk() const;
    // Russian roulette on the throughput; false: the walk ends.
    template <class Path>
    bool survivesRoulette(Path& path, Label label, Rng& rng) const;
    template <class Path>
    float rouletteThreshold(const Path& path, Label label) const;
    // The walk of a single-channel branch with its half-space control:
    // returns f - g (the caller adds the control's mean).
    float walkWithControl(Ray ray, SingleChannelPath path, const HalfSpace& control, LabelMedium::Sampler& medium,
                          Rng& rng, PathStats& stats) const;
    // The refracted ray that enters the object at `entry` (a hit of the
    // camera ray from outside).
    Ray enteringRay(const Ray& camera, const SurfaceHit& entry) const;
    // The control of the branches entering along `inside`: its region, its
    // mean and the mean's standard error (per unit environment radiance
    // times the path's), and which kind it is.
    struct EntryControl {
        HalfSpace region;
        float mean = 0.0f, meanError = 0.0f;
        ControlKind kind = ControlKind::HalfSpace;
        int32_t key = 0;  // controlIndex
    };
    // None where the entry material has none, or where too few entries
    // share it (controlMeanWalksPerEntry). Remembered per thread for the
    // last entry and channel (the samples of a pixel repeat them).
    std::optional<EntryControl> controlForEntry(const Ray& inside, const SingleChannelPath& path,
                                                LabelMedium::Sampler& medium) const;
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
    struct ControlShape {
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
    // entry material and the tabulated shape; false where none fits.
    bool controlFor(const Ray& inside, const SingleChannelPath& path, LabelMedium::Sampler& medium,
                    HalfSpace& control, Label& label, ControlShape& shape) const;
    // Whether the bricks sampled below the entry, over reach_mm, hold only
    // material l (or void).
    bool materialBelow(const Ray& inside, Label l, float reach_mm, const HalfSpace& control) const;
    // Whether the control of material l under the entry plane may run:
    // the flatness probes over reach_mm (controlFor). Sets the control's
    // side plane and the shape where it is a wedge.
    bool controlFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control,
                     ControlShape& shape) const;
    // Whether the surface over reach_mm is, within a quarter of a mean free
    // path, a convex paraboloid with tabulated curvatures; sets the control
    // to the region under it and the shape.
    bool curvedControlFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control,
                           ControlShape& shape) const;
    // Whether the object holds the ball of radius_mm around centre (no
    // surface within 0.9 radius_mm).
    bool holdsBall(const Point3f& centre, float radius_mm) const;
    // The one label of p's majorant brick, or MajorantGrid::kSeveralLabels / kOnlyVoid.
    int solidLabelAt(const Point3f& p) const;
    // Radius (mm) of a ball around p, inside the object, holding only one
    // label (set in label); 0 where there is none.
    float homogeneousBall(const Point3f& p, Label& label) const;
    // Random walk from ray.o in the ball of radius_mm around it, which
    // holds only label: collisions without lookups or boundary queries,
    // until a free flight would leave the ball; ray becomes the point where
    // it crosses the sphere, with its direction. False if the walk ended.
    template <class Path>
    bool walkInBall(Ray& ray, float radius_mm, Label label, Path& path, Rng& rng, PathStats& stats) const;
    WalkFunction<SingleChannelPath> walkSingle_;
    WalkFunction<HeroPath> walkHero_;
    WalkFunction<SpectralPath> walkSpectral_;
    // Light leaving the object straight from x towards the nearest surface,
    // MIS-weighted against phase sampling, per unit environment radiance.
    // Sets the lobe for later weights.
    struct Lobe {
        Vec3f axis;
        float kappa = 0;        // 0: no lobe (no NEE at this vertex)
        float probability = 1;  // chance that NEE ran here (pruning)
    };
    float nextEvent(const Point3f& x, const Vec3f& dIn, Label label, int channel, LabelMedium::Sampler& medium,
                    Rng& rng, Lobe& lobe) const;

    const Scene& scene_;
    PrintPtOptions options_;
    uint64_t seed_;
    uint64_t id_ = 0;  // this integrator among all made in the process (controlForEntry)
    // Per channel, label and shape (ControlShape::index): the control's
    // mean, computed at first use, and its standard error (for the
    // half-space, the solver's error and float round-off).
    static constexpr float kControlUnknown = -1.0f;
    static constexpr int kControlShapes = 1 + kEdgeSteps + kCurvaturePairs;
    static size_t controlIndex(int channel, Label label, int shape) {
        return (size_t(channel) * 256 + label) * kControlShapes + size_t(shape);
    }
    struct ControlMean {
        float mean, standardError;
    };
    ControlMean controlMean(int channel, Label label, const ControlShape& shape) const;
    // The walks that estimate the mean of a control of this shape.
    int64_t controlMeanWalks(const ControlShape& shape) const;
    std::unique_ptr<std::atomic<float>[]> controlMean_, controlStdErr_;
    // Entries of the sensor's survey per control, counted by prepare();
    // until then every control is used.
    std::unique_ptr<std::atomic<uint32_t>[]> controlEntries_;
    bool entriesCounted_ = false;
};

}  // namespace pl
