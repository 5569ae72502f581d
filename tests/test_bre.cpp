// bre (integrators/photons/bre.h): the radius schedule, the white furnace, and
// agreement with volpath on homogeneous boxes with and without a refractive
// boundary and on a halftoned box, over the voxels in the middle of the
// faces (tests/progressive_estimate.h).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

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

// No absorption: the light leaving is the environment's, L = Le, on the
// face middles (where the kernel sees photons all round) within the
// iterations' error.
TEST(Bre, WhiteFurnaceIsTheEnvironment) {
    for (float ior : {1.0f, 1.5f}) {
        Scene scene = test::whiteFurnacePhotonBox(ior);
        const IterationMeans r = renderIterations(scene, 12, 3);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(r.faceMiddle.mean[c], 1.0, 5.0 * r.faceMiddle.standardError[c] + 1e-3)
                << "IOR " << ior << ", channel " << c;
    }
}

TEST(Bre, AgreesWithVolpathOnHomogeneousBoxes) {
    for (float ior : {1.0f, 1.5f}) {
        Scene scene = test::colouredPhotonBox(ior);
        const IterationMeans bre = renderIterations(scene, 12, 7);
        test::expectFaceMiddlesAgree(bre.faceMiddle, test::volpathFaceMiddle(scene, 256),
                                     "IOR " + std::to_string(ior));
    }
}

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

TEST(Bre, SameBitsWhateverTheThreads) {
    const Scene scene = test::stripedPhotonBox();
    RenderSettings s;
    s.integrator = "bre";
    s.spp = 3;
    std::vector<float> values[2];
    for (int run = 0; run < 2; ++run) {
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, run == 0 ? 1 : 4);
        values[run] = test::surfaceValues(scene, s);
    }
    EXPECT_EQ(values[0], values[1]);
}

}  // namespace
}  // namespace pl
