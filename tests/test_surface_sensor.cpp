// The surface-voxel sensor on the bundled 10 mm cube: one pixel per surface
// voxel, every surface voxel exactly once, and each pixel's ray enters the
// object inside its own voxel.
#include <gtest/gtest.h>

#include <set>

#include "core/sensors.h"
#include "io/grid_io.h"
#include "io/mesh_io.h"
#include "test_util.h"

namespace pl {
namespace {

TEST(SurfaceVoxelSensor, HitsEveryCubeSurfaceVoxelExactlyOnce) {
    auto dir = test::sourceDir() / "data";
    LabelGrid grid = loadLabelGrid(dir / "grids/cube10_white.vdb", std::nullopt);
    Geometry geometry(loadMesh(dir / "meshes/cube10.obj"));
    SurfaceVoxelSensor sensor(geometry, grid.frame(), grid.surfaceVoxels());

    // Brute force over the dense grid: non-void voxels with a void face neighbour.
    const GridFrame& f = grid.frame();
    std::vector<Label> dense = grid.toDense();
    auto at = [&](int x, int y, int z) -> Label {
        if (x < 0 || y < 0 || z < 0 || x >= f.resolution.x || y >= f.resolution.y || z >= f.resolution.z)
            return grid.voidLabel();
        return dense[(size_t(z) * f.resolution.y + y) * f.resolution.x + x];
    };
    std::set<Vec3i> expected;
    for (int z = 0; z < f.resolution.z; ++z)
        for (int y = 0; y < f.resolution.y; ++y)
            for (int x = 0; x < f.resolution.x; ++x) {
                if (at(x, y, z) == grid.voidLabel()) continue;
                if (at(x + 1, y, z) == grid.voidLabel() || at(x - 1, y, z) == grid.voidLabel() ||
                    at(x, y + 1, z) == grid.voidLabel() || at(x, y - 1, z) == grid.voidLabel() ||
                    at(x, y, z + 1) == grid.voidLabel() || at(x, y, z - 1) == grid.voidLabel())
                    expected.insert({x + f.indexMin.x, y + f.indexMin.y, z + f.indexMin.z});
            }

    std::set<Vec3i> seen;
    Vec3f scale = f.worldToCellScale(), offset = f.worldToCellOffset();
    size_t wrongVoxel = 0;
    for (size_t p = 0; p < sensor.pixelCount(); ++p) {
        const auto& px = sensor.pixels()[p];
        EXPECT_TRUE(seen.insert(px.voxel).second) << "voxel seen twice";
        Ray ray = sensor.generateRay(p, 0.5f, 0.5f);
        auto hit = geometry.intersect(ray);
        ASSERT_TRUE(hit.has_value()) << "pixel " << p << " misses the mesh";
        EXPECT_LT(dot(ray.d, hit->ng), 0.0f);  // enters from outside
        Point3f q = hit->p - hit->ng * 1e-4f;  // just inside
        Vec3i v{int(std::floor(q.x * scale.x + offset.x)), int(std::floor(q.y * scale.y + offset.y)),
                int(std::floor(q.z * scale.z + offset.z))};
        if (v != px.voxel && ++wrongVoxel < 10)
            ADD_FAILURE() << "voxel " << px.voxel.x << "," << px.voxel.y << "," << px.voxel.z << " entered at "
                          << v.x << "," << v.y << "," << v.z << " p=" << hit->p.x << "," << hit->p.y << "," << hit->p.z
                          << " n=" << px.normal.x << "," << px.normal.y << "," << px.normal.z;
    }
    EXPECT_EQ(seen, expected);
    EXPECT_EQ(sensor.pixelCount(), expected.size());
    EXPECT_EQ(wrongVoxel, 0u);

    // The atlas shows each visible voxel in its own image pixel.
    std::set<int64_t> atlasPixels;
    size_t shown = 0;
    for (size_t p = 0; p < sensor.pixelCount(); ++p) {
        int64_t i = sensor.pixelImageIndex(p);
        if (i < 0) continue;
        ++shown;
        EXPECT_TRUE(atlasPixels.insert(i).second);
        EXPECT_LT(i, int64_t(sensor.imageWidth()) * sensor.imageHeight());
    }
    // On a cube only edge voxels (shared by two faces) can be hidden.
    EXPECT_GT(shown, sensor.pixelCount() * 97 / 100);
}

}  // namespace
}  // namespace pl
