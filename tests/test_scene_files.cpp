// writeScene is parseScene's inverse (render/scene_io.h): scenes written
// elsewhere read back the same, key by key, the bundled ones and one with
// every key away from its default.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <type_traits>

#include "integrators/lighttrace/lighttrace.h"
#include "integrators/printpt/printpt_options.h"
#include "integrators/volpath/volpath.h"
#include "render/scene_io.h"
#include "test_util.h"

namespace pl {
namespace {

template <class Options>
void expectSameOptions(const std::vector<OptionParameter<Options>>& table, const Options& a, const Options& b) {
    for (const OptionParameter<Options>& p : table) EXPECT_EQ(optionValue(p, a), optionValue(p, b)) << p.name;
}

std::filesystem::path absoluteOf(const std::filesystem::path& p) { return std::filesystem::absolute(p).lexically_normal(); }

void expectSameScene(const SceneDescription& a, const SceneDescription& b) {
    EXPECT_EQ(absoluteOf(a.meshFile), absoluteOf(b.meshFile));
    EXPECT_EQ(absoluteOf(a.labelsFile), absoluteOf(b.labelsFile));
    EXPECT_EQ(absoluteOf(a.materialsFile), absoluteOf(b.materialsFile));
    EXPECT_EQ(a.meshPlacement.unit, b.meshPlacement.unit);
    EXPECT_EQ(a.meshPlacement.scale, b.meshPlacement.scale);
    EXPECT_EQ(a.meshRepair, b.meshRepair);
    EXPECT_EQ(a.voidLabel, b.voidLabel);
    EXPECT_EQ(a.ior, b.ior);
    EXPECT_EQ(a.homogeneousCoreDepth_mm, b.homogeneousCoreDepth_mm);
    EXPECT_EQ(a.environment, b.environment);
    const SensorDescription &sa = a.sensor, &sb = b.sensor;
    EXPECT_EQ(sa.type, sb.type);
    EXPECT_EQ(sa.footprint, sb.footprint);
    if (sa.type != "surface_voxels") {
        for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(sa.pose.position_mm[i], sb.pose.position_mm[i]);
            EXPECT_EQ(sa.pose.lookAt_mm[i], sb.pose.lookAt_mm[i]);
            EXPECT_EQ(sa.pose.up[i], sb.pose.up[i]);
        }
        EXPECT_EQ(sa.fovY_deg, sb.fovY_deg);
        EXPECT_EQ(sa.viewWidth_mm, sb.viewWidth_mm);
        EXPECT_EQ(sa.width, sb.width);
        EXPECT_EQ(sa.height, sb.height);
    }
    const RenderSettings &ra = a.render, &rb = b.render;
    EXPECT_EQ(ra.integrator, rb.integrator);
    expectSameOptions(renderParameters(), ra, rb);
    EXPECT_EQ(ra.channels, rb.channels);
    EXPECT_EQ(ra.channelSampling, rb.channelSampling);
    EXPECT_EQ(ra.majorants, rb.majorants);
    EXPECT_EQ(ra.lighttrace.scoring, rb.lighttrace.scoring);
    EXPECT_EQ(absoluteOf(ra.learnedModel), absoluteOf(rb.learnedModel));
    expectSameOptions(volPathParameters(), ra.volpath, rb.volpath);
    expectSameOptions(lightTraceParameters(), ra.lighttrace, rb.lighttrace);
    expectSameOptions(printPtParameters(), ra.printpt, rb.printpt);
    expectSameOptions(breParameters(), ra.bre, rb.bre);
    expectSameOptions(beamParameters(), ra.beams, rb.beams);
    EXPECT_EQ(a.output, b.output);
}

// writeScene is parseScene's inverse: the bundled scenes, and one with every
// key away from its default, written elsewhere and read back.
TEST(SceneFiles, WrittenScenesReadBackTheSame) {
    const std::filesystem::path dir = test::freshTempDir("scene_files");
    for (const char* name : {"cube10_greek_surface", "cube10_greek_preview", "cube10_white_preview"}) {
        const SceneDescription bundled = parseScene(test::sourceDir() / "data/scenes" / (std::string(name) + ".json"));
        writeScene(bundled, dir / "sub" / (std::string(name) + ".json"));
        expectSameScene(bundled, parseScene(dir / "sub" / (std::string(name) + ".json")));
    }
    SceneDescription d = parseScene(test::sourceDir() / "data/scenes/cube10_greek_preview.json");
    d.meshPlacement = {LengthUnit::Inch, 0.25};
    d.meshRepair = true;
    d.voidLabel = Label(0);
    d.ior = 1.4f;
    d.homogeneousCoreDepth_mm = 0.7f;
    d.environment = {0.25f, 0.5f, 2.0f};
    d.sensor.type = "orthographic";
    d.sensor.viewWidth_mm = 12.5f;
    d.render.integrator = "volpath";
    d.render.channels = {1};
    d.render.channelSampling = ChannelSampling::Spectral;
    d.render.majorants = Majorants::Global;
    d.render.lighttrace.scoring = LightTraceOptions::Scoring::Collisions;
    d.render.learnedModel = dir / "models" / "elsewhere.learned.json";
    // Every table option at a value of its range other than its default.
    auto moveAll = [](const auto& table, auto& options) {
        for (const auto& p : table) {
            const double now = optionValue(p, options);
            using Kind = typename std::decay_t<decltype(p)>::Kind;
            const double middle = p.kind() == Kind::Integer ? std::floor((p.min + p.max) / 2) : (p.min + p.max) / 2;
            const double other = p.kind() == Kind::Boolean ? 1 - now : now != p.max ? p.max : middle;
            ASSERT_EQ(setOption(p, options, other), "") << p.name;
        }
    };
    moveAll(renderParameters(), d.render);
    moveAll(volPathParameters(), d.render.volpath);
    moveAll(lightTraceParameters(), d.render.lighttrace);
    moveAll(printPtParameters(), d.render.printpt);
    moveAll(breParameters(), d.render.bre);
    moveAll(beamParameters(), d.render.beams);
    d.output = "out/elsewhere";
    writeScene(d, dir / "every_key.json");
    expectSameScene(d, parseScene(dir / "every_key.json"));
}

}  // namespace
}  // namespace pl
