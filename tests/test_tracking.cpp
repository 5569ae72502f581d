// Delta tracking (free-flight distribution) and regular tracking
// (transmittance) against analytic values on homogeneous and
// piecewise-constant label media, through the OpenVDB-backed sampler.
#include <gtest/gtest.h>

#include "media/ball_walk.h"
#include "media/label_medium.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

// Layers across x (voxel index ranges) with their sigma_t.
struct Layer {
    int x0, x1;
    Label label;
    float sigma;
};
const std::vector<Layer> kLayers = {
    {0, 8, 6, 0.0f}, {8, 12, 0, 0.5f}, {12, 16, 1, 5.0f}, {16, 24, 2, 1.5f}, {24, 32, 3, 0.2f}};
const Vec3f kVoxel{0.1f, 0.05f, 0.2f};  // anisotropic on purpose

LabelMedium layeredMedium() {
    MaterialTable t;
    for (const Layer& l : kLayers) {
        t.byLabel[l.label] = material({l.sigma, 2 * l.sigma, 0.5f * l.sigma}, {0.5f, 0.5f, 0.5f});
    }
    LabelGrid grid = test::boxGrid({32, 128, 32}, kVoxel, [](const Vec3i& v) {
        for (const Layer& l : kLayers)
            if (v.x >= l.x0 && v.x < l.x1) return l.label;
        return test::kTestVoid;
    });
    return LabelMedium(std::move(grid), t);
}

// Optical depth along the ray from 0 to t (channel 0), from the layer planes.
double layeredOpticalDepth(const Ray& r, double t) {
    double tau = 0;
    for (const Layer& l : kLayers) {
        double a = (l.x0 * kVoxel.x - r.o.x) / r.d.x, b = (l.x1 * kVoxel.x - r.o.x) / r.d.x;
        if (a > b) std::swap(a, b);
        double lo = std::max(a, 0.0), hi = std::min(b, t);
        if (hi > lo) tau += l.sigma * (hi - lo);
    }
    return tau;
}

Label layerLabelAt(float x_mm) {
    for (const Layer& l : kLayers)
        if (x_mm >= l.x0 * kVoxel.x && x_mm < l.x1 * kVoxel.x) return l.label;
    return test::kTestVoid;
}

TEST(RegularTracking, TransmittanceOfLayeredMediumIsExact) {
    LabelMedium medium = layeredMedium();
    LabelMedium::Tracker sampler(medium);
    // The ray starts outside the grid and crosses every layer obliquely.
    Ray r{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
    for (float tMax : {0.5f, 1.3f, 1.9f, 2.6f, 3.3f, 4.0f, 5.5f, 8.0f}) {
        double expected = std::exp(-layeredOpticalDepth(r, tMax));
        EXPECT_NEAR(sampler.transmittance(r, tMax, 0), expected, 2e-5 + 1e-4 * expected) << tMax;
    }
    // Exactly along the x axis and along voxel faces (y, z on integer cells).
    Ray axis{{-1.0f, 10 * kVoxel.y, 4 * kVoxel.z}, {1, 0, 0}};
    EXPECT_NEAR(sampler.transmittance(axis, 10.0f, 0), std::exp(-layeredOpticalDepth(axis, 10.0)), 1e-5);
    // Backwards along -x from beyond the far side.
    Ray back{{5.0f, 2.0f, 3.0f}, {-1, 0, 0}};
    EXPECT_NEAR(sampler.transmittance(back, 10.0f, 0), std::exp(-layeredOpticalDepth(back, 10.0)), 1e-5);
    // Channel 1 has twice the density.
    EXPECT_NEAR(sampler.transmittance(r, 8.0f, 1), std::exp(-2 * layeredOpticalDepth(r, 8.0)), 1e-5);
}

TEST(RegularTracking, HomogeneousBeerLambert) {
    MaterialTable t;
    t.byLabel[4] = material({6, 9, 24}, {1, 1, 1});
    LabelMedium medium(test::boxGrid({20, 20, 20}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(4); }), t);
    LabelMedium::Tracker sampler(medium);
    Ray r{{0.05f, 0.5f, 0.5f}, normalize(Vec3f(1.0f, 0.2f, 0.1f))};
    for (int c = 0; c < 3; ++c)
        for (float d : {0.01f, 0.1f, 0.5f, 1.0f})
            EXPECT_NEAR(sampler.transmittance(r, d, c), std::exp(-medium.lut(c).sigmaT_perMm[4] * d), 1e-5f);
}

// A segment whose transmittance a test estimates.
struct SegmentCase {
    LabelMedium* medium;
    Ray ray;
    float tMax_mm;
    int channel;
};

// The mean of n draws and its standard error.
struct DrawnMean {
    double mean, error;
};
template <class Draw>
DrawnMean meanOfDraws(int n, Draw&& draw) {
    double sum = 0, sumSq = 0;
    for (int i = 0; i < n; ++i) {
        const double x = draw();
        sum += x;
        sumSq += x * x;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sumSq / n - mean * mean) / (n - 1))};
}

// With Russian roulette past an optical depth the transmittance is a random
// estimate: its mean must be the exact value, in layered (voxel by voxel)
// and homogeneous (whole bricks) media, and the roulette must actually end
// some segments early.
TEST(RegularTracking, RouletteTransmittanceIsUnbiased) {
    LabelMedium layered = layeredMedium();
    MaterialTable t;
    t.byLabel[4] = material({6, 9, 24}, {1, 1, 1});
    LabelMedium homogeneous(test::boxGrid({20, 20, 20}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(4); }),
                            t);
    const Ray oblique{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
    const Ray inside{{0.05f, 0.5f, 0.5f}, normalize(Vec3f(1.0f, 0.2f, 0.1f))};
    for (const SegmentCase& c : {SegmentCase{&layered, oblique, 3.3f, 0}, SegmentCase{&layered, oblique, 3.3f, 2},
                                 SegmentCase{&homogeneous, inside, 0.5f, 1},
                                 SegmentCase{&homogeneous, inside, 0.2f, 2}}) {
        LabelMedium::Tracker sampler(*c.medium);
        const double exact = sampler.transmittance(c.ray, c.tMax_mm, c.channel);
        ASSERT_GT(exact, 1e-4);
        ASSERT_LT(exact, 0.5) << c.tMax_mm << " " << c.channel;
        Rng rng(7, 3);
        const int n = 40000;
        int ended = 0;
        const DrawnMean m = meanOfDraws(n, [&] {
            const double T = sampler.transmittance(c.ray, c.tMax_mm, c.channel, TransmittanceRoulette{0.5f, &rng});
            ended += T == 0.0;
            return T;
        });
        EXPECT_NEAR(m.mean, exact, 4.0 * m.error) << c.tMax_mm;
        EXPECT_GT(ended, n / 2) << "the roulette should end most segments this deep";
    }
}

// Ratio tracking and pins (media/segment_transmittance.h) estimate a fixed
// segment's transmittance without bias: their means over many draws agree
// with regular tracking's exact value, on the layers (bricks of one label
// and mixed ones) and on a checkerboard (every voxel a label change).
TEST(SegmentTransmittance, RatioTrackingAndPinsAreUnbiased) {
    LabelMedium layered = layeredMedium();
    MaterialTable t;
    t.byLabel[1] = material({5, 10, 2}, {0.9f, 0.9f, 0.9f});
    t.byLabel[2] = material({20, 3, 12}, {0.9f, 0.9f, 0.9f});
    LabelMedium checkerboard(
        test::boxGrid({32, 32, 32}, {0.1f, 0.1f, 0.1f}, [](const Vec3i& v) { return Label(1 + (v.x + v.y + v.z) % 2); }),
        t);
    const Ray oblique{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
    const Ray inside{{0.55f, 0.5f, 0.45f}, normalize(Vec3f(1.0f, 0.3f, 0.2f))};
    for (const SegmentCase& c : {SegmentCase{&layered, oblique, 3.3f, 0}, SegmentCase{&layered, oblique, 2.6f, 1},
                                 SegmentCase{&checkerboard, inside, 0.3f, 0},
                                 SegmentCase{&checkerboard, inside, 0.6f, 2}}) {
        LabelMedium::Tracker tracker(*c.medium);
        const double exact = tracker.transmittance(c.ray, c.tMax_mm, c.channel);
        ASSERT_GT(exact, 0.01);
        ASSERT_LT(exact, 0.8);
        for (int estimator = 0; estimator < 2; ++estimator) {
            Rng rng(17, uint64_t(estimator));
            const DrawnMean m = meanOfDraws(40000, [&] {
                return estimator == 0 ? tracker.ratioTrackedTransmittance(c.ray, c.tMax_mm, c.channel, rng)
                                      : tracker.pinTransmittance(c.ray, c.tMax_mm, c.channel, rng);
            });
            EXPECT_GT(m.error, 0.0);  // the mixed bricks make them stochastic
            EXPECT_NEAR(m.mean, exact, 4.0 * m.error) << (estimator == 0 ? "ratio tracking" : "pins") << ", "
                                                      << c.tMax_mm << " mm, channel " << c.channel;
        }
    }
}

// Free-flight distances: chi-square over distance bins plus an escape bin.
void checkFreeFlight(LabelMedium& medium, const Ray& r, float tMax, int channel,
                     const std::function<double(double)>& tau, int n, uint64_t seed,
                     Majorants majorants = Majorants::PerBrick) {
    LabelMedium::Tracker sampler(medium, majorants);
    const int bins = 60;
    std::vector<double> observed(bins + 1, 0), expected(bins + 1, 0);
    Rng rng(seed, 11);
    for (int i = 0; i < n; ++i) {
        FreeFlight ff = sampler.sampleFreeFlight(r, tMax, channel, rng);
        if (!ff.scattered) {
            observed[bins] += 1;
            continue;
        }
        ASSERT_GE(ff.t_mm, 0.0f);
        ASSERT_LT(ff.t_mm, tMax);
        observed[size_t(std::min(bins - 1, int(ff.t_mm / tMax * bins)))] += 1;
    }
    for (int b = 0; b < bins; ++b)
        expected[size_t(b)] = n * (std::exp(-tau(tMax * b / bins)) - std::exp(-tau(tMax * (b + 1) / bins)));
    expected[bins] = n * std::exp(-tau(tMax));
    EXPECT_LT(test::chiSquareZ(observed, expected), test::kChiSquareZLimit);
}

TEST(DeltaTracking, HomogeneousFreeFlightIsExponential) {
    MaterialTable t;
    t.byLabel[4] = material({6, 9, 24}, {1, 1, 1});
    LabelMedium medium(test::boxGrid({16, 16, 16}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(4); }), t);
    Ray r{{0.8f, 0.8f, 0.8f}, normalize(Vec3f(0.3f, -0.4f, 0.5f))};
    float tMax = 0.7f;
    for (int c = 0; c < 3; ++c) {
        double sigma = medium.lut(c).sigmaT_perMm[4];
        checkFreeFlight(medium, r, tMax, c, [&](double t) { return sigma * t; }, 100000, 10 + c);
    }
}

TEST(DeltaTracking, LayeredFreeFlightMatchesAnalyticOpticalDepth) {
    LabelMedium medium = layeredMedium();
    Ray r{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
    checkFreeFlight(medium, r, 6.0f, 0, [&](double t) { return layeredOpticalDepth(r, t); }, 200000, 3);
    checkFreeFlight(medium, r, 6.0f, 1, [&](double t) { return 2 * layeredOpticalDepth(r, t); }, 200000, 4);
}

// The textbook tracker (one majorant for the grid) samples the same
// distribution, from a ray that starts outside the grid or inside it.
TEST(DeltaTracking, GlobalMajorantFreeFlightMatchesAnalyticOpticalDepth) {
    LabelMedium medium = layeredMedium();
    Ray r{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
    checkFreeFlight(medium, r, 6.0f, 0, [&](double t) { return layeredOpticalDepth(r, t); }, 200000, 5,
                    Majorants::Global);
    checkFreeFlight(medium, r, 6.0f, 2, [&](double t) { return 0.5 * layeredOpticalDepth(r, t); }, 200000, 6,
                    Majorants::Global);
    Ray inside{{1.0f, 3.0f, 3.0f}, normalize(Vec3f(0.7f, -0.2f, 0.3f))};
    checkFreeFlight(medium, inside, 3.0f, 1, [&](double t) { return 2 * layeredOpticalDepth(inside, t); }, 200000, 7,
                    Majorants::Global);
}

// Decomposition tracking: a homogeneous medium is all control; the layers'
// bricks hold a control (their least extinction) and a residual, and
// bricks of clear resin neither.
TEST(DecompositionTracking, FreeFlightMatchesAnalyticOpticalDepth) {
    MaterialTable t;
    t.byLabel[4] = material({6, 9, 24}, {1, 1, 1});
    LabelMedium homogeneous(test::boxGrid({16, 16, 16}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(4); }), t);
    const Ray r{{0.8f, 0.8f, 0.8f}, normalize(Vec3f(0.3f, -0.4f, 0.5f))};
    const double sigma = homogeneous.lut(1).sigmaT_perMm[4];
    checkFreeFlight(homogeneous, r, 0.7f, 1, [&](double s) { return sigma * s; }, 100000, 21,
                    Majorants::Decomposition);
    LabelMedium medium = layeredMedium();
    const Ray oblique{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
    checkFreeFlight(medium, oblique, 6.0f, 0, [&](double s) { return layeredOpticalDepth(oblique, s); }, 200000, 22,
                    Majorants::Decomposition);
    checkFreeFlight(medium, oblique, 6.0f, 1, [&](double s) { return 2 * layeredOpticalDepth(oblique, s); }, 200000,
                    23, Majorants::Decomposition);
    const Ray inside{{1.0f, 3.0f, 3.0f}, normalize(Vec3f(0.7f, -0.2f, 0.3f))};
    checkFreeFlight(medium, inside, 3.0f, 2, [&](double s) { return 0.5 * layeredOpticalDepth(inside, s); }, 200000,
                    24, Majorants::Decomposition);
}

TEST(DeltaTracking, CollisionsReportTheLabelWhereTheyHappen) {
    LabelMedium medium = layeredMedium();
    for (Majorants majorants : {Majorants::PerBrick, Majorants::Global, Majorants::Decomposition}) {
        LabelMedium::Tracker sampler(medium, majorants);
        Ray r{{-1.0f, 1.2f, 1.1f}, normalize(Vec3f(0.8f, 0.36f, 0.48f))};
        Rng rng(8, 8);
        int checked = 0;
        for (int i = 0; i < 20000; ++i) {
            FreeFlight ff = sampler.sampleFreeFlight(r, 6.0f, 0, rng);
            if (!ff.scattered) continue;
            float x = r.at(ff.t_mm).x;
            // Away from layer planes (float round-off may pick either side).
            if (std::abs(x / kVoxel.x - std::round(x / kVoxel.x)) < 1e-3f) continue;
            ASSERT_EQ(ff.label, layerLabelAt(x)) << "x = " << x;
            EXPECT_GT(medium.lut(0).sigmaT_perMm[ff.label], 0.0f);  // never in the clear layer
            ++checked;
        }
        EXPECT_GT(checked, 10000);
    }
}

TEST(Majorants, ClearAndVoidBricksGetTheirOwnBounds) {
    LabelMedium medium = layeredMedium();
    const MajorantGrid& maj = medium.majorants();
    // Brick x = 0 holds only the clear layer (sigma 0); brick 1 holds 0.5 and 5.
    EXPECT_EQ(maj.maxSigmaT({0, 0, 0}, 0), 0.0f);
    EXPECT_EQ(maj.maxSigmaT({1, 0, 0}, 0), 5.0f);
    EXPECT_EQ(maj.minSigmaT({1, 0, 0}, 0), 0.5f);
    EXPECT_EQ(maj.maxSigmaT({2, 3, 1}, 0), 1.5f);
    EXPECT_EQ(maj.minSigmaT({2, 3, 1}, 0), 1.5f);
    EXPECT_EQ(maj.globalMaxSigmaT(1), 10.0f);
}

}  // namespace
}  // namespace pl

namespace pl {
namespace {

// printpt's ball walk against the walk that delta tracking through the
// label grid takes in the same homogeneous material, stopped where its path
// first crosses the sphere: collisions, weight and exit state must have the
// same distribution (means within 4 combined standard errors), and the exit
// must lie on the sphere.
TEST(BallWalk, MatchesDeltaTrackingStoppedAtTheSphere) {
    const float sigma = 6.0f, albedo = 0.97f, g = 0.4f, radius = 0.9f;
    MaterialTable t;
    t.byLabel[4] = material({sigma, sigma, sigma}, {albedo, albedo, albedo}, {g, g, g});
    // Anisotropic voxels; the ball sits in the middle of a 3 mm block.
    LabelMedium medium(test::boxGrid({60, 30, 100}, {0.05f, 0.1f, 0.03f}, [](const Vec3i&) { return Label(4); }), t);
    LabelMedium::Tracker sampler(medium);
    const Point3f center{1.5f, 1.5f, 1.5f};
    const Vec3f w0 = normalize(Vec3f(0.3f, -0.5f, 0.8f));

    struct Moments {
        double n = 0, sum[4] = {0, 0, 0, 0}, sq[4] = {0, 0, 0, 0};
        void add(double collisions, double weight, double forward, double radialCos) {
            double v[4] = {collisions, weight, forward, radialCos};
            for (int i = 0; i < 4; ++i) sum[i] += v[i], sq[i] += v[i] * v[i];
            n += 1;
        }
        double mean(int i) const { return sum[i] / n; }
        double var(int i) const { return (sq[i] / n - mean(i) * mean(i)) / (n - 1); }
    } ball, tracked;
    const int kWalks = 20000;
    Rng rng(5, 1);
    for (int i = 0; i < kWalks; ++i) {
        float beta = 1.0f;
        BallWalk b = walkInBall(w0, radius, sigma, g, [&](float) { beta *= albedo; return true; }, rng);
        ASSERT_NEAR(length(b.exit), radius, 1e-4f);
        ball.add(double(b.collisions), beta, dot(b.exit, w0), dot(b.exit, b.direction) / radius);
    }
    for (int i = 0; i < kWalks; ++i) {
        // The same walk by delta tracking through the grid: follow each free
        // flight; the first one whose path leaves the ball ends it there.
        Point3f p = center;
        Vec3f w = w0;
        double beta = 1.0;
        int64_t collisions = 0;
        for (;;) {
            FreeFlight ff = sampler.sampleFreeFlight({p, w}, 10.0f, 0, rng);
            float tCollision = ff.scattered ? ff.t_mm : 1e30f;  // left the block: beyond the sphere
            Vec3f rel = p - center;
            float b = dot(rel, w), c = dot(rel, rel) - radius * radius;
            float s = -b + std::sqrt(std::max(0.0f, b * b - c));  // distance to the sphere
            if (tCollision >= s) {
                Vec3f exit = rel + w * s;
                tracked.add(double(collisions), beta, dot(exit, w0), dot(exit, w) / radius);
                break;
            }
            p = p + w * tCollision;
            collisions += 1;
            beta *= albedo;
            float u0 = rng.uniform(), u1 = rng.uniform();
            w = sampleHG(w, g, u0, u1).dOut;
        }
    }
    const char* names[4] = {"collisions", "weight", "forward displacement", "exit cosine"};
    for (int i = 0; i < 4; ++i) {
        double se = std::sqrt(ball.var(i) + tracked.var(i));
        EXPECT_GT(se, 0.0);
        EXPECT_NEAR(ball.mean(i), tracked.mean(i), 4.0 * se) << names[i];
    }
    EXPECT_GT(ball.mean(0), 5.0);  // the ball is many mean free paths wide
}

}  // namespace
}  // namespace pl
