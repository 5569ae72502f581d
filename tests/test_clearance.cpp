// The surface clearance is a lower bound of the distance to the boundary
// everywhere in the frame (else printpt would miss boundary crossings), and
// deep inside it is large enough to skip queries.
#include <gtest/gtest.h>

#include "core/rng.h"
#include "core/surface_clearance.h"
#include "test_util.h"

namespace pl {
namespace {

TEST(SurfaceClearance, IsALowerBoundOfTheDistanceToTheBoundary) {
    // Anisotropic voxels, a frame away from the origin whose size is not a
    // multiple of the brick, and a mesh that reaches the frame's faces.
    GridFrame frame;
    frame.indexMin = {-7, 3, 11};
    frame.resolution = {61, 45, 83};
    frame.voxelSize_mm = {0.0423f, 0.0847f, 0.027f};
    frame.cornerMin_mm = {12.5f, -3.0f, 40.0f};
    Point3f hi = frame.cornerMax_mm();
    Point3f lo = frame.cornerMin_mm + Vec3f(0.3f, 0.0f, 0.2f);
    Geometry geometry(test::boxMesh(lo, hi));
    SurfaceClearance clearance(geometry, frame);

    Rng rng(7, 0);
    int positive = 0;
    for (int i = 0; i < 200000; ++i) {
        Point3f p{frame.cornerMin_mm.x + rng.uniform() * (hi.x - frame.cornerMin_mm.x),
                  frame.cornerMin_mm.y + rng.uniform() * (hi.y - frame.cornerMin_mm.y),
                  frame.cornerMin_mm.z + rng.uniform() * (hi.z - frame.cornerMin_mm.z)};
        auto c = geometry.closestPoint(p, 1e3f);
        ASSERT_TRUE(c.has_value());
        float bound = clearance.at(p);
        ASSERT_LE(bound, c->distance_mm) << "at " << p.x << "," << p.y << "," << p.z;
        positive += bound > 0.0f;
    }
    // The box is 2.5 x 3.8 x 2.0 mm and a brick's half diagonal 0.39 mm:
    // much of the inside must be cleared.
    EXPECT_GT(positive, 200000 / 5);
    // Outside the frame nothing is known.
    EXPECT_EQ(clearance.at(frame.cornerMin_mm - Vec3f(0.01f, 0, 0)), 0.0f);
    EXPECT_EQ(clearance.at(hi + Vec3f(0, 0, 0.01f)), 0.0f);
}

}  // namespace
}  // namespace pl
