// Targets the print can show at every point (api/printers_reach.h), on a
// synthetic plate: where requests stay beyond the gamut and the prediction
// falls short along the way they were pushed, the shortfall leaves the
// target, smoothly; noise alone, or a shortfall across that way, does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "api/printers_reach.h"
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
    // pushed out); middle third: requests out by noise only (no shortfall
    // on average); right third: inside the gamut.
    const double noiseSigma = 1.5;  // per CIELAB component of one prediction
    PrintersReach reach(n);
    Rng rng(11, 0);
    bool foundAny = false;
    for (int iteration = 0; iteration < 6; ++iteration) {
        std::vector<Lab> predicted(n), predictedWide(n);
        std::vector<uint8_t> beyond(n, 0);
        std::vector<std::array<float, 3>> outward(n, {0, 0, 0});
        for (size_t i = 0; i < n; ++i) {
            const int x = int(i % kSide);
            const float shortfall = x < kSide / 3 ? 6.0f : 0.0f;
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
        foundAny |= reach.update(
            {goal, predicted, goal, predictedWide, noiseSigma * noiseSigma, noiseSigma * noiseSigma / 10, beyond, outward});
        if (iteration < PrintersReach::kIterationsBeyond - 1) EXPECT_EQ(reach.atLimitShare(), 0.0) << iteration;
    }
    EXPECT_TRUE(foundAny);
    size_t left = 0, middle = 0, right = 0;
    for (size_t i = 0; i < n; ++i) {
        const int x = int(i % kSide);
        (x < kSide / 3 ? left : x < 2 * kSide / 3 ? middle : right) += reach.atLimit()[i];
    }
    EXPECT_EQ(left, n / 3);  // every voxel of the shortfall
    // Noise alone: a shortfall of two standard errors by chance (~2 %).
    EXPECT_LT(double(middle), 0.06 * double(n / 3));
    EXPECT_EQ(right, 0u);

    const std::vector<RGB> mapped(n, linearSrgbFromLab(target));
    const std::vector<RGB> reachable = reach.reachable(mapped, eye);
    double worstJump = 0;
    for (size_t i = 0; i < n; ++i) {
        const int x = int(i % kSide), y = int(i / kSide);
        const Lab t = labFromLinearSrgb(reachable[i]);
        // Deep in the left third: the target is what the print shows there
        // (the shortfall's mean, within its noise); far right: unchanged.
        if (x > 5 && x < kSide / 3 - 6 && y > 6 && y < kSide - 6) {
            EXPECT_NEAR(t.a, target.a - 6.0f, 0.5f) << x << " " << y;
            EXPECT_NEAR(t.L, target.L, 0.05f);
            EXPECT_NEAR(t.b, target.b, 0.05f);
        }
        if (x >= 2 * kSide / 3 + 8) EXPECT_LT(ciede2000(t, target), 0.05) << x << " " << y;
        if (x + 1 < kSide) worstJump = std::max(worstJump, ciede2000(t, labFromLinearSrgb(reachable[i + 1])));
    }
    // No seam: next to each other, targets differ by a fraction of the
    // shortfall (a step would be ~4 CIEDE2000).
    EXPECT_LT(worstJump, 0.6);
}

TEST(PrintersReach, LeavesTheErrorAcrossTheWayOutToTheLoop) {
    // The requests are pushed out along +L, the print misses along b: no
    // shortfall along the way out, nothing taken off.
    const std::vector<Point3f> points = plate();
    const size_t n = points.size();
    const Lab target{60, 40, 30};
    PrintersReach reach(n);
    const std::vector<Lab> goal(n, target), predicted(n, Lab{target.L, target.a, target.b - 8});
    const std::vector<uint8_t> beyond(n, 1);
    const std::vector<std::array<float, 3>> outward(n, {2, 0, 0});
    for (int iteration = 0; iteration < 5; ++iteration)
        reach.update({goal, predicted, goal, predicted, 0.01, 0.001, beyond, outward});
    EXPECT_EQ(reach.atLimitShare(), 0.0);
}

}  // namespace
}  // namespace pl
