// The surface clearance is a lower bound of the distance to the boundary
// everywhere in the frame (else printpt would miss boundary crossings), its
// upper bound one where known (printpt's ball tests trust both), and
// deep inside it is large enough to skip queries.
#include <gtest/gtest.h>

#include "core/rng.h"
#include "core/surface_clearance.h"
#include "media/majorant_grid.h"
#include "test_util.h"

namespace pl {
namespace {

TEST(SurfaceClearance, IsALowerBoundOfTheDistanceToTheBoundary) {
    // Anisotropic voxels, a frame away from the origin whose size is not a
    // multiple of the brick, and a mesh that reaches the frame's faces.
    GridFrame frame;
    frame.indexMin = {-7, 3, 11};
    frame.resolution = {61, 45, 83};
    frame.voxelSize_mm = kPrinterVoxel_mm;
    frame.cornerMin_mm = {12.5f, -3.0f, 40.0f};
    Point3f hi = frame.cornerMax_mm();
    Point3f lo = frame.cornerMin_mm + Vec3f(0.3f, 0.0f, 0.2f);
    Geometry geometry(test::boxMesh(lo, hi));
    SurfaceClearance clearance(geometry, frame);

    Rng rng(7, 0);
    int positive = 0, known = 0;
    for (int i = 0; i < 200000; ++i) {
        Point3f p{frame.cornerMin_mm.x + rng.uniform() * (hi.x - frame.cornerMin_mm.x),
                  frame.cornerMin_mm.y + rng.uniform() * (hi.y - frame.cornerMin_mm.y),
                  frame.cornerMin_mm.z + rng.uniform() * (hi.z - frame.cornerMin_mm.z)};
        auto c = geometry.closestPoint(p, 1e3f);
        ASSERT_TRUE(c.has_value());
        float bound = clearance.at(p);
        ASSERT_LE(bound, c->distance_mm) << "at " << p.x << "," << p.y << "," << p.z;
        positive += bound > 0.0f;
        // The upper bound, where the block's query found the boundary.
        float upper = clearance.upperBoundAt(p);
        ASSERT_GE(upper, c->distance_mm) << "at " << p.x << "," << p.y << "," << p.z;
        known += std::isfinite(upper);
    }
    // Within its search radius (four block diagonals, ~1.5 mm) of the
    // boundary, which is most of this box, the upper bound is known.
    EXPECT_GT(known, 200000 / 2);
    // The box is 2.5 x 3.8 x 2.0 mm and a brick's half diagonal 0.39 mm:
    // much of the inside must be cleared.
    EXPECT_GT(positive, 200000 / 5);
    // Outside the frame nothing is known.
    EXPECT_EQ(clearance.at(frame.cornerMin_mm - Vec3f(0.01f, 0, 0)), 0.0f);
    EXPECT_EQ(clearance.at(hi + Vec3f(0, 0, 0.01f)), 0.0f);
}

// The solid label of a brick is its one label other than void, whatever the
// void voxels around it (the skin between the mesh and the voxels).
TEST(MajorantGrid, SolidLabelIgnoresVoid) {
    const Vec3i res{45, 37, 29};
    LabelGrid grid = test::boxGrid(res, {0.05f, 0.05f, 0.05f}, [](const Vec3i& v) {
        if (v.x < 13) return test::kTestVoid;
        if (v.x == 30 && v.y % 9 == 0 && v.z % 7 == 0) return Label(3);  // sparse dots
        return Label(4);
    });
    std::array<ChannelLut, 3> luts;
    for (ChannelLut& lut : luts)
        for (int l = 0; l < 256; ++l) lut.sigmaT_perMm[l] = float(l + 1);
    MajorantGrid maj(grid, luts);
    int counts[3] = {0, 0, 0};  // only void, white (and void), mixed
    for (int bz = maj.brickMin().z; bz < maj.brickMax().z; ++bz)
        for (int by = maj.brickMin().y; by < maj.brickMax().y; ++by)
            for (int bx = maj.brickMin().x; bx < maj.brickMax().x; ++bx) {
                int expected = MajorantGrid::kOnlyVoid;
                for (int z = bz * 8; z < std::min(res.z, bz * 8 + 8); ++z)
                    for (int y = by * 8; y < std::min(res.y, by * 8 + 8); ++y)
                        for (int x = bx * 8; x < std::min(res.x, bx * 8 + 8); ++x) {
                            int l = grid.label({x, y, z});
                            if (l == grid.voidLabel()) continue;
                            expected = expected == MajorantGrid::kOnlyVoid || expected == l ? l : -1;
                        }
                ASSERT_EQ(maj.solidLabel({bx, by, bz}), expected) << bx << "," << by << "," << bz;
                counts[expected == MajorantGrid::kOnlyVoid ? 0 : expected == 4 ? 1 : 2] += 1;
            }
    // Bricks of each kind, including white next to void (x from 8 to 15).
    EXPECT_GT(counts[0], 0);
    EXPECT_GT(counts[1], 0);
    EXPECT_GT(counts[2], 0);
}

}  // namespace
}  // namespace pl

namespace pl {
namespace {

// Updating the bricks of relabelled voxels gives what a full build of the
// relabelled grid gives: bounds, sole labels, global maximum; or, with
// majorants that only rise, the larger of the majorants before and after.
TEST(MajorantGrid, UpdateOfChangedVoxelsEqualsAFullBuild) {
    const Vec3i res{45, 37, 29};  // not a multiple of the brick size
    LabelGrid grid = test::boxGrid(res, {0.1f, 0.1f, 0.1f}, [](const Vec3i& v) { return Label(v.x < 20 ? 4 : 1); });
    std::array<ChannelLut, 3> luts;
    for (int c = 0; c < 3; ++c)
        for (int l = 0; l < 256; ++l) luts[c].sigmaT_perMm[l] = float((l + 1) * (c + 1));
    MajorantGrid maj(grid, luts);
    Rng rng = Rng::forPath(11, 0, 0, 0);
    std::vector<LabelGrid::Change> changes;
    std::vector<Vec3i> voxels;
    for (int k = 0; k < 200; ++k) {
        Vec3i v{int(rng.uniform() * res.x), int(rng.uniform() * res.y), int(rng.uniform() * res.z)};
        Label l = Label(int(rng.uniform() * 4) == 0 ? test::kTestVoid : int(rng.uniform() * 4));
        changes.push_back({v, l});
        voxels.push_back(v);
    }
    // Also empty a whole brick's worth, and refill a corner brick with one label.
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                changes.push_back({{x + 24, y + 8, z + 8}, test::kTestVoid});
                changes.push_back({{x, y, z}, Label(2)});
                voxels.push_back({x + 24, y + 8, z + 8});
                voxels.push_back({x, y, z});
            }
    LabelGrid next = grid.withChanges(changes);
    const MajorantGrid before = maj;
    MajorantGrid rising = maj;
    maj.update(next, luts, voxels);
    rising.update(next, luts, voxels, true);
    MajorantGrid full(next, luts);
    for (int bz = full.brickMin().z; bz < full.brickMax().z; ++bz)
        for (int by = full.brickMin().y; by < full.brickMax().y; ++by)
            for (int bx = full.brickMin().x; bx < full.brickMax().x; ++bx) {
                Vec3i b{bx, by, bz};
                for (int c = 0; c < 3; ++c) {
                    EXPECT_EQ(maj.maxSigmaT(b, c), full.maxSigmaT(b, c));
                    EXPECT_EQ(maj.minSigmaT(b, c), full.minSigmaT(b, c));
                    // Majorants that only rise: the larger of before and now.
                    EXPECT_EQ(rising.maxSigmaT(b, c), std::max(before.maxSigmaT(b, c), full.maxSigmaT(b, c)));
                    EXPECT_EQ(rising.minSigmaT(b, c), full.minSigmaT(b, c));
                }
                bool raised = false;
                for (int c = 0; c < 3; ++c) raised = raised || before.maxSigmaT(b, c) > full.maxSigmaT(b, c);
                EXPECT_EQ(rising.soleLabel(b), raised ? -1 : full.soleLabel(b)) << bx << " " << by << " " << bz;
                EXPECT_EQ(maj.soleLabel(b), full.soleLabel(b)) << bx << " " << by << " " << bz;
                EXPECT_EQ(maj.solidLabel(b), full.solidLabel(b)) << bx << " " << by << " " << bz;
            }
    for (int c = 0; c < 3; ++c) EXPECT_EQ(maj.globalMaxSigmaT(c), full.globalMaxSigmaT(c));
}

}  // namespace
}  // namespace pl
