// The example estimator (surface_reflection.h) added as any estimator is:
// its folder and one registry line, no file of the library touched. Its
// key reaches it from a scene file, is checked and written back by the
// library's own code, and rendered through the driver it gives the closed
// form of a dielectric's mirror reflection.
#include <gtest/gtest.h>

#include <fstream>

#include "core/input_error.h"
#include "render/registry.h"
#include "render/render.h"
#include "render/scene_io.h"
#include "surface_reflection.h"
#include "test_util.h"

namespace pl {
namespace {

// The registry line (built-in estimators have theirs in render/registry.cpp).
void registerExample() {
    static const bool registered = [] {
        registerIntegrator({"surface_reflection", factoryOf<test::SurfaceReflection>()});
        return true;
    }();
    (void)registered;
}

// A scene file that names the example with these render keys (parseScene
// reads no other file, so the object's files need not exist).
std::filesystem::path exampleScene(const std::string& name, const std::string& renderKeys) {
    const std::filesystem::path file = test::freshTempDir("example_estimator") / (name + ".json");
    std::ofstream(file) << R"({"object": {"mesh": "box.obj", "labels": "box.vdb", "materials": "m.json"},
      "sensor": {"type": "surface_voxels"},
      "render": {"integrator": "surface_reflection", "spp": 1)"
                        << renderKeys << "}}";
    return file;
}

TEST(ExampleEstimator, IsFoundByNameWithWhatItDeclares) {
    registerExample();
    EXPECT_NE(integratorNames().find("surface_reflection"), std::string::npos) << integratorNames();
    RenderSettings s;
    s.integrator = "surface_reflection";
    EXPECT_TRUE(capabilitiesOf(s).deterministic);
    EXPECT_EQ(refusalOf(s), "");  // inherited: it refuses nothing
    EXPECT_THROW(registerIntegrator({"surface_reflection", factoryOf<test::SurfaceReflection>()}),
                 std::invalid_argument);
}

// Along each surface voxel's normal (normal incidence on the box's faces)
// the mirrored light is ((n - 1) / (n + 1))^2 of the environment; one
// sample, exact, whatever spp asks.
TEST(ExampleEstimator, RendersTheNormalIncidenceReflectanceThroughTheDriver) {
    registerExample();
    const float ior = 1.5f;
    const RGB environment{0.5f, 1.0f, 2.0f};
    Scene scene = test::boxScene({6, 5, 4}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(1); },
                                 test::tableOf({{1, test::material({10, 10, 10}, {0.9f, 0.9f, 0.9f})}}), ior,
                                 environment);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    for (ChannelSampling sampling : {ChannelSampling::Separate, ChannelSampling::Hero}) {
        RenderSettings s;
        s.integrator = "surface_reflection";
        s.spp = 8;
        s.channelSampling = sampling;
        const RenderResult r = render(scene, sensor, s);
        const double reflectance = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
        ASSERT_EQ(r.film.pixelCount(), sensor.pixelCount());
        for (size_t p = 0; p < sensor.pixelCount(); ++p)
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(r.film.mean(p, c), reflectance * environment[size_t(c)], 1e-6 * environment[size_t(c)])
                    << "pixel " << p << " channel " << c;
                EXPECT_EQ(r.film.standardError(p, c), 0.0);
            }
        const uint64_t passes = sampling == ChannelSampling::Separate ? 3 : 1;
        EXPECT_EQ(r.stats.paths, passes * sensor.pixelCount()) << "one sample per pixel and pass";
    }
}

// Its key reaches it from the scene file: at 45 degrees on the box's top
// face Schlick's approximation, 0.04 + 0.96 (1 - cos)^5 for n = 1.5, is
// 16 % below the exact factor.
TEST(ExampleEstimator, ItsKeyReachesItFromTheSceneFile) {
    registerExample();
    const RGB environment{1, 1, 1};
    Scene scene = test::boxScene({6, 5, 4}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(1); },
                                 test::tableOf({{1, test::material({10, 10, 10}, {0.9f, 0.9f, 0.9f})}}), 1.5f,
                                 environment);
    const LabelGrid& g = scene.medium->grid();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
    const Bounds3f box = scene.geometry->bounds();
    const Vec3f d = normalize(Vec3f{1, 0, -1});
    const Point3f centre = (box.lo + box.hi) * 0.5f;
    const Point3f onTop{centre.x, centre.y, box.hi.z};
    const Ray ray{onTop - d * 5.0f, d};
    auto mirrored = [&](const RenderSettings& settings) {
        const std::unique_ptr<Integrator> estimator =
            integratorKindOf(settings).factory.create(scene, sensor, settings);
        LabelMedium::Tracker medium(*scene.medium);
        Rng rng(1, 2);
        PathStats stats;
        return dynamic_cast<const PixelIntegrator&>(*estimator)
            .LiRGB(ray, ChannelSampling::Hero, 0, medium, rng, stats)[0];
    };
    const RenderSettings schlick = parseScene(exampleScene("schlick", R"(, "fresnel": "schlick")")).render;
    const RenderSettings exact = parseScene(exampleScene("exact", "")).render;
    const double cosTheta = std::sqrt(0.5);
    EXPECT_NEAR(mirrored(schlick), 0.04 + 0.96 * std::pow(1 - cosTheta, 5), 1e-6);
    // The exact factor for unpolarised light at 45 degrees, n = 1.5.
    const double cosT = std::sqrt(1 - 0.5 / (1.5 * 1.5));
    const double rs = std::pow((cosTheta - 1.5 * cosT) / (cosTheta + 1.5 * cosT), 2);
    const double rp = std::pow((1.5 * cosTheta - cosT) / (1.5 * cosTheta + cosT), 2);
    EXPECT_NEAR(mirrored(exact), 0.5 * (rs + rp), 1e-6);
}

// Its key is checked and written by the library's code, which never names it.
TEST(ExampleEstimator, ItsKeyIsCheckedAndWrittenBack) {
    registerExample();
    try {
        parseScene(exampleScene("typo", R"(, "fresnell": "schlick")"));
        ADD_FAILURE() << "a misspelt key was taken";
    } catch (const InputError& e) {
        const std::string expected = "'render.fresnell' not an option of surface_reflection (its options: fresnel)";
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_THROW(parseScene(exampleScene("unknown", R"(, "fresnel": "snell")")), InputError);
    EXPECT_THROW(parseScene(exampleScene("number", R"(, "fresnel": 1)")), InputError);

    SceneDescription desc = parseScene(exampleScene("given", R"(, "fresnel": "schlick")"));
    const std::filesystem::path written = desc.sceneFile.parent_path() / "written.json";
    writeScene(desc, written);
    std::ifstream in(written);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"fresnel\": \"schlick\""), std::string::npos) << text;
    EXPECT_EQ(parseScene(written).render.parameters, desc.render.parameters);

    // Another estimator keeps none of its keys.
    setIntegrator(desc.render, "volpath");
    EXPECT_EQ(desc.render.parameters.text("fresnel"), nullptr);
    EXPECT_EQ(refusalOf(desc.render), "");
}

}  // namespace
}  // namespace pl
