// A random walk in a homogeneous medium, from the centre of a ball to the
// point where its path first crosses the sphere. Inside a ball that holds a
// single material and no boundary, this is exactly the walk delta tracking
// would take, without grid lookups or boundary queries (printpt's ball
// walks). The walk stops when a sampled free flight would end beyond the
// sphere: nothing collides before the sphere, and since free flights are
// memoryless the caller restarts tracking from the crossing point.
#pragma once

#include <cmath>

#include "core/rng.h"
#include "core/sampling.h"

namespace pl {

struct BallWalk {
    Vec3f exit;               // crossing point relative to the centre (mm)
    Vec3f direction;          // direction of travel there
    float lastFlight_mm = 0;  // from the last collision (or the centre) to the exit
    int64_t collisions = 0;   // scattering events inside the ball
    bool alive = true;        // false: Russian roulette ended the walk
};

// collide(flight_mm) is called at each collision with the free flight that
// reached it; it weights the path (albedo, Russian roulette) and returns
// false if the walk ends there.
template <class Collide>
BallWalk walkInBall(const Vec3f& w0, float radius_mm, float sigmaT_perMm, float g, Collide&& collide, Rng& rng) {
    const float invSigmaT = 1.0f / sigmaT_perMm, r2 = radius_mm * radius_mm;
    BallWalk out;
    Vec3f p(0, 0, 0), w = w0;
    for (;;) {
        float t = sampleOpticalDepth(rng.uniform()) * invSigmaT;
        Vec3f q = p + w * t;
        if (dot(q, q) >= r2) break;
        p = q;
        out.collisions += 1;
        if (!collide(t)) {
            out.alive = false;
            return out;
        }
        float u0 = rng.uniform(), u1 = rng.uniform();
        w = sampleHG(w, g, u0, u1).dOut;
    }
    // Exit distance along w from p (inside) to the sphere.
    float b = dot(p, w), c = dot(p, p) - r2;
    float s = -b + std::sqrt(std::max(0.0f, b * b - c));
    out.exit = p + w * s;
    out.lastFlight_mm = s;
    out.direction = w;
    return out;
}

}  // namespace pl
