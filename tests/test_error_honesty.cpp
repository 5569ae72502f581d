// Whether the reported standard errors are honest at the sample counts the
// loop uses: two independent renders of a halftoned box, each with its own
// errors, compared voxel by voxel (compare/error_calibration.h). Honest
// errors give a mean z^2 near 1 and almost no |z| beyond 4 (6.3e-5 for a
// normal); the bounds are those the bundled greek cube is held to
// (docs/formats.md, "What the standard errors include"). Errors that are
// too small (one block of light paths reporting 0, or a two-sample spread)
// put the mean z^2 in the tens and several per cent beyond 4.
#include <gtest/gtest.h>

#include <cstdio>

#include "compare/error_calibration.h"
#include "core/sensors.h"
#include "io/materials_io.h"
#include "render/render.h"
#include "test_util.h"

namespace pl {
namespace {

// A box at the printer's voxel size with a halftoned 0.5 mm shell over a
// white core: stripes of cyan, magenta, yellow and black, each dithered
// against white, so that bright and dark voxels lie side by side.
Scene halftonedBox() {
    const Vec3f voxel_mm = kPrinterVoxel_mm;
    const Vec3i resolution{36, 18, 56};
    auto labelOf = [&](const Vec3i& v) {
        const float x = (float(v.x) + 0.5f) * voxel_mm.x, y = (float(v.y) + 0.5f) * voxel_mm.y,
                    z = (float(v.z) + 0.5f) * voxel_mm.z;
        const float depth_mm = std::min({x, y, z, resolution.x * voxel_mm.x - x, resolution.y * voxel_mm.y - y,
                                         resolution.z * voxel_mm.z - z});
        if (depth_mm > 0.5f) return Label(4);
        const Label ink = Label(int((x + y + z) / 0.35f) % 4);  // cyan, magenta, yellow, black
        const uint64_t h = mix64(uint64_t(v.x) * 73856093ULL ^ uint64_t(v.y) * 19349663ULL ^ uint64_t(v.z) * 83492791ULL);
        const float share = 0.15f + 0.7f * (0.5f + 0.5f * std::sin(3.0f * x + 2.0f * z));
        return double(h % 1000) / 1000.0 < share ? ink : Label(4);
    };
    return test::boxScene(resolution, voxel_mm, labelOf,
                          loadMaterials(test::sourceDir() / "data/materials/resins_illustrative.json"), 1.5f);
}

class ErrorHonesty : public ::testing::TestWithParam<std::tuple<std::string, uint32_t>> {};

TEST_P(ErrorHonesty, TwoRendersAgreeWithinTheirErrors) {
    const auto& [integrator, spp] = GetParam();
    static const Scene scene = halftonedBox();
    const LabelGrid& g = scene.medium->grid();
    const SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
    RenderSettings s;
    s.integrator = integrator;
    s.spp = spp;
    s.seed = 11;
    const RenderResult a = render(scene, sensor, s);
    s.seed = 12;
    const RenderResult b = render(scene, sensor, s);
    const ErrorCalibration e = calibrateErrors(a.film, b.film);
    ASSERT_GT(e.values, 20000u);
    std::printf("%s at %u spp: mean z^2 %.3f %.3f %.3f, |z| > 4: %zu of %zu\n", integrator.c_str(), spp, e.meanZSq[0],
                e.meanZSq[1], e.meanZSq[2], e.beyondFour, e.values);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(e.meanZSq[size_t(c)], 0.5) << integrator << " at " << spp << " spp, channel " << c;
        EXPECT_LE(e.meanZSq[size_t(c)], 1.6) << integrator << " at " << spp << " spp, channel " << c;
    }
    EXPECT_LT(e.shareBeyondFour(), 1e-3) << integrator << " at " << spp << " spp: " << e.beyondFour << " of "
                                         << e.values << " values beyond 4";
    EXPECT_EQ(e.zeroErrorButDiffer, 0u) << integrator << " at " << spp << " spp";
}

INSTANTIATE_TEST_SUITE_P(LowSampleCounts, ErrorHonesty,
                         ::testing::Combine(::testing::Values("volpath", "printpt", "lighttrace"),
                                            ::testing::Values(1u, 2u, 8u)),
                         [](const auto& info) {
                             return std::get<0>(info.param) + "_" + std::to_string(std::get<1>(info.param)) + "spp";
                         });

}  // namespace
}  // namespace pl
