// Targets the print can show at every point (api/printers_reach.h), on a
// synthetic plate: where requests stayed beyond the gamut and the
// prediction fell short along the way they were pushed, the shortfall
// leaves the target, with no seam over the eye's footprint; noise alone, a
// shortfall across that way, a broken run or an overshoot do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "api/printers_reach.h"
#include "compare/surface_gaussian.h"
#include "core/rng.h"

namespace pl {
namespace {

constexpr float kSpacing_mm = 0.05f;
constexpr int kSide = 60;  // 3 x 3 mm

std::vector<Point3f> plate() {
    std::vector<Point3f> points;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) points.push_back({x * kSpacing_mm, y * kSpacing_mm, 0});
    return points;
}

TEST(PrintersReach, TakesAMeasuredShortfallOffTheTargetWithoutASeam) {
    const std::vector<Point3f> points = plate();
    const size_t n = points.size();
    const SurfaceGaussian eye(points, 0.2f);
    const Lab target{60, 40, 30};
    const std::vector<Lab> goal(n, target);
    // Left third: the print falls 6 short along +a (where the requests are
    // pushed out), after a first iteration 12 short (the loop closing in);
    // middle third: requests out by noise only (no shortfall on average);
    // right third: inside the gamut.
    const double noiseSigma = 1.5;  // per CIELAB component of one prediction
    PrintersReach reach(n);
    Rng rng(11, 0);
    for (int iteration = 0; iteration < 8; ++iteration) {
        std::vector<Lab> predicted(n), predictedWide(n);
        std::vector<uint8_t> beyond(n, 0);
        std::vector<std::array<float, 3>> outward(n, {0, 0, 0});
        for (size_t i = 0; i < n; ++i) {
            const int x = int(i % kSide);
            const float shortfall = x < kSide / 3 ? (iteration == 0 ? 12.0f : 6.0f) : 0.0f;
            auto noise = [&] {  // Box-Muller
                const double u = std::max(double(rng.uniform()), 1e-9), v = rng.uniform();
                return float(noiseSigma * std::sqrt(-2 * std::log(u)) * std::cos(2 * 3.141592653589793 * v));
            };
            predicted[i] = {target.L + noise(), target.a - shortfall + noise(), target.b + noise()};
            // Over three footprints: a tenth of the variance.
            predictedWide[i] = {target.L + noise() / 3.16f, target.a - shortfall + noise() / 3.16f,
                                target.b + noise() / 3.16f};
            beyond[i] = x < 2 * kSide / 3;
            outward[i] = {0, 3, 0};
        }
        reach.update({goal, predicted, goal, predictedWide, noiseSigma * noiseSigma, noiseSigma * noiseSigma / 10,
                      beyond, outward});
    }
    const std::vector<RGB> mapped(n, linearSrgbFromLab(target));
    const std::vector<RGB> reachable = reach.remap(mapped), seen = eye.apply(reachable);
    size_t left = 0, middle = 0, right = 0;
    for (size_t i = 0; i < n; ++i) {
        const int x = int(i % kSide);
        (x < kSide / 3 ? left : x < 2 * kSide / 3 ? middle : right) += reach.atLimit()[i];
    }
    EXPECT_EQ(left, n / 3);  // every voxel of the shortfall
    // Noise alone: a shortfall of three standard errors by chance.
    EXPECT_LT(double(middle), 0.02 * double(n / 3));
    EXPECT_EQ(right, 0u);
    double worstJump = 0;
    for (size_t i = 0; i < n; ++i) {
        const int x = int(i % kSide), y = int(i / kSide);
        const Lab t = labFromLinearSrgb(reachable[i]);
        // In the left third: the target is what the print shows there (the
        // shortfall of the last iterations, the first one's weighing 1/128,
        // within the noise; over the footprint, deep inside, within a
        // tenth of it); on the right: unchanged.
        if (x < kSide / 3) {
            EXPECT_NEAR(t.a, target.a - 6.0f, 4.0f) << x << " " << y;
            EXPECT_NEAR(t.L, target.L, 0.05f);
            EXPECT_NEAR(t.b, target.b, 0.05f);
        }
        if (x < kSide / 3 - 12 && y >= 12 && y < kSide - 12) {
            EXPECT_NEAR(labFromLinearSrgb(seen[i]).a, target.a - 6.0f, 0.3f) << x << " " << y;
        }
        if (x >= 2 * kSide / 3) {
            EXPECT_LT(ciede2000(t, target), 0.01) << x << " " << y;
        }
        // No seam where the eye looks: over the footprint, neighbours
        // differ by a fraction of the shortfall (a step would be ~4
        // CIEDE2000).
        if (x + 1 < kSide)
            worstJump = std::max(worstJump, ciede2000(labFromLinearSrgb(seen[i]), labFromLinearSrgb(seen[i + 1])));
    }
    EXPECT_LT(worstJump, 0.6);
}

// One voxel's evidence, the same every iteration.
struct OneVoxel {
    Lab goal{60, 40, 30}, predicted{60, 40, 30}, goalWide{60, 40, 30}, predictedWide{60, 40, 30};
    double noiseVariance = 0, noiseVarianceWide = 0;
    uint8_t beyond = 1;
    std::array<float, 3> outward{0, 1, 0};
    void update(PrintersReach& reach) const {
        const std::vector<Lab> g{goal}, p{predicted}, gw{goalWide}, pw{predictedWide};
        const std::vector<uint8_t> b{beyond};
        const std::vector<std::array<float, 3>> o{outward};
        reach.update({g, p, gw, pw, noiseVariance, noiseVarianceWide, b, o});
    }
    // The target after remap, CIELAB.
    Lab remapped(PrintersReach& reach) const { return labFromLinearSrgb(reach.remap({linearSrgbFromLab(goal)})[0]); }
};

TEST(PrintersReach, NeedsARunBeyondTheGamutToTheEndAndARealShortfall) {
    OneVoxel v;
    v.predicted.a = v.predictedWide.a = 34;  // 6 short along the way out
    // Five iterations beyond, one inside, five beyond: no run long enough.
    PrintersReach broken(1);
    for (uint8_t beyond : {1, 1, 1, 1, 1, 0, 1, 1, 1, 1, 1}) {
        v.beyond = beyond;
        v.update(broken);
    }
    v.remapped(broken);
    EXPECT_EQ(broken.atLimit()[0], 0);
    v.beyond = 1;
    v.update(broken);  // the sixth in a row
    EXPECT_NEAR(v.remapped(broken).a, 34, 1e-3);
    EXPECT_EQ(broken.atLimit()[0], 1);
    // A run that ended before the loop did says nothing of the end.
    v.beyond = 0;
    v.update(broken);
    EXPECT_NEAR(v.remapped(broken).a, 40, 1e-3);
    EXPECT_EQ(broken.atLimit()[0], 0);
    // An overshoot (the print beyond the target along the way out) is not
    // a limit; nor is a shortfall under the least kept, even without noise.
    v.beyond = 1;
    for (float a : {46.0f, 40.5f}) {
        PrintersReach reach(1);
        v.predicted.a = v.predictedWide.a = a;
        for (int k = 0; k < 8; ++k) v.update(reach);
        v.remapped(reach);
        EXPECT_EQ(reach.atLimit()[0], 0) << a;
    }
}

TEST(PrintersReach, KeepsSignificantDetailAndShrinksNoisyDetail) {
    // The wide scale sees no shortfall; over the footprint the print is
    // short along the way out. Well above the detail's noise it is kept
    // (an edge the wide scale blurs away); at the noise's size James-Stein
    // shrinks it below what is kept.
    OneVoxel v;
    v.noiseVariance = 1.5 * 1.5;
    v.noiseVarianceWide = v.noiseVariance / 10;
    v.predicted.a = 34;
    PrintersReach sharp(1);
    for (int k = 0; k < 40; ++k) v.update(sharp);
    // The average's variance: a third of one iteration's (weights halving
    // into the past), 0.75; 6 x (1 - 0.75 / 36): the shrink takes 2 %.
    EXPECT_NEAR(v.remapped(sharp).a, 40 - 6 * (1 - 0.75 / 36), 0.01);
    EXPECT_EQ(sharp.atLimit()[0], 1);
    v.predicted.a = 38.5f;  // 1.5 short: the shrink leaves 1.5 x (1 - 0.75 / 2.25) = 1.0, not over 1
    PrintersReach noisy(1);
    for (int k = 0; k < 40; ++k) v.update(noisy);
    v.remapped(noisy);
    EXPECT_EQ(noisy.atLimit()[0], 0);
}

TEST(PrintersReach, LeavesTheErrorAcrossTheWayOutToTheLoop) {
    // The requests are pushed out along +L, the print misses along b: no
    // shortfall along the way out, nothing taken off.
    OneVoxel v;
    v.predicted.b = v.predictedWide.b = 22;
    v.outward = {2, 0, 0};
    PrintersReach reach(1);
    for (int k = 0; k < 8; ++k) v.update(reach);
    EXPECT_NEAR(v.remapped(reach).b, 30, 1e-3);
    EXPECT_EQ(reach.atLimit()[0], 0);
}

}  // namespace
}  // namespace pl
