// writeScene is parseScene's inverse (render/scene_io.h): scenes written
// elsewhere read back the same, key by key, the bundled ones and one with
// every key away from its default.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <type_traits>

#include "render/registry.h"
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
    EXPECT_EQ(ra.parameters.numbers(), rb.parameters.numbers());
    EXPECT_EQ(ra.parameters.texts().size(), rb.parameters.texts().size());
    for (const auto& [key, text] : ra.parameters.texts()) {
        ASSERT_TRUE(rb.parameters.text(key)) << key;
        EXPECT_EQ(absoluteOf(text), absoluteOf(*rb.parameters.text(key))) << key;  // paths from elsewhere
    }
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
    d.render.channels = {1};
    d.render.channelSampling = ChannelSampling::Spectral;
    d.render.majorants = Majorants::Global;
    // Every table option at a value of its range other than its default.
    for (const auto& p : renderParameters()) {
        const double now = optionValue(p, d.render);
        using Kind = std::decay_t<decltype(p)>::Kind;
        const double middle = p.kind() == Kind::Integer ? std::floor((p.min + p.max) / 2) : (p.min + p.max) / 2;
        const double other = p.kind() == Kind::Boolean ? 1 - now : now != p.max ? p.max : middle;
        ASSERT_EQ(setOption(p, d.render, other), "") << p.name;
    }
    d.output = "out/elsewhere";
    const SceneDescription surface = parseScene(test::sourceDir() / "data/scenes/cube10_greek_surface.json");
    // Each estimator with every key of its own away from its default (on
    // a sensor it takes; re-entry for volpath alone).
    for (const IntegratorKind& kind : integratorKinds()) {
        SceneDescription e = d;
        if (!(kind.factory.capabilities(RenderSettings{}).sensors & kCameraSensor)) e.sensor = surface.sensor;
        e.render.integrator = kind.name;
        e.render.reentry = e.render.integrator == "volpath";
        e.render.channelSampling = ChannelSampling::Separate;
        for (const ParameterInfo& p : kind.factory.parameters()) {
            using Kind = ParameterInfo::Kind;
            if (p.kind == Kind::Boolean) e.render.parameters.set(p.name, 0);  // every switch is on by default but nee
            if (p.kind == Kind::Integer) e.render.parameters.set(p.name, std::floor((p.min + p.max) / 2));
            if (p.kind == Kind::Number) e.render.parameters.set(p.name, p.max);
            if (p.kind == Kind::Name) e.render.parameters.setText(p.name, p.names.front());
            if (p.kind == Kind::Path)  // the bundled model, named from elsewhere
                e.render.parameters.setText(p.name,
                                            (test::sourceDir() / "data/materials/resins_illustrative.learned.json").string());
        }
        if (!refusalOf(e.render).empty()) {
            ADD_FAILURE() << kind.name << ": " << refusalOf(e.render);
            continue;
        }
        const std::filesystem::path file = dir / "every_key" / (std::string(kind.name) + ".json");
        writeScene(e, file);
        expectSameScene(e, parseScene(file));
    }
}

}  // namespace
}  // namespace pl
