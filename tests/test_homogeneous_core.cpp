// The homogeneous-core approximation (scene/homogeneous_core.h) changes no
// voxel nearer the surface than its depth, gives every voxel deeper than
// the depth plus the clearance's block the core's label, and takes that
// label from the deep voxels' majority.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/rng.h"
#include "core/surface_clearance.h"
#include "scene/homogeneous_core.h"
#include "test_util.h"

namespace pl {
namespace {

constexpr Label kWhite = 4, kBlack = 3, kCyan = 0;

TEST(HomogeneousCore, RelabelsExactlyTheDeepVoxels) {
    // A box of anisotropic printer voxels: a dithered shell of cyan and
    // black over a core that is mostly white with black specks.
    const Vec3i resolution{60, 30, 90};
    const Vec3f voxel_mm = kPrinterVoxel_mm;
    const Point3f corner{1.0f, -2.0f, 0.5f};
    auto depthOf = [&](const Vec3i& v) {
        float d = 1e9f;
        for (int a = 0; a < 3; ++a)
            d = std::min({d, (v[a] + 0.5f) * voxel_mm[a], (resolution[a] - v[a] - 0.5f) * voxel_mm[a]});
        return d;
    };
    auto labelOf = [&](const Vec3i& v) {
        const uint64_t h = mix64(uint64_t(v.x) * 73856093u ^ uint64_t(v.y) * 19349663u ^ uint64_t(v.z) * 83492791u);
        if (depthOf(v) < 0.3f) return h % 2 ? kCyan : kBlack;
        return h % 10 == 0 ? kBlack : kWhite;
    };
    const LabelGrid grid = synthetic::labelGrid(resolution, voxel_mm, labelOf, corner);
    const Geometry geometry(test::boxMesh(corner, grid.frame().cornerMax_mm()));
    const float block_mm = float(1 << SurfaceClearance::kBlockLog2) * length(voxel_mm);

    for (float depth_mm : {0.1f, 0.4f}) {
        HomogeneousCore core;
        const LabelGrid cored = withHomogeneousCore(grid, geometry, depth_mm, &core);
        EXPECT_EQ(core.label, kWhite) << depth_mm;
        uint64_t deeper = 0, changed = 0, sure = 0;
        for (int z = 0; z < resolution.z; ++z)
            for (int y = 0; y < resolution.y; ++y)
                for (int x = 0; x < resolution.x; ++x) {
                    const Vec3i v{x, y, z};
                    const Label before = grid.label(v), after = cored.label(v);
                    const float d = depthOf(v);
                    if (d <= depth_mm) {
                        ASSERT_EQ(after, before) << depth_mm << " at " << x << "," << y << "," << z;
                    }
                    if (d > depth_mm + block_mm) {
                        ASSERT_EQ(after, kWhite) << depth_mm << " at " << x << "," << y << "," << z;
                        sure += 1;
                    }
                    deeper += d > depth_mm;
                    changed += after != before;
                }
        EXPECT_EQ(changed, core.changedVoxels) << depth_mm;
        EXPECT_GT(changed, 0u) << depth_mm;
        EXPECT_GE(core.coreVoxels, sure) << depth_mm;
        EXPECT_LE(core.coreVoxels, deeper) << depth_mm;
    }
    // Deeper than any colour or speck: nothing changes.
    HomogeneousCore none;
    const LabelGrid same = withHomogeneousCore(grid, geometry, 2.0f, &none);
    EXPECT_EQ(none.changedVoxels, 0u);
    EXPECT_EQ(none.coreVoxels, 0u);
}

}  // namespace
}  // namespace pl
