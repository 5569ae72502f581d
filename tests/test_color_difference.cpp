// CIEDE2000 against the test data of Sharma, Wu and Dalal (2005), and the
// sRGB to L*a*b* conversion against known points.
#include <gtest/gtest.h>

#include "compare/color_difference.h"

namespace pl {
namespace {

TEST(ColorDifference, Ciede2000MatchesSharmasTestData) {
    struct Pair {
        Lab a, b;
        double deltaE;
    };
    const Pair pairs[] = {
        {{50.0f, 2.6772f, -79.7751f}, {50.0f, 0.0f, -82.7485f}, 2.0425},
        {{50.0f, 3.1571f, -77.2803f}, {50.0f, 0.0f, -82.7485f}, 2.8615},
        {{50.0f, 2.8361f, -74.0200f}, {50.0f, 0.0f, -82.7485f}, 3.4412},
        {{50.0f, 0.0f, 0.0f}, {50.0f, -1.0f, 2.0f}, 2.3669},
        {{50.0f, 2.4900f, -0.0010f}, {50.0f, -2.4900f, 0.0009f}, 7.1792},
        {{50.0f, 2.5f, 0.0f}, {73.0f, 25.0f, -18.0f}, 27.1492},
        {{60.2574f, -34.0099f, 36.2677f}, {60.4626f, -34.1751f, 39.4387f}, 1.2644},
    };
    for (const Pair& p : pairs) {
        EXPECT_NEAR(ciede2000(p.a, p.b), p.deltaE, 1e-4) << p.a.L << " " << p.a.a << " " << p.a.b;
        EXPECT_NEAR(ciede2000(p.b, p.a), p.deltaE, 1e-4);  // symmetric
    }
    EXPECT_EQ(ciede2000({40, 10, -5}, {40, 10, -5}), 0.0);
}

TEST(ColorDifference, LinearSrgbToLab) {
    Lab white = labFromLinearSrgb({1, 1, 1});
    EXPECT_NEAR(white.L, 100.0f, 1e-3f);
    EXPECT_NEAR(white.a, 0.0f, 1e-2f);
    EXPECT_NEAR(white.b, 0.0f, 1e-2f);
    Lab black = labFromLinearSrgb({0, 0, 0});
    EXPECT_NEAR(black.L, 0.0f, 1e-4f);
    // Middle grey: Y = 0.18 gives L* = 49.5.
    EXPECT_NEAR(labFromLinearSrgb({0.18f, 0.18f, 0.18f}).L, 49.496f, 1e-2f);
    // Pure sRGB red: L* 53.24, a* 80.09, b* 67.20.
    Lab red = labFromLinearSrgb({1, 0, 0});
    EXPECT_NEAR(red.L, 53.24f, 0.05f);
    EXPECT_NEAR(red.a, 80.09f, 0.1f);
    EXPECT_NEAR(red.b, 67.20f, 0.1f);
}

}  // namespace
}  // namespace pl
