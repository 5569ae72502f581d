// A single-channel path with its control walk coupled to it: the path
// printpt's walk drives when a branch has a control (control_variate.h).
// The walk treats it like any path; underneath, every flight it tracks
// draws one optical depth for both walks (the surface walk's by inverting
// it through the grid, the control's in its region), every collision both
// share plays one roulette on the larger weight and samples both
// directions from the same numbers, and each walk adds its own light at
// its own boundary. Where their events part (partsAfterFlight) the
// control's walk finishes alone; the walk completes that step and goes on
// with the plain path (plain()) from there. The walk's value is f - g
// (value); the caller adds the control's mean.
#pragma once

#include <algorithm>

#include "integrators/channel_paths.h"
#include "integrators/printpt/half_space_walk.h"
#include "integrators/printpt/printpt_options.h"

namespace pl {

struct ControlledPath : SingleChannelPath {
    static constexpr bool kSupportsNee = false;

    // The branch's path, its control's region and the direction both start along.
    ControlledPath(const SingleChannelPath& path, const HalfSpace& region, const Vec3f& d,
                   const PrintPtOptions& options)
        : SingleChannelPath(path),
          control(&region),
          walker{region.origin, d, 1.0f},
          roulette{options.rrThreshold, options.rrCap},
          ballMinMfp(std::max(1.0f, options.ballMinMfp)),
          continuations(options.controlContinuations) {}

    const HalfSpace* control;
    HalfSpaceWalker walker;   // the control's walk
    RouletteRule roulette;    // the control's own roulette, once it walks alone
    float ballMinMfp;         // and its ball walks
    int continuations;        // independent finishes of the control's walk where they part
    bool coupled = true;           // false from the step where they part
    bool controlCollided = false;  // the control's last flight ended in a collision
    float controlLight = 0.0f;     // g per unit environment radiance
    float partedValue = 0.0f;      // f - g up to where they parted

    FreeFlight track(LabelMedium::Tracker& medium, const Ray& ray, float tMax_mm, Rng& rng) {
        const float opticalDepth = sampleOpticalDepth(rng.uniform());
        controlCollided = halfSpaceFlight(*control, walker, opticalDepth, controlLight);
        return medium.freeFlightAtDepth(ray, tMax_mm, channel, opticalDepth);
    }
    Vec3f samplePhase(Label l, const Vec3f& dIn, Rng& rng) {
        if (!coupled) return SingleChannelPath::samplePhase(l, dIn, rng);
        float u0 = rng.uniform(), u1 = rng.uniform();
        walker.d = sampleHG(walker.d, control->g, u0, u1).dOut;
        return sampleHG(dIn, lut->g[l], u0, u1).dOut;
    }
    // One roulette for both, on the larger weight: neither weight can grow
    // past the threshold (in ink the surface walk's weight drops fast while
    // the control's may not). A survivor's weights both take 1 / survival.
    float rouletteValue() const { return coupled ? std::max(beta, walker.weight) : beta; }
    void survive(float survival) {
        scale(1.0f / survival);
        if (coupled) walker.weight /= survival;
    }

    // After a flight the walks part where one collides and the other
    // reaches its boundary, or the surface walk collides in another
    // material (whose roulette the control should not share). Then the
    // control finishes alone, L (the light so far) moves into the parted
    // value, and the step goes on from L = 0 (coupled is false).
    void partsAfterFlight(bool collides, Label label, float& L, Rng& rng) {
        if (collides == controlCollided && (!collides || sameMaterial(label))) return;
        partedValue = finish(L, rng);
        coupled = false;
        L = 0.0f;
    }
    // The path without its control, once they have parted.
    SingleChannelPath plain() const { return *this; }
    // f - g for the walk that ended with light L (after they parted: L of
    // the parting step); absorbed: by a roulette (which, coupled, ended
    // the control's walk too).
    float value(float L, bool absorbed, Rng& rng) const {
        if (!coupled) return partedValue + L;
        return absorbed ? L - controlLight * Le : finish(L, rng);
    }

    // Ball walks only in the control's material and below its boundary:
    // one walk for both, rotated onto the control's direction.
    bool canWalkBall(Label l) const { return sameMaterial(l); }
    float ballLimit_mm(const Vec3f& d) const { return dot(d, walker.d) > -0.99f ? control->depth(walker.x) : 0.0f; }
    void ballCollision(Label) { walker.weight *= control->albedo; }
    // The ball walk that started along d0 left the ball at exit (relative
    // to its centre) along direction.
    void followBall(const Vec3f& d0, const Vec3f& exit, const Vec3f& direction) {
        walker.x = walker.x + rotateAtoB(d0, walker.d, exit);
        walker.d = normalize(rotateAtoB(d0, walker.d, direction));
    }

private:
    bool sameMaterial(Label l) const {
        return lut->sigmaT_perMm[l] == control->sigmaT_perMm && lut->albedo[l] == control->albedo &&
               lut->g[l] == control->g;
    }
    // f - g with the control's walk finished alone from its state (the mean
    // of `continuations` independent finishes).
    float finish(float L, Rng& rng) const {
        float remainder = 0.0f;
        int64_t collisions = 0;
        for (int i = 0; i < continuations; ++i)
            remainder += finishHalfSpaceWalk(*control, walker, controlCollided, roulette, ballMinMfp, rng, collisions);
        return L - (controlLight + remainder / float(continuations)) * Le;
    }
};

}  // namespace pl
