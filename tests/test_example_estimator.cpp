// The example estimator (surface_reflection.h) added as any estimator is:
// its file pair and one registry line. Rendered through the driver it gives
// the closed form of a dielectric's mirror reflection.
#include <gtest/gtest.h>

#include "render/registry.h"
#include "render/render.h"
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

}  // namespace
}  // namespace pl
