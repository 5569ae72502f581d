// The label grid's surface voxels against brute force over every voxel.
#include <gtest/gtest.h>

#include <vector>

#include "media/label_grid.h"

namespace pl {
namespace {

// The surface voxels of a grid with every kind of storage: tiles of 8^3
// and 128^3 (a pruned block of one resin), leaves, a void cavity, a plate
// one voxel thick, voxels stored outside the frame (not in it) and a
// frame that starts off the leaves' alignment and cuts the block.
TEST(LabelGrid, SurfaceVoxelsAreTheBruteForceOnes) {
    GridFrame f;
    f.indexMin = {-5, -10, -20};
    f.resolution = {290, 280, 300};
    f.voxelSize_mm = {0.05f, 0.05f, 0.05f};
    f.cornerMin_mm = {0, 0, 0};
    const Label voidLabel = 0;
    auto inBlock = [](int x, int y, int z) { return x >= -8 && x < 285 && y >= -3 && y < 262 && z >= -20 && z < 270; };
    auto inCavity = [](int x, int y, int z) {
        const int dx = x - 200, dy = y - 150, dz = z - 170;
        return dx * dx + dy * dy + dz * dz < 30 * 30;
    };
    auto labelOf = [&](int x, int y, int z) -> Label {
        if (inBlock(x, y, z)) {
            if (inCavity(x, y, z)) return voidLabel;
            if (z < 0 && (x * 7 + y * 13 + z * 3) % 5 == 0) return 3;  // a grain: leaves
            return 1;
        }
        if (y == 100 && x >= 10 && x < 60 && z >= 270 && z < 279) return 2;  // the plate above the block
        return voidLabel;
    };
    LabelGridBuilder builder(f, voidLabel);
    for (int z = -25; z < 285; ++z) {
        for (int y = -15; y < 275; ++y)
            for (int x = -10; x < 290; ++x) {
                const Label l = labelOf(x, y, z);
                if (l != voidLabel) builder.set({x, y, z}, l);
            }
        if (z % 16 == 15) builder.compact();
    }
    const LabelGrid grid = builder.finish();
    const Vec3i hi = f.indexMax();
    auto labelIn = [&](int x, int y, int z) -> Label {
        const bool inFrame = x >= f.indexMin.x && y >= f.indexMin.y && z >= f.indexMin.z && x < hi.x && y < hi.y && z < hi.z;
        return inFrame ? labelOf(x, y, z) : voidLabel;
    };
    std::vector<SurfaceVoxel> expected;
    for (int z = f.indexMin.z; z < hi.z; ++z)
        for (int y = f.indexMin.y; y < hi.y; ++y)
            for (int x = f.indexMin.x; x < hi.x; ++x) {
                if (labelIn(x, y, z) == voidLabel) continue;
                uint8_t exposed = 0;
                for (int k = 0; k < 6; ++k) {
                    const Vec3i& o = kFaceDirections[k];
                    if (labelIn(x + o.x, y + o.y, z + o.z) == voidLabel) exposed |= uint8_t(1u << k);
                }
                if (exposed) expected.push_back({{x, y, z}, exposed});
            }
    const std::vector<SurfaceVoxel> found = grid.surfaceVoxels();
    ASSERT_EQ(found.size(), expected.size());
    size_t wrong = 0;
    for (size_t i = 0; i < found.size(); ++i)
        if (!(found[i].voxel == expected[i].voxel) || found[i].exposedFaces != expected[i].exposedFaces) ++wrong;
    EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace pl
