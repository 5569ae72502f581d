// volpath: the plain reference volumetric path tracer. Delta tracking for
// distances, HG phase sampling, Fresnel choosing reflection or refraction at
// random, throughput Russian roulette, no depth cap unless asked. It is the
// oracle every specialised estimator is checked against: keep it simple.
#pragma once

#include <cstdint>

#include "core/rng.h"
#include "integrators/scene.h"

namespace pl {

struct PathStats {
    uint64_t paths = 0;
    uint64_t scatterEvents = 0;  // real collisions that scattered
    uint64_t leaks = 0;          // rays inside that found no boundary (mesh not closed)
    uint64_t trapped = 0;        // paths ended after kMaxBoundaryBounces without scattering
    void operator+=(const PathStats& o) {
        paths += o.paths;
        scatterEvents += o.scatterEvents;
        leaks += o.leaks;
        trapped += o.trapped;
    }
};

// Boundary events in a row, without scattering, after which a path counts
// as trapped (lossless total internal reflection) and ends.
constexpr int64_t kMaxBoundaryBounces = 10000000;

struct VolPathOptions {
    bool reentry = false;  // trace light that leaves the object back against it
    int64_t maxDepth = -1; // scattering events per path; < 0: unlimited (unbiased)
};

class VolPath {
public:
    VolPath(const Scene& scene, VolPathOptions options) : scene_(scene), options_(options) {}

    // Radiance arriving along -ray.d at ray.o (a point outside the object),
    // in one colour channel.
    float Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
             PathStats& stats) const;

private:
    const Scene& scene_;
    VolPathOptions options_;
};

}  // namespace pl
