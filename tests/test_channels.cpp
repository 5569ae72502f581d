// Three channels from one path (hero channel + balance heuristic, spectral
// tracking) against what they must equal: Beer-Lambert per channel through
// one material and through voxel layers of two (mixed bricks: null
// collisions), and three single-channel passes on scattering scenes whose
// channel densities differ 4x (white resin 6, 9, 24 /mm), for volpath and
// printpt.
#include <gtest/gtest.h>

#include "render_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::Estimate;
using test::material;

const char* nameOf(ChannelSampling s) { return s == ChannelSampling::Hero ? "hero" : "spectral"; }

// Purely absorbing 4 x 4 x 0.5 mm slab at IOR 1, seen head-on through its
// middle: each channel's mean must be exp(-optical depth of that channel).
void expectBeerLambert(const std::function<Label(const Vec3i&)>& labelOf, const MaterialTable& table, RGB expected,
                       Majorants majorants = Majorants::PerBrick) {
    Scene scene = test::boxScene({40, 40, 10}, {0.1f, 0.1f, 0.05f}, labelOf, table, 1.0f);
    CameraPose pose{{2, 2, 5}, {2, 2, 0}, {0, 1, 0}};
    OrthographicSensor sensor(pose, 1.0f, 16, 16);
    for (const char* integrator : {"volpath", "printpt"})
        for (ChannelSampling sampling : {ChannelSampling::Hero, ChannelSampling::Spectral}) {
            RenderSettings s;
            s.integrator = integrator;
            s.spp = 192;
            s.channelSampling = sampling;
            s.majorants = majorants;
            s.parameters.set("branches", 1);
            Estimate e = test::renderMean(scene, sensor, s);
            for (int c = 0; c < 3; ++c) {
                EXPECT_GT(e.standardError[c], 0.0f);
                EXPECT_NEAR(e.mean[c], expected[c], 4.0f * e.standardError[c])
                    << integrator << " " << nameOf(sampling) << " channel " << c;
            }
        }
}

TEST(OnePassChannels, BeerLambertPerChannelThroughOneMaterial) {
    const RGB sigma{2, 4, 1};
    MaterialTable t = test::tableOf({{4, material(sigma, {0, 0, 0})}});
    RGB expected;
    for (int c = 0; c < 3; ++c) expected[c] = std::exp(-sigma[c] * 0.5f);
    expectBeerLambert([](const Vec3i&) { return Label(4); }, t, expected);
}

TEST(OnePassChannels, BeerLambertThroughLayersOfTwoMaterials) {
    // Layers one voxel thick alternate: every brick holds both, so the
    // trackers take null collisions, for the hero in some channels only.
    const RGB a{2, 4, 1}, b{6, 1, 3};
    MaterialTable t = test::tableOf({{0, material(a, {0, 0, 0})}, {1, material(b, {0, 0, 0})}});
    RGB expected;
    for (int c = 0; c < 3; ++c) expected[c] = std::exp(-(a[c] + b[c]) * 0.25f);
    expectBeerLambert([](const Vec3i& v) { return Label(v.z % 2); }, t, expected);
    // The textbook tracker (one majorant for the grid) through the same loop.
    expectBeerLambert([](const Vec3i& v) { return Label(v.z % 2); }, t, expected, Majorants::Global);
}

// Scattering scenes: one pass for three channels agrees with three passes.
void expectOnePassAgrees(const Scene& scene, const char* integrator, uint32_t spp, const std::string& what) {
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    RenderSettings s;
    s.integrator = integrator;
    s.spp = spp;
    s.seed = 7;
    s.channelSampling = ChannelSampling::Separate;
    Estimate separate = test::renderMean(scene, sensor, s);
    for (ChannelSampling sampling : {ChannelSampling::Hero, ChannelSampling::Spectral}) {
        s.channelSampling = sampling;
        s.seed = 8;
        test::expectAgreement(separate, test::renderMean(scene, sensor, s),
                              what + " " + integrator + " " + nameOf(sampling));
    }
}

TEST(OnePassChannels, AgreeWithThreeSingleChannelPassesInWhiteResin) {
    MaterialTable t = test::tableOf({{4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})}});
    Scene scene = test::boxScene({16, 12, 20}, {0.05f, 0.05f, 0.05f}, [](const Vec3i&) { return Label(4); }, t, 1.5f);
    for (const char* integrator : {"volpath", "printpt"}) expectOnePassAgrees(scene, integrator, 6, "white");
}

TEST(OnePassChannels, AgreeWithThreeSingleChannelPassesInMixedResins) {
    // Per-channel g differs in one material: phase-sampling ratios too.
    MaterialTable t = test::tableOf({{0, material({10, 8, 8}, {0.25f, 0.97f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                                     {1, material({2.5f, 10, 6}, {0.98f, 0.25f, 0.9f}, {0.2f, 0.5f, 0.7f})},
                                     {4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})},
                                     {6, material({1e-4f, 1e-4f, 1e-4f}, {1, 1, 1})}});
    Scene scene = test::boxScene({24, 16, 30}, {0.0423f, 0.0647f, 0.037f},
                                 [](const Vec3i& v) {
                                     static const Label palette[5] = {0, 1, 4, 4, 6};
                                     return palette[(v.x / 4 + 2 * (v.y / 3) + 3 * (v.z / 6)) % 5];
                                 },
                                 t, 1.5f);
    for (const char* integrator : {"volpath", "printpt"}) expectOnePassAgrees(scene, integrator, 6, "mixed");
}

}  // namespace
}  // namespace pl
