// A ray spawned into the object at an edge (an entry sampled on it, a
// round-off past it) can leave through the other face before its tMin,
// which skips the face it was spawned on: without looking there the walk
// found no boundary at all, a numerical leak (one in 2 x 10^5 photon walks
// on the clearer slab).
#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry.h"
#include "test_util.h"

namespace pl {
namespace {

TEST(SpawnRay, ExitBeforeTMinIsTheFaceByTheEdge) {
    Geometry geometry(test::boxMesh({0, 0, 0}, {8, 8, 1}));
    const Vec3f up{0, 0, 1};  // the top face's outward normal
    const Vec3f towardsSide = normalize(Vec3f(0.7f, 0.0f, -0.7f));
    const Ray atEdge = geometry.spawnRay({std::nextafter(8.0f, 9.0f), 4.0f, 1.0f}, up, towardsSide);
    EXPECT_FALSE(geometry.intersect(atEdge)) << "the case the walk must handle";
    const std::optional<SurfaceHit> exit = geometry.exitBeforeTMin(atEdge);
    ASSERT_TRUE(exit);
    EXPECT_NEAR(exit->ng.x, 1.0f, 1e-5f);
    EXPECT_NEAR(exit->p.x, 8.0f, 1e-4f);
    EXPECT_LT(exit->t, atEdge.tMin);
    // Away from edges the faces beyond tMin are found as ever, and nothing
    // is taken for an exit before it.
    const Ray middle = geometry.spawnRay({4.0f, 4.0f, 1.0f}, up, towardsSide);
    EXPECT_TRUE(geometry.intersect(middle));
    EXPECT_FALSE(geometry.exitBeforeTMin(middle));
}

}  // namespace
}  // namespace pl
