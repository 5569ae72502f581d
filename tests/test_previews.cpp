// Perspective previews: re-entry is nothing on a convex mesh (so the
// estimators that do not trace it serve a convex object's preview), and
// printpt on a perspective camera agrees with volpath pixel by pixel.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sensors.h"
#include "render/render.h"
#include "render_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

TEST(Convexity, BoxesAndPolyhedraAreConvexDentsAndPairsAreNot) {
    EXPECT_TRUE(isConvex(boxMesh({0, 0, 0}, {10, 20, 5})));
    // Far from the origin, where float round-off of the corners is largest.
    EXPECT_TRUE(isConvex(boxMesh({1000, 1000, 1000}, {1000.3f, 1000.1f, 1000.2f})));
    // An octahedron: no face is axis-aligned.
    TriangleMesh octahedron;
    octahedron.positions_mm = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    octahedron.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    EXPECT_TRUE(isConvex(octahedron));
    // The same with its top pushed in below its equator: a dent.
    TriangleMesh dented = octahedron;
    dented.positions_mm[4] = {0, 0, -0.5f};
    EXPECT_FALSE(isConvex(dented));
    // Two boxes side by side: each convex, the pair not (light leaving one
    // can enter the other).
    TriangleMesh pair = boxMesh({0, 0, 0}, {1, 1, 1});
    const TriangleMesh second = boxMesh({2, 0, 0}, {3, 1, 1});
    const uint32_t first = uint32_t(pair.positions_mm.size());
    pair.positions_mm.insert(pair.positions_mm.end(), second.positions_mm.begin(), second.positions_mm.end());
    for (uint32_t i : second.indices) pair.indices.push_back(first + i);
    EXPECT_FALSE(isConvex(pair));
    EXPECT_FALSE(isConvex(TriangleMesh{}));
}

// A halftone-like box of inks and clear resin seen from above a corner.
Scene halftonedBox() {
    MaterialTable t = test::mixedResins();
    return test::boxScene({24, 24, 24}, {0.05f, 0.05f, 0.05f},
                          [](const Vec3i& v) {
                              static const Label palette[6] = {0, 1, 3, 4, 4, 6};
                              return palette[(v.x / 2 + 2 * (v.y / 3) + 3 * (v.z / 2)) % 6];
                          },
                          t, 1.5f);
}

TEST(Previews, PrintptAgreesWithVolpathPixelByPixel) {
    const Scene scene = halftonedBox();
    ASSERT_TRUE(isConvex(scene.geometry->mesh()));
    const PerspectiveSensor camera({{3.2f, -1.9f, 2.9f}, {0.6f, 0.6f, 0.6f}, {0, 0, 1}}, 30.0f, 40, 30);
    RenderSettings s;
    s.seed = 3;
    s.spp = 64;
    const RenderResult volpath = render(scene, camera, s);
    s.integrator = "printpt";
    s.spp = 16;
    s.seed = 4;
    const RenderResult printpt = render(scene, camera, s);
    test::expectAgreement(test::meanOf(volpath), test::meanOf(printpt), "printpt on a perspective camera");
    // Pixel by pixel: z = difference over the combined standard error, over
    // the pixels whose samples varied in both (those that saw the box). The
    // silhouette's pixels mix rays that miss with rays that enter: their
    // errors must hold that mixing too.
    double sumZ2 = 0;
    size_t values = 0, beyond4 = 0;
    for (size_t p = 0; p < camera.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            const double a = volpath.film.standardError(p, c), b = printpt.film.standardError(p, c);
            const double combined = std::sqrt(a * a + b * b);
            if (!(volpath.film.spreadError(p, c) > 0.0f && printpt.film.spreadError(p, c) > 0.0f)) continue;
            const double z = (volpath.film.mean(p, c) - printpt.film.mean(p, c)) / combined;
            sumZ2 += z * z;
            beyond4 += std::abs(z) > 4.0 ? 1 : 0;
            ++values;
        }
    ASSERT_GT(values, 1000u);
    // A bias of half a standard error, or errors a tenth too small, move the
    // mean z^2 by 0.25; sampling moves it by about sqrt(2 / values) ~ 0.04.
    EXPECT_NEAR(sumZ2 / double(values), 1.0, 0.25);
    EXPECT_LT(double(beyond4) / double(values), 0.005);
}

}  // namespace
}  // namespace pl
