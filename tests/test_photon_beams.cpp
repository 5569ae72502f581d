// pb2d and bb1d (integrators/photons/photon_beams.h): the beam map finds every beam
// near a point or a segment, the radius schedules, the white furnace, and
// agreement with volpath on homogeneous boxes with and without a refractive
// boundary and on a halftoned box, over the voxels in the middle of the
// faces (tests/progressive_estimate.h).
#include <gtest/gtest.h>

#include <set>

#include "core/sampling.h"

#include "integrators/photons/bb1d.h"
#include "integrators/photons/pb2d.h"
#include "progressive_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::IterationMeans;
using test::material;

const char* const kEstimators[] = {"pb2d", "bb1d"};

IterationMeans renderIterations(const Scene& scene, const char* integrator, uint32_t iterations, uint64_t seed,
                                BeamOptions options = {}) {
    RenderSettings s;
    s.integrator = integrator;
    s.seed = seed;
    writeOptions(beamParameters(), options, s.parameters);
    return test::renderIterations(scene, s, iterations);
}

// Beams of every length and direction, and points and segments among them:
// what the map visits holds every beam within the radius (by brute force).
TEST(PhotonBeams, MapFindsEveryBeamWithinTheRadius) {
    Rng rng(7, 0);
    auto point = [&] { return Point3f{rng.uniform(), rng.uniform(), rng.uniform()}; };
    // Isotropic phase sampling: uniform on the sphere.
    auto direction = [&] { return sampleHG(Vec3f{0, 0, 1}, 0.0f, rng.uniform(), rng.uniform()).dOut; };
    std::vector<PhotonBeam> beams;
    for (int i = 0; i < 2000; ++i) beams.push_back({point(), direction(), 0.3f * rng.uniform(), 1.0f});
    const float r = 0.04f;
    const PhotonBeamMap map(beams, r, Point3f{-0.5f, -0.5f, -0.5f});
    auto distanceToBeam = [](const PhotonBeam& b, const Point3f& x) {
        const float s = std::min(std::max(dot(x - b.o, b.d), 0.0f), b.length_mm);
        return length(x - b.at(s));
    };
    for (int q = 0; q < 300; ++q) {
        const Point3f x = point();
        std::set<uint32_t> visited;
        map.forEachNearPoint(x, [&](uint32_t i) { visited.insert(i); });
        for (uint32_t i = 0; i < beams.size(); ++i) {
            if (!(distanceToBeam(beams[i], x) < r)) continue;
            EXPECT_TRUE(visited.count(i)) << "query " << q << ", beam " << i;
        }
        // A segment: every beam within r of a point along it.
        const Ray segment{x, direction()};
        const float tMax = 0.2f;
        visited.clear();
        map.forEachNearSegment(segment, tMax, [&](uint32_t i) { visited.insert(i); });
        for (int k = 0; k <= 20; ++k) {
            const Point3f y = segment.at(tMax * k / 20.0f);
            for (uint32_t i = 0; i < beams.size(); ++i) {
                if (!(distanceToBeam(beams[i], y) < r)) continue;
                EXPECT_TRUE(visited.count(i)) << "segment " << q << ", beam " << i;
            }
        }
    }
}

// The kernels at both radii integrate to 1 (the disc's over the plane, the
// line's across it), and a density that does not vary shows no bias.
TEST(PhotonBeams, KernelsAtBothRadiiIntegrateToOne) {
    const double r = 0.3, step = r / 2000;
    TwoRadii disc, line;
    for (double x = step / 2; x < r; x += step) {
        disc += discBiweight(x * x, r * r) * (2.0 * kPi * x * step);
        line += lineBiweight(x * x, r) * (2.0 * step);
    }
    EXPECT_NEAR(disc.full, 1.0, 1e-5);
    EXPECT_NEAR(disc.half, 1.0, 1e-5);
    EXPECT_NEAR(line.full, 1.0, 1e-5);
    EXPECT_NEAR(line.half, 1.0, 1e-5);
    EXPECT_NEAR(disc.bias(), 0.0, 1e-5);
    // Half the disc cut away beyond 0.75 r from the query: the half radius
    // misses none of it, the full one some, and the bias says how much.
    TwoRadii cut;
    for (double x = -r; x < r; x += step)
        for (double y = -r; y < r; y += step)
            if (x < 0.75 * r) cut += discBiweight(x * x + y * y, r * r) * (step * step);
    EXPECT_NEAR(cut.half, 1.0, 1e-3);
    EXPECT_LT(cut.full, 1.0);
    EXPECT_NEAR(cut.bias(), 2.0 * (cut.full - 1.0), 1e-3);
}

TEST(PhotonBeams, RadiusShrinksWithTheKernelsDimensions) {
    Scene scene = test::homogeneousPhotonBox(material({10, 10, 10}, {0.9f, 0.9f, 0.9f}), 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    BeamOptions o;
    o.radius_voxels = 2.0f;
    o.alpha = 0.5f;
    const Pb2d pb2d(scene, sensor, o, Majorants::PerBrick, 1);
    const Bb1d bb1d(scene, sensor, o, Majorants::PerBrick, 1);
    EXPECT_FLOAT_EQ(pb2d.radiusAt_mm(1), 2.0f * 0.04f);  // the smallest voxel side
    EXPECT_FLOAT_EQ(bb1d.radiusAt_mm(1), 2.0f * 0.04f);
    for (uint32_t i = 1; i < 50; ++i) {
        const double shrink = (i + 0.5) / (i + 1.0);
        EXPECT_NEAR(std::pow(double(pb2d.radiusAt_mm(i + 1)) / pb2d.radiusAt_mm(i), 2.0), shrink, 1e-5) << i;
        EXPECT_NEAR(double(bb1d.radiusAt_mm(i + 1)) / bb1d.radiusAt_mm(i), shrink, 1e-5) << i;
    }
    o.alpha = 1.0f;
    const Bb1d kept(scene, sensor, o, Majorants::PerBrick, 1);
    EXPECT_FLOAT_EQ(kept.radiusAt_mm(40), kept.radiusAt_mm(1));
}

RenderSettings settingsOf(const char* estimator) {
    RenderSettings s;
    s.integrator = estimator;
    return s;
}

TEST(PhotonBeams, WhiteFurnaceIsTheEnvironment) {
    for (const char* estimator : kEstimators) test::expectWhiteFurnace(settingsOf(estimator), 12, 3);
}

TEST(PhotonBeams, AgreeWithVolpathOnHomogeneousBoxes) {
    for (const char* estimator : kEstimators) test::expectAgreementOnHomogeneousBoxes(settingsOf(estimator), 12, 7);
}

// A skin of one resin over a halftone of two denser ones at the voxel
// scale (bre's test): beams cross voxels of every label, and bb1d's sigma_s
// is the voxel's at each closest point. A first radius of half a voxel
// keeps the kernel's blur across columns below the iterations' error.
TEST(PhotonBeams, AgreeWithVolpathOnAHalftonedBox) {
    Scene scene = test::halftonedPhotonBox();
    const test::Estimate reference = test::volpathFaceMiddle(scene, 256);
    BeamOptions o;
    o.radius_voxels = 0.5f;
    for (const char* estimator : kEstimators)
        test::expectFaceMiddlesAgree(renderIterations(scene, estimator, 16, 9, o).faceMiddle, reference, estimator);
}

TEST(PhotonBeams, SameBitsWhateverTheThreads) {
    for (const char* estimator : kEstimators) test::expectSameBitsWhateverTheThreads(settingsOf(estimator));
}

}  // namespace
}  // namespace pl
