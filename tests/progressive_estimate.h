// The progressive photon estimators' tests share this: a box's surface
// voxels in the middle of its faces (the kernel around a query there sees
// medium all round: nothing blurs across the face; at edges and corners it
// reaches past the object, where no photons are, a bias that shrinks with
// the radius), their mean over iterations with its error from the spread of
// the iterations' means (each iteration its own photons), and volpath's
// mean over the same voxels.
#pragma once

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "render/registry.h"
#include "render_estimate.h"
#include "test_util.h"

namespace pl::test {

// The boxes the photon estimators' tests render: 14 x 12 x 10 voxels,
// anisotropic on purpose.
inline const Vec3i kPhotonBoxResolution{14, 12, 10};
inline const Vec3f kPhotonBoxVoxel_mm{0.05f, 0.04f, 0.06f};

// One resin throughout.
inline Scene homogeneousPhotonBox(const Material& resin, float ior) {
    return boxScene(kPhotonBoxResolution, kPhotonBoxVoxel_mm, [](const Vec3i&) { return Label(1); },
                    tableOf({{1, resin}}), ior);
}
// No absorption: the white furnace.
inline Scene whiteFurnacePhotonBox(float ior) {
    return homogeneousPhotonBox(material({8, 12, 20}, {1, 1, 1}, {0, 0.3f, 0.6f}), ior);
}
// Absorbing, anisotropic and coloured.
inline Scene colouredPhotonBox(float ior) {
    return homogeneousPhotonBox(material({6, 12, 24}, {0.95f, 0.8f, 0.5f}, {0.2f, 0, 0.5f}), ior);
}
// A skin of one resin over a halftone of two denser ones at the voxel
// scale, IOR 1.5: light reaching a query comes through voxels of every label.
inline Scene halftonedPhotonBox() {
    auto labelOf = [](const Vec3i& v) {
        int depth = 1 << 30;
        for (int a = 0; a < 3; ++a) depth = std::min(depth, std::min(v[a], kPhotonBoxResolution[a] - 1 - v[a]));
        return Label(depth == 0 ? 1 : 2 + (v.x + 2 * v.y + 3 * v.z) % 2);
    };
    return boxScene(kPhotonBoxResolution, kPhotonBoxVoxel_mm, labelOf,
                    tableOf({{1, material({6, 12, 24}, {0.95f, 0.8f, 0.5f}, {0.2f, 0, 0.5f})},
                             {2, material({20, 8, 10}, {0.5f, 0.97f, 0.9f}, {0.4f, 0.4f, 0.4f})},
                             {3, material({30, 30, 30}, {0.9f, 0.6f, 0.3f})}}),
                    1.5f);
}
// Two resins in stripes, IOR 1.5 (the same-bits checks).
inline Scene stripedPhotonBox() {
    return boxScene(kPhotonBoxResolution, kPhotonBoxVoxel_mm,
                    [](const Vec3i& v) { return Label(1 + (v.x + v.y) % 2); },
                    tableOf({{1, material({10, 10, 10}, {0.9f, 0.7f, 0.5f})},
                             {2, material({20, 5, 10}, {0.6f, 0.9f, 0.8f})}}),
                    1.5f);
}

// Every surface voxel's value in every channel (the same-bits checks).
inline std::vector<float> surfaceValues(const Scene& scene, const RenderSettings& settings) {
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    const RenderResult r = render(scene, sensor, settings);
    std::vector<float> values;
    for (size_t p = 0; p < sensor.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) values.push_back(r.film.mean(p, c));
    return values;
}

// One coordinate on the box's side, the others at least three voxels from its edges.
inline bool inFaceMiddle(const Vec3i& v, const Vec3i& resolution) {
    int onSide = 0;
    bool farFromEdges = true;
    for (int a = 0; a < 3; ++a) {
        const bool side = v[a] == 0 || v[a] == resolution[a] - 1;
        onSide += side;
        if (!side) farFromEdges = farFromEdges && v[a] >= 3 && v[a] < resolution[a] - 3;
    }
    return onSide == 1 && farFromEdges;
}

struct IterationMeans {
    RenderResult result;
    Estimate faceMiddle;  // the mean over the face-middle voxels, from the iterations' spread
};

// `settings` (its integrator and options) run for `iterations` samples, one at a time.
inline IterationMeans renderIterations(const Scene& scene, const RenderSettings& settings, uint32_t iterations) {
    const LabelGrid& g = scene.medium->grid();
    const GridFrame& frame = g.frame();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    const auto integrator = makeIntegrator(scene, sensor, settings);
    IterationMeans out{RenderResult{Film(sensor.pixelCount())}, {}};
    std::vector<size_t> middle;
    for (size_t p = 0; p < sensor.pixelCount(); ++p)
        if (inFaceMiddle(sensor.pixels()[p].voxel - frame.indexMin, frame.resolution)) middle.push_back(p);
    EXPECT_GT(middle.size(), 100u);
    double previous[3] = {0, 0, 0}, sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0};
    for (uint32_t it = 0; it < iterations; ++it) {
        renderSamples(*integrator, scene, sensor, settings, {}, it, 1, out.result);
        for (int c = 0; c < 3; ++c) {
            double total = 0;
            for (size_t p : middle) total += double(out.result.film.mean(p, c)) * out.result.film.samples(p, c);
            const double iterationMean = (total - previous[c]) / double(middle.size());
            previous[c] = total;
            sum[c] += iterationMean;
            sumSq[c] += iterationMean * iterationMean;
        }
    }
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / iterations;
        const double variance = std::max(0.0, (sumSq[c] - iterations * mean * mean) / (iterations - 1.0));
        out.faceMiddle.mean[c] = float(mean);
        out.faceMiddle.standardError[c] = float(std::sqrt(variance / iterations));
    }
    return out;
}

// volpath's mean over the same voxels.
inline Estimate volpathFaceMiddle(const Scene& scene, uint32_t spp) {
    const LabelGrid& g = scene.medium->grid();
    const GridFrame& frame = g.frame();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    RenderSettings s;
    s.spp = spp;
    s.seed = 5;
    const RenderResult r = render(scene, sensor, s);
    Estimate e{};
    for (int c = 0; c < 3; ++c) {
        double sum = 0, var = 0;
        size_t n = 0;
        for (size_t p = 0; p < sensor.pixelCount(); ++p) {
            if (!inFaceMiddle(sensor.pixels()[p].voxel - frame.indexMin, frame.resolution)) continue;
            sum += r.film.mean(p, c);
            var += double(r.film.standardError(p, c)) * r.film.standardError(p, c);
            ++n;
        }
        e.mean[c] = float(sum / double(n));
        e.standardError[c] = float(std::sqrt(var) / double(n));
    }
    return e;
}

// Within 5 combined standard errors, per channel, and not dark.
inline void expectFaceMiddlesAgree(const Estimate& estimate, const Estimate& reference, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(estimate.mean[c], 0.02f) << what << ", channel " << c;
        EXPECT_NEAR(estimate.mean[c], reference.mean[c],
                    5.0 * std::hypot(estimate.standardError[c], reference.standardError[c]))
            << what << ", channel " << c;
    }
}

// No absorption: the light leaving is the environment's, L = Le, on the
// face middles within the iterations' error, at IOR 1 and 1.5.
inline void expectWhiteFurnace(RenderSettings settings, uint32_t iterations, uint64_t seed) {
    settings.seed = seed;
    for (float ior : {1.0f, 1.5f}) {
        Scene scene = whiteFurnacePhotonBox(ior);
        const IterationMeans r = renderIterations(scene, settings, iterations);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(r.faceMiddle.mean[c], 1.0, 5.0 * r.faceMiddle.standardError[c] + 1e-3)
                << settings.integrator << ", IOR " << ior << ", channel " << c;
    }
}

// The coloured box at IOR 1 and 1.5 against volpath over the face middles.
inline void expectAgreementOnHomogeneousBoxes(RenderSettings settings, uint32_t iterations, uint64_t seed) {
    settings.seed = seed;
    for (float ior : {1.0f, 1.5f}) {
        Scene scene = colouredPhotonBox(ior);
        expectFaceMiddlesAgree(renderIterations(scene, settings, iterations).faceMiddle, volpathFaceMiddle(scene, 256),
                               settings.integrator + ", IOR " + std::to_string(ior));
    }
}

// The striped box's surface voxels: the same bits with 1 and 4 threads.
inline void expectSameBitsWhateverTheThreads(RenderSettings settings) {
    const Scene scene = stripedPhotonBox();
    settings.spp = 3;
    std::vector<float> values[2];
    for (int run = 0; run < 2; ++run) {
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, run == 0 ? 1 : 4);
        values[run] = surfaceValues(scene, settings);
    }
    EXPECT_EQ(values[0], values[1]) << settings.integrator;
}

}  // namespace pl::test
