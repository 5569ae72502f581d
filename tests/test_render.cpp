// End-to-end estimator checks of volpath: white furnace, a purely absorbing
// slab against Beer-Lambert (with and without a Fresnel boundary), and
// bitwise determinism across thread counts.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/fresnel.h"
#include "integrators/printpt/half_space_walk.h"
#include "render/render.h"
#include "render_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

// Mixed densities, all albedo 1: a furnace must return the environment exactly.
Scene furnaceScene(float ior, RGB environment) {
    MaterialTable t = test::tableOf({{0, material({1, 2, 4}, {1, 1, 1}, {0.4f, 0.4f, 0.4f})},
                                     {4, material({6, 9, 24}, {1, 1, 1}, {0.4f, 0.4f, 0.4f})},
                                     {3, material({80, 150, 300}, {1, 1, 1}, {-0.5f, 0.0f, 0.9f})},
                                     {6, material({1e-6f, 1e-6f, 1e-6f}, {1, 1, 1})}});
    return test::boxScene({24, 12, 36}, kPrinterVoxel_mm,
                          [](const Vec3i& v) {
                              static const Label l[4] = {0, 4, 3, 6};
                              return l[(v.x / 3 + v.y / 2 + v.z / 5) % 4];
                          },
                          t, ior, environment);
}

void expectFurnace(const Scene& scene, const Sensor& sensor, bool reentry) {
    RenderSettings settings;
    settings.spp = 8;
    settings.reentry = reentry;
    settings.channelSampling = ChannelSampling::Separate;
    RenderResult r = render(scene, sensor, settings);
    for (size_t p = 0; p < sensor.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            // Every path ends in the environment with throughput exactly 1.
            ASSERT_FLOAT_EQ(r.film.mean(p, c), scene.environment[c]) << "pixel " << p << " channel " << c;
            ASSERT_EQ(r.film.standardError(p, c), 0.0f);
        }
    EXPECT_GT(r.stats.scatterEvents, r.stats.paths);  // light really scattered
    // One path for three channels whose densities differ: single paths
    // carry channel weights other than 1, the mean must still be exact.
    for (ChannelSampling sampling : {ChannelSampling::Hero, ChannelSampling::Spectral}) {
        settings.channelSampling = sampling;
        test::Estimate e = test::renderMean(scene, sensor, settings);
        for (int c = 0; c < 3; ++c) {
            EXPECT_GT(e.standardError[c], 0.0f);
            EXPECT_NEAR(e.mean[c], scene.environment[c], 4.0f * e.standardError[c])
                << (sampling == ChannelSampling::Hero ? "hero" : "spectral") << " channel " << c;
        }
    }
}

TEST(WhiteFurnace, IndexMatchedSurfaceVoxels) {
    Scene scene = furnaceScene(1.0f, {0.3f, 1.0f, 2.5f});
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    expectFurnace(scene, sensor, false);
}

TEST(WhiteFurnace, DielectricWithReentryFromAPerspectiveCamera) {
    Scene scene = furnaceScene(1.5f, {1, 1, 1});
    CameraPose pose{{3, -2, 2.5f}, {0.5f, 0.5f, 0.5f}, {0, 0, 1}};
    PerspectiveSensor sensor(pose, 30.0f, 24, 18);
    expectFurnace(scene, sensor, true);
}

TEST(WhiteFurnace, StrongTotalInternalReflectionLosesNothing) {
    Scene scene = furnaceScene(2.5f, {1, 1, 1});
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    expectFurnace(scene, sensor, false);
}

// Purely absorbing slab seen head-on through its middle: every path either
// crosses without a collision or is absorbed, so L is a Bernoulli mean.
struct SlabResult {
    double mean, standardError;
};
SlabResult renderSlab(float ior, float sigma, int channel) {
    const Vec3f voxel{0.1f, 0.1f, 0.05f};
    MaterialTable t = test::tableOf({{4, material({sigma, 2 * sigma, 0.5f * sigma}, {0, 0, 0})}});
    Scene scene = test::boxScene({40, 40, 10}, voxel, [](const Vec3i&) { return Label(4); }, t, ior);
    // Orthographic view along -z onto the middle 1 x 1 mm of a 4 x 4 x 0.5 mm slab.
    CameraPose pose{{2, 2, 5}, {2, 2, 0}, {0, 1, 0}};
    OrthographicSensor sensor(pose, 1.0f, 16, 16);
    RenderSettings settings;
    settings.spp = 256;
    settings.channels = {channel};
    RenderResult r = render(scene, sensor, settings);
    double sum = 0, sumSq = 0;
    size_t n = sensor.pixelCount();
    for (size_t p = 0; p < n; ++p) {
        sum += r.film.mean(p, channel);
        sumSq += double(r.film.standardError(p, channel)) * r.film.standardError(p, channel);
    }
    return {sum / n, std::sqrt(sumSq) / n};
}

TEST(AbsorbingSlab, BeerLambertWithIndexMatchedBoundary) {
    const float sigma = 2.0f, d = 0.5f;
    for (int c = 0; c < 3; ++c) {
        float s = c == 0 ? sigma : (c == 1 ? 2 * sigma : 0.5f * sigma);
        SlabResult r = renderSlab(1.0f, sigma, c);
        double expected = std::exp(-s * d);
        EXPECT_NEAR(r.mean, expected, 4.0 * r.standardError) << "channel " << c;
        EXPECT_GT(r.standardError, 0.0);
    }
}

TEST(AbsorbingSlab, BeerLambertBehindFresnelBoundary) {
    // Normal incidence: L = R + (1-R)^2 T / (1 - R T), with R = ((n-1)/(n+1))^2
    // (reflections inside bounce back and forth along the normal).
    const float sigma = 2.0f, d = 0.5f;
    for (float n : {1.5f, 2.5f}) {
        double R = std::pow((n - 1) / (n + 1), 2), T = std::exp(-sigma * d);
        double expected = R + (1 - R) * (1 - R) * T / (1 - R * T);
        SlabResult r = renderSlab(n, sigma, 0);
        EXPECT_NEAR(r.mean, expected, 4.0 * r.standardError) << "ior " << n;
        // At n = 2.5 the boundary matters far beyond the noise.
        if (n == 2.5f) {
            EXPECT_GT(std::abs(r.mean - T), 10.0 * r.standardError);
        }
    }
}

// Samples whose randomness hides in rare events (printpt's control
// residuals) pool their residuals' second moment per key: a pixel whose own
// samples all came out equal still gets the error its key's samples show,
// shrunk with the pixel's own spread where it has one, and the shared
// error on top.
TEST(Film, PoolsResidualsPerKeyAndAddsSharedErrors) {
    Film f(3);
    for (int s = 0; s < 4; ++s) {
        f.add(0, 0, ChannelSample{0.5f, 0.0f, 7, 0.0f});  // never met a rare event
        f.add(1, 0, ChannelSample{s == 0 ? 2.5f : 0.5f, 0.0f, 7, s == 0 ? 2.0f : 0.0f});
        f.add(2, 0, ChannelSample{0.5f, 0.001f, 9, 0.0f});
    }
    f.poolErrors();
    EXPECT_EQ(f.spreadError(0, 0), 0.0f);
    // Key 7: 8 samples, residuals squared summing to 4: 0.5 per sample, a
    // bound that controlled samples report at least. Pixel 0's window
    // (itself) is flat: the key's 0.5 with the window's weight and its own
    // 0 with 3 degrees of freedom, less than the bound.
    EXPECT_FLOAT_EQ(f.standardError(0, 0), std::sqrt(0.5f / 4));
    // Pixel 1's own residuals (2, 0, 0, 0): variance 1 per sample, its own
    // window: all its weight, more than the bound.
    EXPECT_NEAR(f.standardError(1, 0), std::sqrt(1.0 / 4), 1e-6);
    // Key 9 met no event: only the shared error.
    EXPECT_FLOAT_EQ(f.standardError(2, 0), 0.001f);
}

// A sample's bias estimate: the pixel's shared error adds the bias their
// mean shows beyond its own noise, sqrt(mean^2 - variance of the mean).
TEST(Film, AddsTheBiasItsSamplesShowBeyondTheirNoise) {
    Film f(3);
    const float noisy[] = {0.3f, -0.1f, 0.2f, -0.4f};  // mean 0, variance of the mean 0.025
    for (int s = 0; s < 4; ++s) {
        ChannelSample steady{0.5f}, spread{0.5f}, shifted{0.5f};
        steady.bias = 0.1f;
        spread.bias = noisy[s];
        shifted.bias = 1.0f + noisy[s];
        f.add(0, 0, steady);
        f.add(1, 0, spread);
        f.add(2, 0, shifted);
    }
    f.poolErrors();
    EXPECT_NEAR(f.sharedError(0, 0), 0.1f, 1e-6);
    EXPECT_EQ(f.sharedError(1, 0), 0.0f);  // no bias beyond the noise
    EXPECT_NEAR(f.sharedError(2, 0), std::sqrt(1.0 - 0.025), 1e-6);
    EXPECT_NEAR(f.standardError(2, 0), f.sharedError(2, 0), 1e-6);  // the values themselves are all equal
}

// A pixel's variance is shrunk towards its neighbours' in the sensor's
// image: one sample of its own says nothing, its neighbours' do.
TEST(Film, OneSampleTakesItsNeighboursVariance) {
    MaterialTable t = test::tableOf({{0, material({10, 10, 10}, {0.9f, 0.9f, 0.9f})}});
    Scene scene = test::boxScene({8, 8, 8}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(0); }, t, 1.0f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    Film f(sensor.pixelCount());
    // Samples of no key, 0 or 1 by a coin per pixel: a variance near 0.25
    // in every window, whatever a pixel's own value.
    for (size_t p = 0; p < sensor.pixelCount(); ++p) f.add(p, 0, float(mix64(p) % 2));
    EXPECT_EQ(f.standardError(0, 0), 0.0f);  // before pooling: one sample, no spread
    f.poolErrors(&sensor);
    for (size_t p = 0; p < sensor.pixelCount(); ++p) {
        EXPECT_GT(f.standardError(p, 0), 0.3f) << p;
        EXPECT_LT(f.standardError(p, 0), 0.6f) << p;
    }
}

TEST(Film, GroupsOfStratifiedSamplesAreTheUnitsOfTheVariance) {
    Film f(3);
    for (float v : {1.0f, 2.0f, 3.0f, 4.0f}) f.add(0, 0, v);
    EXPECT_FLOAT_EQ(f.mean(0, 0), 2.5f);
    EXPECT_NEAR(f.standardError(0, 0), std::sqrt((5.0 / 3.0) / 4.0), 1e-6);  // sample variance / n
    // Two groups of three whose samples differ but whose means agree: no error.
    f.addGroup(1, 0, 0.0 + 0.0 + 3.0, 3);
    f.addGroup(1, 0, 3.0 + 0.0 + 0.0, 3);
    EXPECT_FLOAT_EQ(f.mean(1, 0), 1.0f);
    EXPECT_EQ(f.samples(1, 0), 6u);
    EXPECT_EQ(f.standardError(1, 0), 0.0f);
    // Group means 1 and 2: the variance of a group mean is 0.5, over two groups.
    f.addGroup(2, 0, 3.0, 3);
    EXPECT_EQ(f.standardError(2, 0), 0.0f);  // one unit: no estimate yet
    f.addGroup(2, 0, 6.0, 3);
    EXPECT_NEAR(f.standardError(2, 0), std::sqrt(0.5 / 2.0), 1e-6);
}

TEST(Determinism, BitIdenticalForOneAndTwoThreads) {
    MaterialTable t = test::tableOf({{0, material({10, 8, 8}, {0.25f, 0.97f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                                     {1, material({2.5f, 10, 6}, {0.98f, 0.25f, 0.9f}, {0.4f, 0.4f, 0.4f})},
                                     {4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})}});
    Scene scene = test::boxScene({30, 15, 40}, kPrinterVoxel_mm,
                                 [](const Vec3i& v) { return Label((v.x * 7 + v.y * 3 + v.z) % 3 == 0 ? 4 : (v.x + v.z) % 2); },
                                 t, 1.5f);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    RenderSettings settings;
    settings.spp = 3;
    settings.seed = 1234;
    auto renderWith = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return render(scene, sensor, settings);
    };
    for (ChannelSampling sampling : {ChannelSampling::Separate, ChannelSampling::Hero, ChannelSampling::Spectral}) {
        settings.channelSampling = sampling;
        settings.seed = 1234;
        RenderResult a = renderWith(1), b = renderWith(2);
        ASSERT_EQ(a.film.pixelCount(), b.film.pixelCount());
        for (size_t p = 0; p < a.film.pixelCount(); ++p)
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(a.film.mean(p, c), b.film.mean(p, c));
                ASSERT_EQ(a.film.standardError(p, c), b.film.standardError(p, c));
            }
        EXPECT_EQ(a.stats.scatterEvents, b.stats.scatterEvents);
        // A different seed gives a different image.
        settings.seed = 1235;
        RenderResult c = renderWith(2);
        bool differs = false;
        for (size_t p = 0; p < a.film.pixelCount() && !differs; ++p) differs = a.film.mean(p, 0) != c.film.mean(p, 0);
        EXPECT_TRUE(differs) << int(sampling);
    }
    // printpt's control variate (its walks share numbers with a half-space walk).
    settings.channelSampling = ChannelSampling::Separate;
    settings.integrator = "printpt";
    settings.parameters.set("control_variate", 1);
    settings.parameters.set("control_walks", 4096);
    settings.seed = 1234;
    RenderResult a = renderWith(1), b = renderWith(2);
    for (size_t p = 0; p < a.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a.film.mean(p, c), b.film.mean(p, c));
}

TEST(Determinism, HalfSpaceMeanIsTheSameForAnyThreadCount) {
    HalfSpace hs{{0, 0, 0}, {0, 0, 1}, 9.0f, 0.995f, 0.4f, 1.0f / 1.5f};
    auto estimate = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return estimateHalfSpaceMean(hs, {0.25f, 1.0f}, 1.0f, 20000, 7);
    };
    HalfSpaceMean a = estimate(1), b = estimate(2);
    EXPECT_EQ(a.mean, b.mean);
    EXPECT_EQ(a.standardError, b.standardError);
    EXPECT_GT(a.standardError, 0.0);
}

// The half-space walk against Chandrasekhar: with no boundary reflection and
// isotropic scattering of albedo w, a half-space sends back 1 - H(1) sqrt(1 - w)
// of normally incident light (H: Chandrasekhar's H-function, solved here by
// iterating H(mu) = 1 / (1 - w/2 mu int_0^1 H(m) / (mu + m) dm)).
TEST(HalfSpaceWalk, MatchesChandrasekharsAlbedo) {
    const double w = 0.9;
    const int n = 400;
    std::vector<double> mu(n), H(n, 1.0);
    for (int i = 0; i < n; ++i) mu[i] = (i + 0.5) / n;
    auto integralAt = [&](double m) {
        double s = 0;
        for (int j = 0; j < n; ++j) s += H[j] / (m + mu[j]);
        return s / n;
    };
    for (int iter = 0; iter < 100; ++iter)
        for (int i = 0; i < n; ++i) H[i] = 1.0 / (1.0 - 0.5 * w * mu[i] * integralAt(mu[i]));
    const double expected = 1.0 - std::sqrt(1.0 - w) / (1.0 - 0.5 * w * integralAt(1.0));
    HalfSpace hs{{0, 0, 0}, {0, 0, 1}, 2.0f, float(w), 0.0f, 1.0f};
    HalfSpaceMean m = estimateHalfSpaceMean(hs, {1.0f, 1.0f}, 1.0f, 200000, 3);
    EXPECT_NEAR(m.mean, expected, 4.0 * m.standardError + 2e-3) << "stderr " << m.standardError;
}

// printpt estimates the control's mean once at sigma_t = 1 for every
// material of the same albedo and g: sigma_t must only scale the walk.
TEST(HalfSpaceWalk, MeanDoesNotDependOnSigmaT) {
    const RouletteRule roulette{0.25f, 1.0f};
    HalfSpace unit{{0, 0, 0}, {0, 0, 1}, 1.0f, 0.98f, 0.4f, 1.0f / 1.5f};
    HalfSpace dense = unit;
    dense.sigmaT_perMm = 24.0f;
    HalfSpaceMean a = estimateHalfSpaceMean(unit, roulette, 1.0f, 100000, 5);
    HalfSpaceMean b = estimateHalfSpaceMean(dense, roulette, 1.0f, 100000, 6);
    const double combined = std::hypot(a.standardError, b.standardError);
    EXPECT_NEAR(a.mean, b.mean, 4.0 * combined) << "stderr " << combined;
    // A different albedo is told apart at this sample count.
    HalfSpace darker = unit;
    darker.albedo = 0.9f;
    EXPECT_GT(a.mean - estimateHalfSpaceMean(darker, roulette, 1.0f, 100000, 7).mean, 8.0 * combined);
}

// Near an edge printpt's control is a wedge: the half-space cut by a side
// plane at right angles. A flight that reaches the side plane first leaves
// through it (1 - F) and is reflected there.
TEST(HalfSpaceWalk, WedgeFlightsLeaveThroughTheSideFace) {
    HalfSpace wedge{{0, 0, 0}, {0, 0, 1}, 1.0f, 0.9f, 0.0f, 1.0f / 1.5f};
    wedge.hasSide = true;
    wedge.sideOrigin = {1, 0, 0};
    wedge.sideNormal = {1, 0, 0};
    HalfSpaceWalker w{{0.5f, 0, -2}, {1, 0, 0}, 1.0f};
    EXPECT_FLOAT_EQ(wedge.depth(w.x), 0.5f);
    float light = 0.0f;
    EXPECT_FALSE(halfSpaceFlight(wedge, w, 10.0f, light));
    const float F = fresnelDielectric(1.0f, 1.0f / 1.5f);
    EXPECT_FLOAT_EQ(light, 1.0f - F);
    EXPECT_FLOAT_EQ(w.weight, F);
    EXPECT_NEAR(w.x.x, 1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(w.d.x, -1.0f);
    // Short of the plane it collides.
    HalfSpaceWalker v{{0.5f, 0, -2}, {1, 0, 0}, 1.0f};
    EXPECT_TRUE(halfSpaceFlight(wedge, v, 0.25f, light));
    EXPECT_FLOAT_EQ(v.x.x, 0.75f);
    EXPECT_FLOAT_EQ(v.weight, 0.9f);
}

// The wedge's mean is tabulated in mean free paths at sigma_t = 1 (the
// edge's distance scales with the walk); far from the edge it is the
// half-space's, close to it more light gets out.
TEST(HalfSpaceWalk, WedgeMeanScalesAndMeetsTheHalfSpaceFarFromTheEdge) {
    const RouletteRule roulette{0.25f, 1.0f};
    auto wedgeAt = [](float sigmaT, float edge_mfp) {
        HalfSpace w{{0, 0, 0}, {0, 0, 1}, sigmaT, 0.95f, 0.4f, 1.0f / 1.5f};
        w.hasSide = true;
        w.sideNormal = {1, 0, 0};
        w.sideOrigin = {edge_mfp / sigmaT, 0, 0};
        return w;
    };
    HalfSpaceMean unit = estimateHalfSpaceMean(wedgeAt(1.0f, 2.0f), roulette, 1.0f, 100000, 5);
    HalfSpaceMean dense = estimateHalfSpaceMean(wedgeAt(24.0f, 2.0f), roulette, 1.0f, 100000, 6);
    double combined = std::hypot(unit.standardError, dense.standardError);
    EXPECT_NEAR(unit.mean, dense.mean, 4.0 * combined) << "stderr " << combined;

    HalfSpace half = wedgeAt(1.0f, 0.0f);
    half.hasSide = false;
    HalfSpaceMean plane = estimateHalfSpaceMean(half, roulette, 1.0f, 100000, 7);
    HalfSpaceMean far = estimateHalfSpaceMean(wedgeAt(1.0f, 60.0f), roulette, 1.0f, 100000, 8);
    combined = std::hypot(plane.standardError, far.standardError);
    EXPECT_NEAR(far.mean, plane.mean, 4.0 * combined) << "stderr " << combined;
    EXPECT_GT(unit.mean - plane.mean, 8.0 * std::hypot(unit.standardError, plane.standardError));
}

// Under a curved surface the control is the region below a paraboloid. A
// flight leaves where the paraboloid is, with its normal there; depth() is
// a lower bound of the distance to it (no point of the ball it promises
// lies outside); the mean, in mean free paths, scales with sigma_t (the
// curvatures scale too), and a curved region lets out more light than the
// half-space (less room to wander off).
TEST(HalfSpaceWalk, CurvedRegionExitsDepthAndMean) {
    HalfSpace curved{{0, 0, 0}, {0, 0, 1}, 1.0f, 0.95f, 0.4f, 1.0f / 1.5f};
    curved.curved = true;
    curved.axisS = normalize(Vec3f(1, 1, 0));
    curved.axisT = normalize(Vec3f(-1, 1, 0));
    curved.kappaS_perMm = 0.5f;
    curved.kappaT_perMm = 0.1f;
    auto outside = [&](const Point3f& p) {
        const float u = dot(p - curved.origin, curved.axisS), v = dot(p - curved.origin, curved.axisT);
        return dot(p - curved.origin, curved.normal) + 0.5f * (0.5f * u * u + 0.1f * v * v);
    };
    Rng rng(3, 1);
    auto anyDirection = [&] { return sampleHG({0, 0, 1}, 0.0f, rng.uniform(), rng.uniform()).dOut; };
    for (int i = 0; i < 2000; ++i) {
        const Point3f x{4.0f * (rng.uniform() - 0.5f), 4.0f * (rng.uniform() - 0.5f), -3.0f * rng.uniform() - 0.01f};
        if (outside(x) >= 0.0f) continue;
        const Vec3f d = anyDirection();
        if (auto exit = curved.exit(x, d)) {
            const float t = exit->t_mm;
            const Vec3f n = exit->outward;
            const Point3f e = x + d * t;
            EXPECT_NEAR(outside(e), 0.0f, 1e-4f * (1.0f + t)) << i;
            // The normal is the paraboloid's gradient, outward.
            const float u = dot(e, curved.axisS), v = dot(e, curved.axisT);
            const Vec3f gradient = normalize(curved.normal + curved.axisS * (0.5f * u) + curved.axisT * (0.1f * v));
            EXPECT_GT(dot(n, gradient), 0.9999f) << i;
            EXPECT_GE(dot(d, n), -1e-4f) << i;
        }
        // No point of the ball depth(x) promises is outside.
        const float r = curved.depth(x);
        EXPECT_GE(r, 0.0f);
        for (int j = 0; j < 8; ++j)
            EXPECT_LT(outside(x + anyDirection() * r), 1e-5f) << i;
    }
    const RouletteRule roulette{0.25f, 1.0f};
    HalfSpace dense = curved;
    dense.sigmaT_perMm = 24.0f;
    dense.kappaS_perMm *= 24.0f;
    dense.kappaT_perMm *= 24.0f;
    HalfSpaceMean unit = estimateHalfSpaceMean(curved, roulette, 1.0f, 100000, 5);
    HalfSpaceMean scaled = estimateHalfSpaceMean(dense, roulette, 1.0f, 100000, 6);
    double combined = std::hypot(unit.standardError, scaled.standardError);
    EXPECT_NEAR(unit.mean, scaled.mean, 4.0 * combined) << "stderr " << combined;
    HalfSpace flat = curved;
    flat.curved = false;
    HalfSpaceMean plane = estimateHalfSpaceMean(flat, roulette, 1.0f, 100000, 7);
    EXPECT_GT(unit.mean - plane.mean, 8.0 * std::hypot(unit.standardError, plane.standardError));
}

}  // namespace
}  // namespace pl
