// bre (integrators/photons/bre.h): the radius schedule, the white furnace, and
// agreement with volpath on homogeneous boxes with and without a refractive
// boundary and on a halftoned box, over the voxels in the middle of the
// faces (tests/progressive_estimate.h).
#include <gtest/gtest.h>

#include "integrators/photons/bre.h"
#include "progressive_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::IterationMeans;
using test::material;

IterationMeans renderIterations(const Scene& scene, uint32_t iterations, uint64_t seed, BreOptions options = {}) {
    RenderSettings s;
    s.integrator = "bre";
    s.seed = seed;
    writeOptions(breParameters(), options, s.parameters);
    return test::renderIterations(scene, s, iterations);
}

TEST(Bre, RadiusShrinksAsScheduled) {
    Scene scene = test::homogeneousPhotonBox(material({10, 10, 10}, {0.9f, 0.9f, 0.9f}), 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    BreOptions o;
    o.radius_voxels = 2.0f;
    o.alpha = 0.5f;
    const Bre shrinking(scene, sensor, o, Majorants::PerBrick, 1);
    EXPECT_FLOAT_EQ(shrinking.radiusAt_mm(1), 2.0f * 0.04f);  // the smallest voxel side
    for (uint32_t i = 1; i < 50; ++i) {
        const double ratio = std::pow(double(shrinking.radiusAt_mm(i + 1)) / shrinking.radiusAt_mm(i), 2.0);
        EXPECT_NEAR(ratio, (i + 0.5) / (i + 1.0), 1e-5) << "iteration " << i;
    }
    o.alpha = 1.0f;
    const Bre kept(scene, sensor, o, Majorants::PerBrick, 1);
    EXPECT_FLOAT_EQ(kept.radiusAt_mm(40), kept.radiusAt_mm(1));
}

RenderSettings bre() {
    RenderSettings s;
    s.integrator = "bre";
    return s;
}

TEST(Bre, WhiteFurnaceIsTheEnvironment) { test::expectWhiteFurnace(bre(), 12, 3); }

TEST(Bre, AgreesWithVolpathOnHomogeneousBoxes) { test::expectAgreementOnHomogeneousBoxes(bre(), 12, 7); }

// A skin of one resin over a halftone of two denser ones at the voxel
// scale: the light reaching a query comes through voxels of each label
// (the segment vector's transmittance: the skin's extinction taken for
// the whole segment puts red 45 % off), and the photons lie in all three.
// A first radius of half a voxel keeps the kernel's blur across columns
// below the iterations' error on the face-middle mean.
TEST(Bre, AgreesWithVolpathOnAHalftonedBox) {
    Scene scene = test::halftonedPhotonBox();
    BreOptions o;
    o.radius_voxels = 0.5f;
    const IterationMeans bre = renderIterations(scene, 16, 9, o);
    test::expectFaceMiddlesAgree(bre.faceMiddle, test::volpathFaceMiddle(scene, 256), "halftoned box");
}

TEST(Bre, SameBitsWhateverTheThreads) { test::expectSameBitsWhateverTheThreads(bre()); }

}  // namespace
}  // namespace pl
