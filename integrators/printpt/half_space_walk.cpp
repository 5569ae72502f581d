#include "integrators/printpt/half_space_walk.h"

#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "core/fresnel.h"
#include "core/sampling.h"
#include "media/ball_walk.h"

namespace pl {

std::optional<HalfSpace::Exit> HalfSpace::exit(const Point3f& x, const Vec3f& d) const {
    // F(t) = z + (kappaS u^2 + kappaT v^2) / 2 along the ray, negative
    // inside: a t^2 + b t + c with a >= 0 and c <= 0 has one root t >= 0.
    const Vec3f r = x - origin;
    const float u = dot(r, axisS), v = dot(r, axisT), du = dot(d, axisS), dv = dot(d, axisT);
    const float a = 0.5f * (kappaS_perMm * du * du + kappaT_perMm * dv * dv);
    const float b = dot(d, normal) + kappaS_perMm * u * du + kappaT_perMm * v * dv;
    const float c = std::min(0.0f, dot(r, normal) + 0.5f * (kappaS_perMm * u * u + kappaT_perMm * v * v));
    float t_mm;
    if (a <= 1e-12f * std::abs(b)) {
        if (b <= 0.0f) return std::nullopt;
        t_mm = -c / b;
    } else {
        const float root = std::sqrt(b * b - 4.0f * a * c);
        t_mm = b >= 0.0f ? -2.0f * c / (b + root) : (root - b) / (2.0f * a);
    }
    const float ue = u + du * t_mm, ve = v + dv * t_mm;
    return Exit{t_mm, normalize(normal + axisS * (kappaS_perMm * ue) + axisT * (kappaT_perMm * ve))};
}

bool halfSpaceFlight(const HalfSpace& hs, HalfSpaceWalker& w, float opticalDepth, float& light) {
    float t = opticalDepth / hs.sigmaT_perMm;
    // The boundary the flight reaches first, if it reaches one.
    bool crossed = false;
    Vec3f crossedNormal;
    float cosCrossed = 0.0f;
    auto reach = [&](const Point3f& origin, const Vec3f& normal) {
        float towards = dot(w.d, normal);
        if (towards <= 0.0f) return;
        float tPlane = std::max(0.0f, dot(origin - w.x, normal)) / towards;
        if (tPlane <= t) {
            t = tPlane;
            crossed = true;
            crossedNormal = normal;
            cosCrossed = towards;
        }
    };
    if (hs.curved) {
        if (auto e = hs.exit(w.x, w.d); e && e->t_mm <= t) {
            t = e->t_mm;
            crossed = true;
            crossedNormal = e->outward;
            cosCrossed = std::max(0.0f, dot(w.d, e->outward));
        }
    } else {
        reach(hs.origin, hs.normal);
        if (hs.hasSide) reach(hs.sideOrigin, hs.sideNormal);
    }
    w.x = w.x + w.d * t;
    if (!crossed) {
        w.weight *= hs.albedo;
        return true;
    }
    float F = fresnelDielectric(cosCrossed, hs.etaOut);
    light += (1.0f - F) * w.weight;
    w.weight *= F;
    // Inward after the reflection (round-off at grazing exits aside).
    w.d = reflect(w.d, crossedNormal);
    if (dot(w.d, crossedNormal) > 0.0f) w.d = reflect(w.d, crossedNormal);
    return false;
}

namespace {

// Roulette and phase sampling after a collision; false if the walk ends.
bool scatter(const HalfSpace& hs, HalfSpaceWalker& w, const RouletteRule& roulette, Rng& rng) {
    if (!playRoulette(roulette.survival(w.weight), rng, [&](float survival) { w.weight /= survival; })) return false;
    float u0 = rng.uniform(), u1 = rng.uniform();
    w.d = sampleHG(w.d, hs.g, u0, u1).dOut;
    return true;
}

}  // namespace

float finishHalfSpaceWalk(const HalfSpace& hs, HalfSpaceWalker w, bool atCollision, const RouletteRule& roulette,
                          float ballMinMfp, Rng& rng, int64_t& collisions) {
    float light = 0.0f;
    if (atCollision && !scatter(hs, w, roulette, rng)) return light;
    for (int reflections = 0; w.weight > 0.0f && reflections < 256;) {
        // Deep enough: walk to the edge of the ball that touches the plane.
        float radius_mm = hs.depth(w.x);
        if (radius_mm * hs.sigmaT_perMm >= ballMinMfp) {
            BallWalk b = walkInBall(
                w.d, radius_mm, hs.sigmaT_perMm, hs.g,
                [&](float) {
                    w.weight *= hs.albedo;
                    return playRoulette(roulette.survival(w.weight), rng, [&](float survival) { w.weight /= survival; });
                },
                rng);
            collisions += b.collisions;
            if (!b.alive) return light;
            w.x = w.x + b.exit;
            w.d = b.direction;
            continue;
        }
        float opticalDepth = sampleOpticalDepth(rng.uniform());
        if (halfSpaceFlight(hs, w, opticalDepth, light)) {
            collisions += 1;
            reflections = 0;
            if (!scatter(hs, w, roulette, rng)) return light;
        } else {
            reflections += 1;  // total internal reflection leaves the weight as it is
        }
    }
    return light;
}

HalfSpaceMean estimateHalfSpaceMean(const HalfSpace& hs, const RouletteRule& roulette, float ballMinMfp,
                                    int64_t walks, uint64_t seed) {
    // Fixed chunks with their own streams, summed in order: the same result
    // for any thread count.
    constexpr int64_t kChunk = 4096;
    const int64_t chunks = (walks + kChunk - 1) / kChunk;
    std::vector<double> sum(size_t(chunks), 0.0), sumSq(size_t(chunks), 0.0);
    // Its own context: a render cancelled around it cannot cut a mean
    // short that the process-wide cache then keeps.
    tbb::task_group_context own(tbb::task_group_context::isolated);
    tbb::parallel_for(int64_t(0), chunks, [&](int64_t c) {
        Rng rng = Rng::forPath(seed, uint64_t(c), 0, 0);
        int64_t collisions = 0;
        for (int64_t i = c * kChunk; i < std::min(walks, (c + 1) * kChunk); ++i) {
            HalfSpaceWalker w{hs.origin, -hs.normal, 1.0f};
            double f = finishHalfSpaceWalk(hs, w, false, roulette, ballMinMfp, rng, collisions);
            sum[size_t(c)] += f;
            sumSq[size_t(c)] += f * f;
        }
    }, own);
    double s = 0, s2 = 0;
    for (int64_t c = 0; c < chunks; ++c) {
        s += sum[size_t(c)];
        s2 += sumSq[size_t(c)];
    }
    double n = double(walks), mean = s / n;
    double variance = std::max(0.0, (s2 - n * mean * mean) / (n - 1));
    return {mean, std::sqrt(variance / n)};
}

HalfSpaceMeans& HalfSpaceMeans::ofProcess() {
    static HalfSpaceMeans means;
    return means;
}

HalfSpaceMean HalfSpaceMeans::get(const HalfSpace& hs, const RouletteRule& roulette, float ballMinMfp, int64_t walks,
                                  uint64_t seed) {
    const float side_mm = hs.hasSide ? dot(hs.sideOrigin - hs.origin, hs.sideNormal) : -1.0f;
    const float kappaS = hs.curved ? hs.kappaS_perMm : -1.0f, kappaT = hs.curved ? hs.kappaT_perMm : -1.0f;
    const Key key{hs.sigmaT_perMm, hs.albedo, hs.g, hs.etaOut, side_mm, kappaS, kappaT, roulette.threshold,
                  roulette.cap, ballMinMfp, walks, seed};
    std::promise<HalfSpaceMean> promise;
    std::shared_future<HalfSpaceMean> result;
    bool first = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto [it, inserted] = known_.try_emplace(key);
        if (inserted) it->second = promise.get_future().share();
        result = it->second;
        first = inserted;
    }
    // Estimated outside the lock, so that threads asking for different
    // means estimate them side by side.
    if (first) {
        try {
            promise.set_value(estimateHalfSpaceMean(hs, roulette, ballMinMfp, walks, seed));
        } catch (...) {
            {  // not kept: the next render asks again
                std::lock_guard<std::mutex> lock(mutex_);
                known_.erase(key);
            }
            promise.set_exception(std::current_exception());
        }
    }
    return result.get();
}

}  // namespace pl
