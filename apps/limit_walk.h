// The cost floor of every estimator here: a random walk in an infinite
// homogeneous medium with no lookups (exponential flights, Henyey-Greenstein
// sampling, the renderer's PCG32 streams), on every thread the process may
// use. bench reports each configuration's scattering events per second per
// core against it, measured in the same run (docs/performance.md, "The
// limit walk").
#pragma once

#include <cstdint>

namespace pl {

struct LimitWalkRate {
    double eventsPerSecondPerCore = 0;
    uint64_t events = 0;
    double seconds = 0;
    int threads = 0;
};

// Walks eventsPerThread events per thread (threads: the TBB limit in force).
LimitWalkRate measureLimitWalk(int threads, uint64_t eventsPerThread = 20'000'000);

}  // namespace pl
