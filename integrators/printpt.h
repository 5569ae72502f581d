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
//    albedo as a weight until the throughput falls below it;
//  - branching: k independent walks from the entry point, weight 1/k each;
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

#include "integrators/integrator.h"

namespace pl {

struct PrintPtOptions {
    bool mediumFirst = true;
    bool fresnelWeighting = true;
    float rrCap = 1.0f;  // Brecka: 0.99, which lets weights grow as (albedo / 0.99)^n
    int branches = 4;
    bool nee = false;
    float neeMaxKappa = 50.0f;
    float neePruneScale = 4.0f;
    float neeMinProbability = 0.05f;
    float rrThreshold = 0.25f;  // measured best on the test set (docs/performance.md)
    bool clearance = true;
};

class PrintPt : public Integrator {
public:
    PrintPt(const Scene& scene, PrintPtOptions options);

    float Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
             PathStats& stats) const override;

private:
    // Radiance leaving the object back along -ray.d, for a ray that starts
    // inside, with throughput 1.
    template <bool kNee, bool kMediumFirst, bool kFresnelWeighting>
    float walk(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng, PathStats& stats) const;
    using WalkFunction = float (PrintPt::*)(Ray, int, LabelMedium::Sampler&, Rng&, PathStats&) const;
    WalkFunction walk_;
    // Light leaving the object straight from x towards the nearest surface,
    // MIS-weighted against phase sampling. Sets the lobe for later weights.
    struct Lobe {
        Vec3f axis;
        float kappa = 0;        // 0: no lobe (no NEE at this vertex)
        float probability = 1;  // chance that NEE ran here (pruning)
    };
    float nextEvent(const Point3f& x, const Vec3f& dIn, Label label, int channel, LabelMedium::Sampler& medium,
                    Rng& rng, Lobe& lobe) const;

    const Scene& scene_;
    PrintPtOptions options_;
};

}  // namespace pl
