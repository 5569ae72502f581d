// The prediction on the model (.glb): the mesh with the surface voxels'
// colours baked into a texture atlas. Read back by the glTF reader and
// sampled where each voxel meets the surface, as a viewer samples it, the
// colours must be those written, over the eye's footprint.
#include <random>

#include "compare/surface_colour_error.h"
#include "core/triangle_atlas.h"
#include "io/mesh_io.h"
#include "io/mesh_repair.h"
#include "test_util.h"

namespace pl {
namespace {

// A sphere's surface voxels at the printer's anisotropic voxel: the cells
// whose centres lie inside with a face neighbour's outside.
std::vector<Vec3i> sphereSurfaceVoxels(const GridFrame& frame, const Point3f& centre, float radius_mm) {
    auto inside = [&](const Vec3i& v) {
        const Vec3f d = frame.voxelCenter_mm(v) - centre;
        return dot(d, d) < radius_mm * radius_mm;
    };
    std::vector<Vec3i> voxels;
    const Vec3i hi = frame.indexMax();
    for (int z = frame.indexMin.z; z < hi.z; ++z)
        for (int y = frame.indexMin.y; y < hi.y; ++y)
            for (int x = frame.indexMin.x; x < hi.x; ++x) {
                const Vec3i v{x, y, z};
                if (!inside(v)) continue;
                bool exposed = false;
                for (int a = 0; a < 3; ++a)
                    for (int s : {-1, 1}) {
                        Vec3i n = v;
                        n[a] += s;
                        exposed = exposed || !inside(n);
                    }
                if (exposed) voxels.push_back(v);
            }
    return voxels;
}

TEST(PredictionGlb, ColoursOnTheModelAreTheVoxelsOverTheEyesFootprint) {
    const Point3f centre{1.6f, 1.6f, 1.6f};
    const float radius_mm = 1.5f;
    TriangleMesh sphere = synthetic::sphereMesh(centre, radius_mm, 32);
    GridFrame frame;
    frame.voxelSize_mm = kPrinterVoxel_mm;
    for (int a = 0; a < 3; ++a) frame.resolution[a] = int(std::ceil(3.2f / frame.voxelSize_mm[a]));
    const std::vector<Vec3i> voxels = sphereSurfaceVoxels(frame, centre, radius_mm);
    ASSERT_GT(voxels.size(), 10000u);
    // A smooth gradient with a halftone's grain on it, saturated in places.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> grain(-0.15f, 0.15f);
    std::vector<RGB> colours(voxels.size());
    for (size_t i = 0; i < voxels.size(); ++i) {
        const Point3f p = frame.voxelCenter_mm(voxels[i]);
        colours[i] = {std::clamp(p.x / 3.2f + grain(rng), 0.0f, 1.0f), std::clamp(0.05f + grain(rng), 0.0f, 1.0f),
                      std::clamp(1.0f - p.z / 3.2f + grain(rng), 0.0f, 1.0f)};
    }
    const auto dir = test::freshTempDir("prediction_glb");
    writePredictionGlb(sphere, frame, voxels, colours, dir / "p.glb");
    // Each triangle's vertices, positions and texture coordinates, and an
    // 8-bit PNG: under 80 bytes a surface voxel.
    EXPECT_LT(std::filesystem::file_size(dir / "p.glb"), 80 * voxels.size());

    // (Repaired: the sphere's poles have triangles of no area, which the
    // reader's check for a closed surface would not take.)
    MeshRepairSummary repaired;
    const MeshAsset back = loadMeshAsset(dir / "p.glb", MeshPlacement{}, &repaired);
    ASSERT_EQ(back.appearance.textures.size(), 1u);
    const Geometry geometry(back.mesh);
    std::vector<Point3f> points(voxels.size());
    std::vector<RGB> seen(voxels.size());
    for (size_t i = 0; i < voxels.size(); ++i) {
        const auto cp = geometry.closestPoint(frame.voxelCenter_mm(voxels[i]), 0.5f);
        ASSERT_TRUE(cp);
        points[i] = cp->p;
        seen[i] = back.appearance.colorAt(back.mesh, cp->prim, cp->p);
    }
    const SurfaceColourError e = surfaceColourError(points, seen, colours);
    // Per voxel a few units where the grain changes: a voxel's point may
    // show a neighbour whose centre is nearer the surface there (the
    // patches gave the surface to voxels the same way), and bilinear
    // lookups blend neighbouring voxels' texels (8-bit sRGB alone makes
    // 0.01 over the footprint). Over the eye's footprint, well under one.
    EXPECT_LT(e.meanFiltered, 0.5) << "p95 " << e.p95Filtered << ", per voxel " << e.mean << " / " << e.p95;
    EXPECT_LT(e.p95Filtered, 1.0);
    std::filesystem::remove_all(dir);
}

TEST(TriangleAtlas, GrowsItsTexelToFitTheLargestSide) {
    const TriangleMesh sphere = synthetic::sphereMesh({0, 0, 0}, 5.0f, 16);
    const TriangleAtlas fine(sphere, 0.01f, 256);
    EXPECT_LE(std::max(fine.width(), fine.height()), 256);
    EXPECT_GT(fine.texel_mm(), 0.01f);
    // More triangles than their gutters fit in the side asked for: the
    // atlas ends as small as they allow.
    const TriangleMesh many = synthetic::sphereMesh({0, 0, 0}, 5.0f, 64);
    const TriangleAtlas crowded(many, 0.01f, 64);
    EXPECT_GT(crowded.width(), 64);
    EXPECT_LT(double(crowded.width()) * crowded.height(), 2.0 * 25.0 * double(many.triangleCount()));
    const TriangleAtlas coarse(sphere, 0.5f);
    EXPECT_FLOAT_EQ(coarse.texel_mm(), 0.5f);
    // Each triangle's corners land in the atlas, inside its own rectangle:
    // a bake that paints each triangle its own colour reads back that
    // colour at its centroid.
    const std::vector<RGB> image =
        coarse.bake(sphere, [](uint32_t t, const Point3f&) { return RGB{float(t % 7) / 7, float(t % 11) / 11, float(t) / 1e4f}; });
    for (size_t t = 0; t < sphere.triangleCount(); ++t) {
        float u = 0, v = 0;
        for (const auto& c : coarse.uv(t)) {
            EXPECT_GE(c[0], 0.0f);
            EXPECT_LE(c[0], 1.0f);
            EXPECT_GE(c[1], 0.0f);
            EXPECT_LE(c[1], 1.0f);
            u += c[0] / 3, v += c[1] / 3;
        }
        const RGB at = image[size_t(v * float(coarse.height())) * size_t(coarse.width()) + size_t(u * float(coarse.width()))];
        EXPECT_EQ(at[0], float(t % 7) / 7) << t;
        EXPECT_EQ(at[2], float(t) / 1e4f) << t;
    }
}

}  // namespace
}  // namespace pl
