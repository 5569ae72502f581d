// The surface-voxel sensor's two footprints (core/sensors.h): the patches
// tile the mesh (their areas add up to it; a face voxel's patch is its
// face), and on the flat faces of a box of one material, away from its
// edges, the patch average and the ray agree voxel by voxel and on the mean.
// The prism index (core/prism_index.h): the inward normal lines through a
// point, for light tracing into the patches.
#include <gtest/gtest.h>

#include "core/prism_index.h"
#include "render_estimate.h"
#include "test_util.h"

namespace pl {
namespace {

using test::material;

const Vec3i kResolution{24, 20, 16};
const Vec3f kVoxel_mm{0.05f, 0.04f, 0.06f};  // anisotropic on purpose

Scene whiteBox() {
    MaterialTable t = test::tableOf({{4, material({20, 20, 20}, {0.99f, 0.99f, 0.99f}, {0.4f, 0.4f, 0.4f})}});
    return test::boxScene(kResolution, kVoxel_mm, [](const Vec3i&) { return Label(4); }, t, 1.5f);
}

// Voxels with one exposed face at least `margin` voxels from every other face.
bool awayFromEdges(const SurfaceVoxel& sv, int margin) {
    if (__builtin_popcount(sv.exposedFaces) != 1) return false;
    int facesNear = 0;
    for (int a = 0; a < 3; ++a) {
        const int lo = sv.voxel[a], hi = kResolution[a] - 1 - sv.voxel[a];
        facesNear += (lo < margin) + (hi < margin);
    }
    return facesNear == 1;  // only the exposed one
}

TEST(SurfacePatches, TileTheMeshAndAFaceVoxelsPatchIsItsFace) {
    Scene scene = whiteBox();
    const LabelGrid& g = scene.medium->grid();
    const std::vector<SurfaceVoxel> voxels = g.surfaceVoxels();
    SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), voxels, SurfaceVoxelSensor::Footprint::Patch);
    const SurfacePatches& patches = *sensor.patches();
    EXPECT_EQ(patches.emptyPatches(), 0u);
    EXPECT_EQ(patches.unassignedArea_mm2(), 0.0);
    const Vec3f size{kResolution.x * kVoxel_mm.x, kResolution.y * kVoxel_mm.y, kResolution.z * kVoxel_mm.z};
    const double boxArea = 2.0 * (double(size.x) * size.y + double(size.y) * size.z + double(size.z) * size.x);
    double total = 0;
    int faceVoxels = 0;
    for (size_t i = 0; i < voxels.size(); ++i) {
        total += patches.area_mm2(i);
        if (__builtin_popcount(voxels[i].exposedFaces) != 1) continue;
        const int face = __builtin_ctz(voxels[i].exposedFaces);
        const int axis = std::abs(kFaceDirections[face].x) ? 0 : std::abs(kFaceDirections[face].y) ? 1 : 2;
        const double faceArea = double(kVoxel_mm[(axis + 1) % 3]) * kVoxel_mm[(axis + 2) % 3];
        EXPECT_NEAR(patches.area_mm2(i), faceArea, 1e-4 * faceArea) << i;
        ++faceVoxels;
    }
    EXPECT_GT(faceVoxels, 1000);
    EXPECT_NEAR(total, boxArea, 1e-5 * boxArea);
    // Samples land on the patch, on the voxel's face, and the point of the
    // triangle is found to be that patch's (light tracing scores there).
    Rng rng(1, 2);
    for (size_t i = 0; i < voxels.size(); i += 37) {
        auto x = patches.sample(i, rng.uniform(), rng.uniform());
        ASSERT_TRUE(x);
        EXPECT_EQ(patches.pixelAt(x->prim, x->p), std::optional<uint32_t>(uint32_t(i))) << i;
        Ray r = sensor.generateRay(i, rng.uniform(), rng.uniform());
        const Point3f lo = g.frame().voxelCenter_mm(voxels[i].voxel) - kVoxel_mm * 0.5f;
        auto hit = scene.geometry->intersect(r);
        ASSERT_TRUE(hit);
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(hit->p[a], lo[a] - 1e-4f) << i;
            EXPECT_LE(hit->p[a], lo[a] + kVoxel_mm[a] + 1e-4f) << i;
        }
    }
}

TEST(SurfacePatches, PatchAndRayAgreeOnFlatFacesOfOneMaterial) {
    Scene scene = whiteBox();
    const LabelGrid& g = scene.medium->grid();
    const std::vector<SurfaceVoxel> voxels = g.surfaceVoxels();
    RenderSettings s;
    s.integrator = "printpt";
    s.spp = 16;
    s.channelSampling = ChannelSampling::Hero;
    SurfaceVoxelSensor raySensor(*scene.geometry, g.frame(), voxels);
    SurfaceVoxelSensor patchSensor(*scene.geometry, g.frame(), voxels, SurfaceVoxelSensor::Footprint::Patch);
    s.seed = 1;
    RenderResult ray = render(scene, raySensor, s);
    s.seed = 2;
    RenderResult patch = render(scene, patchSensor, s);
    double sumRay = 0, sumPatch = 0, variance = 0;
    int n = 0, beyond = 0;
    for (size_t i = 0; i < voxels.size(); ++i) {
        if (!awayFromEdges(voxels[i], 5)) continue;
        for (int c = 0; c < 3; ++c) {
            const double a = ray.film.mean(i, c), b = patch.film.mean(i, c);
            const double ea = ray.film.standardError(i, c), eb = patch.film.standardError(i, c);
            sumRay += a;
            sumPatch += b;
            variance += ea * ea + eb * eb;
            beyond += std::abs(a - b) > 4.0 * std::sqrt(ea * ea + eb * eb);
            ++n;
        }
    }
    ASSERT_GT(n, 1000);
    EXPECT_NEAR(sumRay / n, sumPatch / n, 4.0 * std::sqrt(variance) / n);
    EXPECT_LT(beyond, n / 100) << "values beyond 4 sigma";
}

}  // namespace
}  // namespace pl

namespace pl {
namespace {

// Inside a cube every point lies on the inward normal line of each of the
// six faces (one of its two triangles), at its distance from that face;
// the depth limits which ones count.
TEST(PrismIndex, APointInACubeLiesOnEachFacesLineWithinTheDepth) {
    const TriangleMesh cube = synthetic::boxMesh({0, 0, 0}, {1, 1, 1});
    const Point3f y{0.2f, 0.3f, 0.45f};
    for (float depth : {2.0f, 0.4f}) {
        PrismIndex index(cube, depth);
        std::vector<PrismIndex::Line> lines;
        index.forEachLine(y, [&](const PrismIndex::Line& l) { lines.push_back(l); });
        const float expected[6] = {0.8f, 0.2f, 0.7f, 0.3f, 0.55f, 0.45f};  // +x -x +y -y +z -z
        size_t within = 0;
        for (float s : expected) within += s <= depth;
        ASSERT_EQ(lines.size(), within) << "depth " << depth;
        for (const PrismIndex::Line& l : lines) {
            int axis = std::abs(l.normal.x) > 0.5f ? 0 : std::abs(l.normal.y) > 0.5f ? 1 : 2;
            const bool positive = l.normal[axis] > 0;
            EXPECT_NEAR(l.s_mm, expected[2 * axis + (positive ? 0 : 1)], 1e-6f);
            EXPECT_NEAR(l.x_mm[axis], positive ? 1.0f : 0.0f, 1e-6f);
            EXPECT_NEAR(length(l.x_mm - y), l.s_mm, 1e-6f);
        }
    }
    // The prisms know no inside: a point beyond the +x face is on the -x
    // face's line (the caller checks that the segment meets no other
    // surface), and on none beyond the depth.
    PrismIndex index(cube, 2.0f);
    std::vector<PrismIndex::Line> lines;
    index.forEachLine({1.5f, 0.3f, 0.65f}, [&](const PrismIndex::Line& l) { lines.push_back(l); });
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_NEAR(lines[0].s_mm, 1.5f, 1e-6f);
    EXPECT_LT(lines[0].normal.x, -0.5f);
    int count = 0;
    index.forEachLine({2.5f, 0.5f, 0.5f}, [&](const PrismIndex::Line&) { ++count; });
    EXPECT_EQ(count, 0);
}

}  // namespace
}  // namespace pl
