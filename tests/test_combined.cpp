// combined (integrators/photons/combined.h): volpath, pp3d and bre's
// queries under one weighting. The merges' ratios; the white furnace,
// agreement with volpath on homogeneous and halftoned boxes at pp3d's
// defaults (where the merges take almost all the weight) and with few
// photons (where the walk's light and the merges share it: the weights
// must sum to one there, or the estimate counts light twice or not at
// all), and the same bits whatever the threads.
#include <gtest/gtest.h>

#include "integrators/photons/combined.h"
#include "progressive_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

RenderSettings combined(bool beams = false) {
    RenderSettings s;
    setIntegrator(s, "combined");
    s.parameters.set("combined_beams", beams ? 1.0 : 0.0);
    return s;
}

// The merges' ratios to the walk's pdf, n^2 N V / (pi A) and n^2 N r^2 / A,
// on the coloured box (its area from the mesh, N from the pixels).
TEST(Combined, MergeRatiosArePhotonDensityTimesTheKernelsSupport) {
    Scene scene = test::colouredPhotonBox(1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    CombinedOptions o;
    o.photonsPerPixel = 2.0f;
    o.beams = true;
    const Combined estimator(scene, sensor, o, Majorants::PerBrick, 1);
    double side_mm[3];
    for (int a = 0; a < 3; ++a) side_mm[a] = test::kPhotonBoxResolution[a] * double(test::kPhotonBoxVoxel_mm[a]);
    const double area_mm2 = 2.0 * (side_mm[0] * side_mm[1] + side_mm[1] * side_mm[2] + side_mm[2] * side_mm[0]);
    const double photons = std::llround(2.0 * double(sensor.pixelCount()));
    const Combined::MergeRatios ratios = estimator.mergeRatios(0.1f);
    EXPECT_NEAR(ratios.ballPerExtinction_mm, 2.25 * photons * (4.0 / 3.0) * 1e-3 / area_mm2, 1e-4 * ratios.ballPerExtinction_mm);
    EXPECT_NEAR(ratios.discTimesPhase, 2.25 * photons * 1e-2 / area_mm2, 1e-4 * ratios.discTimesPhase);
    o.beams = false;
    EXPECT_EQ(Combined(scene, sensor, o, Majorants::PerBrick, 1).mergeRatios(0.1f).discTimesPhase, 0.0);
}

TEST(Combined, WhiteFurnaceIsTheEnvironment) { test::expectWhiteFurnace(combined(), 12, 3); }

// With the beams, whose gathers take the flight's point nearest each photon
// as the merging vertex (taking the photon's own position counted light
// twice where a flight passes just outside the clear region, and failed
// this test).
TEST(Combined, WithBeamsWhiteFurnaceIsTheEnvironment) { test::expectWhiteFurnace(combined(true), 12, 3); }

TEST(Combined, AgreesWithVolpathOnHomogeneousBoxes) { test::expectAgreementOnHomogeneousBoxes(combined(), 12, 7); }

TEST(Combined, WithBeamsAgreesWithVolpathOnHomogeneousBoxes) {
    test::expectAgreementOnHomogeneousBoxes(combined(true), 12, 7);
}

TEST(Combined, AgreesWithVolpathOnAHalftonedBox) {
    Scene scene = test::halftonedPhotonBox();
    const test::Estimate reference = test::volpathFaceMiddle(scene, 256);
    for (bool beams : {false, true}) {
        RenderSettings s = combined(beams);
        s.seed = 9;
        test::expectFaceMiddlesAgree(test::renderIterations(scene, s, 16).faceMiddle, reference,
                                     beams ? "halftoned box, with beams" : "halftoned box");
    }
}

// A photon for every 4 surface voxels and a ball of one voxel: q_point is
// about 0.5-2 (and q_beam about 5), and the techniques share the weight.
// (Weighting the walk's light or the merged photons by 1, or leaving out
// the roulette's inverse, fails here.)
TEST(Combined, AgreesWithVolpathWhereEveryTechniqueCarriesWeight) {
    for (bool beams : {false, true}) {
        RenderSettings s = combined(beams);
        s.parameters.set("combined_photons_per_pixel", 0.25);
        s.parameters.set("combined_radius_voxels", 1.0);
        s.seed = 13;
        for (float ior : {1.0f, 1.5f}) {
            Scene scene = test::colouredPhotonBox(ior);
            test::expectFaceMiddlesAgree(test::renderIterations(scene, s, 32).faceMiddle,
                                         test::volpathFaceMiddle(scene, 256),
                                         std::string(beams ? "with beams" : "without") + ", few photons, IOR " +
                                             std::to_string(ior));
        }
    }
}

TEST(Combined, SameBitsWhateverTheThreads) {
    test::expectSameBitsWhateverTheThreads(combined());
    test::expectSameBitsWhateverTheThreads(combined(true));
}

}  // namespace
}  // namespace pl
