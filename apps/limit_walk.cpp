#include "apps/limit_walk.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "runtime/scheduler.h"

namespace pl {

namespace {

// Each chunk walks its events from its own stream.
constexpr uint64_t kEventsPerChunk = 1'000'000;
// White resin's red extinction and the resins' anisotropy (the values only
// set the step; the cost is the same for any).
constexpr float kSigmaT_perMm = 6.0f;
constexpr float kG = 0.4f;

}  // namespace

LimitWalkRate measureLimitWalk(int threads, uint64_t eventsPerThread) {
    const uint64_t chunks = std::max<uint64_t>(1, eventsPerThread * uint64_t(threads) / kEventsPerChunk);
    // Where each chunk's walk ends, so that no step can be optimised away.
    std::vector<float> ends(chunks, 0.0f);
    const auto start = std::chrono::steady_clock::now();
    parallelForTiles(chunks, 1, [&](size_t begin, size_t end) {
        for (size_t chunk = begin; chunk < end; ++chunk) {
            Rng rng = Rng::forPath(0x6c696d6974ULL, chunk, 0, 0);
            Point3f p{0, 0, 0};
            Vec3f d{0, 0, 1};
            for (uint64_t i = 0; i < kEventsPerChunk; ++i) {
                p += d * (sampleOpticalDepth(rng.uniform()) / kSigmaT_perMm);
                const float u0 = rng.uniform(), u1 = rng.uniform();
                d = sampleHG(d, kG, u0, u1).dOut;
            }
            ends[chunk] = p.x + p.y + p.z;
        }
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    volatile float sink = 0;
    for (float e : ends) sink = sink + e;
    LimitWalkRate r;
    r.events = chunks * kEventsPerChunk;
    r.seconds = seconds;
    r.threads = threads;
    r.eventsPerSecondPerCore = double(r.events) / (seconds * threads);
    return r;
}

}  // namespace pl
