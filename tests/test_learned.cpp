// The learned predictor (integrators/learned/learned.h): its descriptor's pyramid
// keeps the object's volume and coefficients at every level, the
// descriptor is blind to a turn about the normal, the perceptron computes
// what its weights say, the model refuses what it was not trained for,
// and the committed model (data/materials/resins_illustrative.learned.json)
// gives the exact half-space of white resin within the bound it reports.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <tbb/global_control.h>

#include "integrators/learned/learned.h"
#include "core/input_error.h"
#include "io/learned_model_io.h"
#include "io/materials_io.h"
#include "media/slab_transport.h"
#include "render/render.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

constexpr float kIor = 1.5f;

std::filesystem::path materialsFile() { return test::sourceDir() / "data/materials/resins_illustrative.json"; }
std::filesystem::path modelFile() { return learnedModelBeside(materialsFile()); }

MaterialTable twoResins() {
    return test::tableOf({{4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})},
                          {3, material({20, 20, 20}, {0.02f, 0.02f, 0.02f}, {0.4f, 0.4f, 0.4f})}});
}

Label scattered(const Vec3i& v) {
    const uint64_t h = mix64(uint64_t(v.x) * 73856093u ^ uint64_t(v.y) * 19349663u ^ uint64_t(v.z) * 83492791u);
    return h % 3 == 0 ? test::kTestVoid : Label(h % 3 == 1 ? 3 : 4);
}

// With 2 x 2 x 2 voxels per finest cell, every level holds the object's
// volume and its summed coefficients exactly (a cell beyond the grid is void).
TEST(Learned, PyramidKeepsTheVolumeAndTheCoefficients) {
    const Vec3i resolution{40, 36, 28};
    const float voxel_mm = 0.05f;
    const Scene scene = test::boxScene(resolution, {voxel_mm, voxel_mm, voxel_mm}, scattered, twoResins(), kIor);
    double volume = 0, scattering = 0;
    for (int z = 0; z < resolution.z; ++z)
        for (int y = 0; y < resolution.y; ++y)
            for (int x = 0; x < resolution.x; ++x) {
                const Label l = scattered({x, y, z});
                if (l == test::kTestVoid) continue;
                volume += std::pow(voxel_mm, 3);
                scattering += std::pow(voxel_mm, 3) * (l == 4 ? 6 * 0.995 : 20 * 0.02);
            }
    const PropertyPyramid pyramid(*scene.medium, 0.1f, 4, uint64_t(1) << 30);
    for (int l = 0; l < pyramid.levels(); ++l) {
        const float cell = pyramid.cellSize_mm(l);
        double v = 0, s = 0;
        for (int z = 0; z * cell < resolution.z * voxel_mm; ++z)
            for (int y = 0; y * cell < resolution.y * voxel_mm; ++y)
                for (int x = 0; x * cell < resolution.x * voxel_mm; ++x) {
                    const CellProperties c = pyramid.at(l, {(x + 0.5f) * cell, (y + 0.5f) * cell, (z + 0.5f) * cell});
                    v += c.filled * std::pow(cell, 3);
                    s += c.sigmaS_perMm[0] * std::pow(cell, 3);
                }
        EXPECT_NEAR(v, volume, 1e-4 * volume) << "level " << l;
        EXPECT_NEAR(s, scattering, 1e-4 * scattering) << "level " << l;
    }
}

// Reflectance under uniform light does not change when the labels turn
// about the normal; nor may the descriptor (its rings are means).
TEST(Learned, DescriptorIsBlindToAQuarterTurnAboutTheNormal) {
    const int side = 64, depth = 30;  // 3.2 mm: whole cells at every level, the turn maps cells onto cells
    const float voxel_mm = 0.05f;
    auto pattern = [](int x, int y, int z) {
        return (x / 3 + 2 * (y / 5) + z / 4) % 3 == 0 ? Label(3) : Label(4);
    };
    const Scene a = test::boxScene({side, side, depth}, {voxel_mm, voxel_mm, voxel_mm},
                                   [&](const Vec3i& v) { return pattern(v.x, v.y, v.z); }, twoResins(), kIor);
    // Turned by 90 degrees about z: the voxel (x, y) holds what (y, side-1-x) held.
    const Scene b = test::boxScene({side, side, depth}, {voxel_mm, voxel_mm, voxel_mm},
                                   [&](const Vec3i& v) { return pattern(v.y, side - 1 - v.x, v.z); }, twoResins(), kIor);
    const LabelDescriptor da(*a.medium, uint64_t(1) << 30), db(*b.medium, uint64_t(1) << 30);
    LabelMedium::Tracker sa(*a.medium), sb(*b.medium);
    const float top_mm = depth * voxel_mm, centre_mm = 0.5f * side * voxel_mm;
    for (const Vec3f offset : {Vec3f(0, 0, 0), Vec3f(0.4f, -0.2f, 0)}) {
        std::array<LabelDescriptor::Values, 3> va, vb;
        // In the turned grid the point (x, y) sits at (y, -x) about the centre... and back.
        const Point3f pa{centre_mm + offset.x, centre_mm + offset.y, top_mm};
        const Point3f pb{centre_mm - offset.y, centre_mm + offset.x, top_mm};
        da.compute(pa, {0, 0, 1}, sa, va);
        db.compute(pb, {0, 0, 1}, sb, vb);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < LabelDescriptor::kSize; ++k)
                EXPECT_NEAR(va[size_t(c)][size_t(k)], vb[size_t(c)][size_t(k)], 2e-5f) << "channel " << c << " value " << k;
    }
}

TEST(Learned, PerceptronComputesWhatItsWeightsSay) {
    LearnedModel m;
    m.descriptorSize = 2;
    m.layers = {{2, 2, {1, -1, 0.5f, 2}, {0.1f, -3}}, {2, 1, {2, 3}, {0.5f}}};
    const float inputs[4] = {1, 2, 3, 0.5f};
    float outputs[2];
    evaluateLearnedModel(m, inputs, 2, outputs);
    // Row 1: hidden (max(0, 1-2+0.1), max(0, 0.5+4-3)) = (0, 1.5) -> 2*0 + 3*1.5 + 0.5.
    EXPECT_FLOAT_EQ(outputs[0], 5.0f);
    // Row 2: hidden (max(0, 3-0.5+0.1), max(0, 1.5+1-3)) = (2.6, 0) -> 5.2 + 0.5.
    EXPECT_FLOAT_EQ(outputs[1], 5.7f);
}

TEST(Learned, ModelRefusesWhatItWasNotTrainedFor) {
    const std::shared_ptr<const LearnedModel> model = loadLearnedModel(modelFile());
    MaterialTable table = loadMaterials(materialsFile());
    EXPECT_EQ(model->refusal(table, kPrinterVoxel_mm), "");
    EXPECT_NE(model->refusal(table, {0.05f, 0.05f, 0.05f}).find("voxels"), std::string::npos);
    table.byLabel[kWhiteLabel].albedo[1] = 0.9f;
    EXPECT_NE(model->refusal(table, kPrinterVoxel_mm).find("'white'"), std::string::npos);
    // And the predictor says so, naming the model.
    const Scene scene = test::boxScene({20, 20, 20}, {0.05f, 0.05f, 0.05f}, [](const Vec3i&) { return Label(4); },
                                       loadMaterials(materialsFile()), kIor);
    const SurfaceVoxelSensor sensor(*scene.geometry, scene.medium->frame(), scene.medium->grid().surfaceVoxels());
    try {
        Learned learned(scene, sensor, model);
        ADD_FAILURE() << "no refusal";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(modelFile().string()), std::string::npos);
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
    // A malformed file is refused with its name.
    const auto dir = test::freshTempDir("learned_model");
    std::ofstream(dir / "bad.learned.json") << R"({"format": "printlight-learned-1", "layers": []})";
    EXPECT_THROW(loadLearnedModel(dir / "bad.learned.json"), InputError);
}

// White resin 8 x 8 x 4 mm at the printer's voxels: at the centre of the
// top face, a half-space. The model never saw this block; it must give
// the deterministic solver's value within twice the bound it reports.
// And the same bits whatever the threads.
TEST(Learned, WhiteHalfSpaceWithinItsBoundOnAnyThreads) {
    const MaterialTable table = loadMaterials(materialsFile());
    const Vec3i resolution{189, 94, 148};
    const Scene scene = test::boxScene(resolution, kPrinterVoxel_mm, [](const Vec3i&) { return Label(kWhiteLabel); },
                                       table, kIor);
    std::vector<SurfaceVoxel> centre;
    for (const SurfaceVoxel& v : scene.medium->grid().surfaceVoxels())
        if (v.voxel.z == resolution.z - 1 && std::abs(v.voxel.x - 94) < 5 && std::abs(v.voxel.y - 47) < 3)
            centre.push_back(v);
    const SurfaceVoxelSensor sensor(*scene.geometry, scene.medium->frame(), centre);
    RenderSettings s;
    s.integrator = "learned";
    s.parameters.setText("learned_model", modelFile().string());
    s.spp = 1;
    auto renderWith = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return render(scene, sensor, s);
    };
    const RenderResult one = renderWith(1), two = renderWith(2);
    const double specular = std::pow((kIor - 1.0) / (kIor + 1.0), 2);
    const Material& white = table.byLabel[kWhiteLabel];
    for (int c = 0; c < 3; ++c) {
        const double exact = specular + (1 - specular) * slabEscape({white.albedo[c], white.g[c], kIor}).top;
        for (size_t p = 0; p < sensor.pixelCount(); ++p) {
            const double v = one.film.mean(p, c);
            EXPECT_LE(std::abs(v - exact), 2 * one.film.sharedError(p, c)) << "channel " << c << " pixel " << p;
            EXPECT_EQ(v, two.film.mean(p, c));
        }
    }
}

}  // namespace
}  // namespace pl
