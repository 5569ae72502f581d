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
//  - control variate (single channel, no NEE): each branch's walk runs
//    coupled to a walk in a region of the entry's material whose mean is
//    known (integrators/printpt/control_variate.h); the estimate is
//    f - g + E[g];
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

#include "integrators/printpt/control_variate.h"
#include "integrators/printpt/half_space_walk.h"
#include "integrators/integrator.h"
#include "integrators/printpt/printpt_options.h"

namespace pl {

class PrintPt : public PixelIntegrator {
public:
    // Next-event estimation needs the surface fields and keeps separate
    // passes (it is single-channel); clearance and ball walks the clearance.
    static std::vector<ParameterInfo> parameters() { return describe(printPtParameters()); }
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("printpt", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);
    // seed: the render's, which seeds the Monte Carlo control means.
    PrintPt(const Scene& scene, PrintPtOptions options, uint64_t seed);

    ChannelSample Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                     PathStats& stats) const override;
    // One path for three channels: as Li, without next-event estimation
    // (single-channel only), and with ball walks for hero sampling only.
    RGB LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
              PathStats& stats) const override;
    // The control variate's census of the sensor's survey (controlMeanWalksPerEntry).
    void preprocess(const Sensor& sensor, const std::vector<int>& channels) override;
    // Whether walks entering along this camera ray in this channel run
    // with a control (after prepare: the census decides some).
    bool controlsEntry(const Ray& cameraRay, int channel, LabelMedium::Tracker& medium) const;

private:
    // A sample's radiance and, with a control, the standard error it shares
    // through the control's mean, the control's key (ControlVariate::key) and the
    // sample's residual (its walks' f - g, weighted as in L). Without a
    // control, single-channel samples are pooled by entry label and
    // channel where a pixel's samples are all equal: residual is what the
    // walks brought (Film, ChannelSample::poolWhereFlat).
    template <class Value>
    struct Traced {
        Value L{};
        float sharedError = 0.0f;
        int32_t poolKey = -1;
        float residual = 0.0f;
        bool poolWhereFlat = false;
    };
    // Camera ray to entry, Fresnel there, and the branches' walks.
    template <class Path>
    Traced<typename Path::Value> trace(Ray ray, const Path& path, LabelMedium::Tracker& medium, Rng& rng,
                                       PathStats& stats) const;
    // Radiance leaving the object back along -ray.d, for a ray that starts
    // inside, with the path's throughput.
    template <class Path, bool kNee, bool kMediumFirst, bool kFresnelWeighting>
    typename Path::Value walk(Ray ray, Path path, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const;
    template <class Path>
    using WalkFunction = typename Path::Value (PrintPt::*)(Ray, Path, LabelMedium::Tracker&, Rng&, PathStats&) const;
    // The walk compiled for the scene's switches.
    template <class Path>
    WalkFunction<Path> selectWalk() const;
    // Russian roulette on the throughput at a collision in `label`; false:
    // the walk ends.
    template <class Path>
    bool survivesRoulette(Path& path, Label label, Rng& rng) const;
    // The same with survival min(rr_cap, throughput / threshold).
    template <class Path>
    bool survivesRouletteAbove(Path& path, float threshold, Rng& rng) const;
    template <class Path>
    float rouletteThreshold(const Path& path, Label label) const;
    // A ball around p, inside the object, that holds only one label;
    // radius 0 where there is none. (8 bytes, returned in a register.)
    struct Ball {
        float radius_mm = 0.0f;
        Label label = 0;
    };
    Ball homogeneousBall(const Point3f& p) const;
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
    // MIS-weighted against phase sampling, per unit environment radiance,
    // and the lobe it was sampled from (for the phase path's weight).
    struct Lobe {
        Vec3f axis;
        float kappa = 0;        // 0: no lobe (no NEE at this vertex)
        float probability = 1;  // chance that NEE ran here (pruning)
    };
    struct NextEvent {
        float light = 0.0f;
        Lobe lobe;
    };
    NextEvent nextEvent(const Point3f& x, const Vec3f& dIn, Label label, int channel, LabelMedium::Tracker& medium,
                        Rng& rng) const;

    const Scene& scene_;
    PrintPtOptions options_;
    ControlVariate control_;
};

}  // namespace pl
