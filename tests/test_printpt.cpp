// printpt against the reference: on small scenes its mean surface radiance
// must agree with volpath's (no re-entry) within their combined standard
// error, with every switch on and off; and it must pass the white furnace.
#include <gtest/gtest.h>

#include "integrators/render.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

Scene mixedScene(float ior) {
    MaterialTable t = test::tableOf({{0, material({10, 8, 8}, {0.25f, 0.97f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                                     {1, material({2.5f, 10, 6}, {0.98f, 0.25f, 0.9f}, {0.4f, 0.4f, 0.4f})},
                                     {3, material({20, 20, 20}, {0.02f, 0.02f, 0.02f}, {0.4f, 0.4f, 0.4f})},
                                     {4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})},
                                     {6, material({1e-4f, 1e-4f, 1e-4f}, {1, 1, 1})}});
    return test::boxScene({40, 20, 60}, {0.0423f, 0.0847f, 0.027f},
                          [](const Vec3i& v) {
                              static const Label palette[6] = {0, 1, 3, 4, 4, 6};
                              return palette[(v.x / 4 + 2 * (v.y / 3) + 3 * (v.z / 6)) % 6];
                          },
                          t, ior);
}

struct Estimate {
    RGB mean, standardError;
};

// Mean over all pixels, with the standard error of that mean.
Estimate renderMean(const Scene& scene, const Sensor& sensor, const RenderSettings& settings) {
    RenderResult r = render(scene, sensor, settings);
    Estimate e{};
    size_t n = sensor.pixelCount();
    for (int c = 0; c < 3; ++c) {
        double sum = 0, var = 0;
        for (size_t p = 0; p < n; ++p) {
            sum += r.film.mean(p, c);
            var += double(r.film.standardError(p, c)) * r.film.standardError(p, c);
        }
        e.mean[c] = float(sum / n);
        e.standardError[c] = float(std::sqrt(var) / n);
    }
    return e;
}

void expectAgreement(const Estimate& a, const Estimate& b, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        double combined = std::sqrt(double(a.standardError[c]) * a.standardError[c] +
                                    double(b.standardError[c]) * b.standardError[c]);
        EXPECT_GT(combined, 0.0);
        EXPECT_NEAR(a.mean[c], b.mean[c], 4.0 * combined) << what << ", channel " << c;
    }
}

TEST(PrintPt, AgreesWithVolpathWithEverySwitch) {
    for (float ior : {1.0f, 1.5f}) {
        Scene scene = mixedScene(ior);
        const LabelGrid& g = scene.medium->grid();
        SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
        RenderSettings reference;
        reference.spp = 24;
        reference.seed = 11;
        Estimate volpath = renderMean(scene, sensor, reference);

        struct Config {
            const char* name;
            PrintPtOptions options;
        };
        const Config configs[] = {{"all on", {true, true, 0.99f, 4}},
                                  {"geometry first", {false, true, 0.99f, 4}},
                                  {"random Fresnel", {true, false, 0.99f, 4}},
                                  {"no branching, low RR cap", {true, true, 0.6f, 1}}};
        for (const Config& cfg : configs) {
            RenderSettings s = reference;
            s.integrator = "printpt";
            s.printpt = cfg.options;
            s.spp = 8;
            s.seed = 12;
            expectAgreement(volpath, renderMean(scene, sensor, s), std::string(cfg.name) + ", ior " + std::to_string(ior));
        }
    }
}

TEST(PrintPt, WhiteFurnaceWithinStatisticalError) {
    MaterialTable t = test::tableOf({{4, material({6, 9, 24}, {1, 1, 1}, {0.4f, 0.4f, 0.4f})},
                                     {6, material({0.5f, 0.5f, 0.5f}, {1, 1, 1})}});
    for (float ior : {1.0f, 1.5f}) {
        Scene scene = test::boxScene({20, 10, 30}, {0.0423f, 0.0847f, 0.027f},
                                     [](const Vec3i& v) { return Label((v.x + v.z) % 3 ? 4 : 6); }, t, ior);
        const LabelGrid& g = scene.medium->grid();
        SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels());
        RenderSettings s;
        s.integrator = "printpt";
        s.spp = 8;
        Estimate e = renderMean(scene, sensor, s);
        for (int c = 0; c < 3; ++c) {
            // Russian roulette makes single paths differ from 1; the mean must not.
            EXPECT_GT(e.standardError[c], 0.0f);
            EXPECT_NEAR(e.mean[c], 1.0f, 4.0f * e.standardError[c]) << "ior " << ior << " channel " << c;
        }
    }
}

}  // namespace
}  // namespace pl
