// printpt: the path tracer specialised for surface-radiance prediction
// (Brecka 2021, 3.6 and 4.3). Each feature is a switch so that it can be
// measured against volpath:
//  - no re-entry: light that leaves the object is done (always on);
//  - medium first: delta tracking runs before the boundary is looked for,
//    and the boundary query only reaches as far as the sampled collision;
//  - Fresnel weighting: at the entry and at inner boundary hits both the
//    reflected and the transmitted part are kept as weights instead of
//    choosing one at random;
//  - Russian roulette on the throughput with survival probability
//    min(rrCap, throughput);
//  - branching: k independent walks from the entry point, weight 1/k each.
// Next-event estimation towards the surface is not implemented yet.
#pragma once

#include "integrators/integrator.h"

namespace pl {

struct PrintPtOptions {
    bool mediumFirst = true;
    bool fresnelWeighting = true;
    float rrCap = 0.99f;
    int branches = 4;
};

class PrintPt : public Integrator {
public:
    PrintPt(const Scene& scene, PrintPtOptions options) : scene_(scene), options_(options) {}

    float Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
             PathStats& stats) const override;

private:
    // Radiance leaving the object back along -ray.d, for a ray that starts
    // inside, with throughput 1.
    float walk(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng, PathStats& stats) const;

    const Scene& scene_;
    PrintPtOptions options_;
};

}  // namespace pl
