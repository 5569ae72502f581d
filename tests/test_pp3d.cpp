// pp3d (integrators/photons/pp3d.h): the ball kernel, the map's point
// query, the radius schedule, the white furnace, and agreement with volpath
// on homogeneous boxes with and without a refractive boundary and on a
// halftoned box, over the voxels in the middle of the faces
// (tests/progressive_estimate.h).
#include <gtest/gtest.h>

#include <set>

#include "integrators/photons/pp3d.h"
#include "integrators/photons/two_radii.h"
#include "progressive_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

RenderSettings pp3d() {
    RenderSettings s;
    s.integrator = "pp3d";
    return s;
}

// The ball's kernel at both radii integrates to 1 over space (shells).
TEST(Pp3d, BallKernelAtBothRadiiIntegratesToOne) {
    const double r = 0.3, step = r / 4000;
    TwoRadii ball;
    for (double x = step / 2; x < r; x += step) ball += ballBiweight(x * x, r * r) * (4.0 * kPi * x * x * step);
    EXPECT_NEAR(ball.full, 1.0, 1e-5);
    EXPECT_NEAR(ball.half, 1.0, 1e-5);
    EXPECT_NEAR(ball.bias(), 0.0, 1e-5);
}

// What the map visits around a point holds every photon within the radius
// (by brute force), each once.
TEST(Pp3d, MapFindsEveryPhotonWithinTheRadius) {
    Rng rng(11, 0);
    auto point = [&] { return Point3f{rng.uniform(), rng.uniform(), rng.uniform()}; };
    std::vector<PhotonMap::Photon> photons;
    for (int i = 0; i < 5000; ++i) photons.push_back({point(), Vec3f{0, 0, 1}, float(i), 0});
    const float r = 0.05f;
    const PhotonMap map(photons, r);
    for (int q = 0; q < 300; ++q) {
        const Point3f x = point();
        std::multiset<float> visited;
        map.forEachNearPoint(x, [&](const PhotonMap::Photon& ph) { visited.insert(ph.power); });
        for (const PhotonMap::Photon& ph : photons) {
            if (!(length(ph.p - x) < r)) continue;
            EXPECT_EQ(visited.count(ph.power), 1u) << "query " << q << ", photon " << ph.power;
        }
    }
}

TEST(Pp3d, RadiusShrinksAsScheduled) {
    Scene scene = test::homogeneousPhotonBox(material({10, 10, 10}, {0.9f, 0.9f, 0.9f}), 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    Pp3dOptions o;
    o.radius_voxels = 2.0f;
    o.alpha = 0.5f;
    const Pp3d shrinking(scene, sensor, o, Majorants::PerBrick, 1);
    EXPECT_FLOAT_EQ(shrinking.radiusAt_mm(1), 2.0f * 0.04f);  // the smallest voxel side
    for (uint32_t i = 1; i < 50; ++i) {
        const double ratio = std::pow(double(shrinking.radiusAt_mm(i + 1)) / shrinking.radiusAt_mm(i), 3.0);
        EXPECT_NEAR(ratio, (i + 0.5) / (i + 1.0), 1e-5) << "iteration " << i;
    }
    o.alpha = 1.0f;
    const Pp3d kept(scene, sensor, o, Majorants::PerBrick, 1);
    EXPECT_FLOAT_EQ(kept.radiusAt_mm(40), kept.radiusAt_mm(1));
}

TEST(Pp3d, WhiteFurnaceIsTheEnvironment) { test::expectWhiteFurnace(pp3d(), 12, 3); }

TEST(Pp3d, AgreesWithVolpathOnHomogeneousBoxes) { test::expectAgreementOnHomogeneousBoxes(pp3d(), 12, 7); }

// A skin of one resin over a halftone of two denser ones at the voxel
// scale (bre's test): the ball takes photons from voxels of every label,
// each divided by sigma_s where it was stored. (Dividing by sigma_s at the
// query instead moves red 4 % here, within this test's errors.)
TEST(Pp3d, AgreesWithVolpathOnAHalftonedBox) {
    Scene scene = test::halftonedPhotonBox();
    RenderSettings s = pp3d();
    s.seed = 9;
    test::expectFaceMiddlesAgree(test::renderIterations(scene, s, 16).faceMiddle, test::volpathFaceMiddle(scene, 256),
                                 "halftoned box");
}

TEST(Pp3d, SameBitsWhateverTheThreads) { test::expectSameBitsWhateverTheThreads(pp3d()); }

}  // namespace
}  // namespace pl
