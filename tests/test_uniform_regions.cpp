// The uniform regions printpt walks balls in: each cell's label and radius
// match brute force, every ball they promise holds only the cell's label
// (checked on the voxels themselves), and an update of relabelled voxels
// gives what a full build gives.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/rng.h"
#include "core/sampling.h"
#include "media/uniform_regions.h"
#include "test_util.h"

namespace pl {
namespace {

constexpr int kCell = UniformRegions::kCellSize;

// White in a void margin, with a magenta slab and scattered black voxels, on
// anisotropic voxels, a frame away from the index origin whose size is not a
// multiple of the cell.
LabelGrid testGrid(GridFrame& f) {
    f.indexMin = {-3, 5, 2};
    f.resolution = {75, 49, 61};
    f.voxelSize_mm = kPrinterVoxel_mm;
    std::vector<Label> labels(f.voxelCount());
    size_t i = 0;
    for (int z = 0; z < f.resolution.z; ++z)
        for (int y = 0; y < f.resolution.y; ++y)
            for (int x = 0; x < f.resolution.x; ++x) {
                Label l = 4;
                if (x < 3 || y > 45 || z < 2) l = test::kTestVoid;
                else if (x >= 50 && x < 58) l = 1;
                else if ((uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ uint32_t(z) * 83492791u) % 20000 == 0) l = 3;
                labels[i++] = l;
            }
    return LabelGrid::fromDense(f, labels, test::kTestVoid);
}

// The cell's label counted from its voxels (frame-relative cell index).
int labelOfCell(const LabelGrid& grid, const GridFrame& f, const Vec3i& c) {
    int label = -2;
    for (int z = c.z * kCell; z < std::min(f.resolution.z, c.z * kCell + kCell); ++z)
        for (int y = c.y * kCell; y < std::min(f.resolution.y, c.y * kCell + kCell); ++y)
            for (int x = c.x * kCell; x < std::min(f.resolution.x, c.x * kCell + kCell); ++x) {
                int l = grid.label({f.indexMin.x + x, f.indexMin.y + y, f.indexMin.z + z});
                label = label == -2 || label == l ? l : UniformRegions::kMixed;
            }
    return label;
}

Vec3i firstVoxel(const GridFrame& f, const Vec3i& c) {
    return {f.indexMin.x + c.x * kCell, f.indexMin.y + c.y * kCell, f.indexMin.z + c.z * kCell};
}

TEST(UniformRegions, LabelsAndRadiiMatchBruteForce) {
    GridFrame f;
    LabelGrid grid = testGrid(f);
    UniformRegions regions(grid);
    const Vec3i n = regions.cells();
    std::vector<Vec3i> cells;
    std::vector<int> labels;
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                cells.push_back({x, y, z});
                labels.push_back(labelOfCell(grid, f, {x, y, z}));
            }
    int deep = 0;
    for (size_t i = 0; i < cells.size(); ++i) {
        const Vec3i& c = cells[i];
        const UniformRegions::Cell got = regions.at(firstVoxel(f, c));
        ASSERT_EQ(got.label, labels[i]) << c.x << "," << c.y << "," << c.z;
        // The gap between the cell's box and every cell of another label
        // (or mixed), and the frame's edge; none for void.
        float expected = 0.0f;
        if (labels[i] >= 0 && labels[i] != test::kTestVoid) {
            expected = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a) {
                const int first = c[a] * kCell, end = first + kCell;
                expected = std::min(expected, float(std::max(0, std::min(first, f.resolution[a] - end))) *
                                                  f.voxelSize_mm[a]);
            }
            for (size_t j = 0; j < cells.size(); ++j) {
                if (labels[j] == labels[i]) continue;
                float gap2 = 0.0f;
                for (int a = 0; a < 3; ++a) {
                    float g = float(std::max(0, std::abs(cells[j][a] - c[a]) - 1)) * kCell * f.voxelSize_mm[a];
                    gap2 += g * g;
                }
                expected = std::min(expected, std::sqrt(gap2));
            }
        }
        expected = std::min(expected, UniformRegions::kMaxRadius_mm);
        ASSERT_NEAR(got.radius_mm, expected, 1e-5f) << c.x << "," << c.y << "," << c.z;
        deep += expected >= 0.5f;
    }
    EXPECT_GT(deep, 20);  // the test must see cells with a real radius
    // Outside the frame: nothing.
    EXPECT_EQ(regions.at({f.indexMin.x - 1, f.indexMin.y, f.indexMin.z}).radius_mm, 0.0f);
    EXPECT_EQ(regions.at(f.indexMax()).label, UniformRegions::kMixed);
}

TEST(UniformRegions, EveryBallHoldsOnlyTheCellsLabel) {
    GridFrame f;
    LabelGrid grid = testGrid(f);
    UniformRegions regions(grid);
    // Random points of random voxels, random points in the ball the cell
    // promises around them: the voxel there holds the same label.
    Rng rng(3, 0);
    int checked = 0;
    for (int i = 0; i < 200000; ++i) {
        Vec3f cell_coords;  // frame-relative, in voxels
        for (int a = 0; a < 3; ++a) cell_coords[a] = rng.uniform() * float(f.resolution[a]);
        Vec3i v;
        for (int a = 0; a < 3; ++a) v[a] = f.indexMin[a] + std::min(int(cell_coords[a]), f.resolution[a] - 1);
        const UniformRegions::Cell cell = regions.at(v);
        if (cell.radius_mm <= 0.0f) continue;
        const Vec3f d = sampleHG({0, 0, 1}, 0.0f, rng.uniform(), rng.uniform()).dOut;  // uniform
        const float r_mm = 0.999f * cell.radius_mm * std::cbrt(rng.uniform());
        Vec3i w;
        for (int a = 0; a < 3; ++a) {
            const float q = cell_coords[a] + d[a] * r_mm / f.voxelSize_mm[a];
            ASSERT_TRUE(q >= 0.0f && q < float(f.resolution[a])) << "the ball leaves the frame";
            w[a] = f.indexMin[a] + int(q);
        }
        ASSERT_EQ(int(grid.label(w)), cell.label) << "ball around voxel " << v.x << "," << v.y << "," << v.z;
        ++checked;
    }
    EXPECT_GT(checked, 50000);
}

TEST(UniformRegions, UpdateOfChangedVoxelsEqualsAFullBuild) {
    GridFrame f;
    LabelGrid grid = testGrid(f);
    UniformRegions regions(grid);
    Rng rng(11, 0);
    std::vector<LabelGrid::Change> changes;
    std::vector<Vec3i> voxels;
    auto change = [&](const Vec3i& v, Label l) {
        changes.push_back({v, l});
        voxels.push_back(v);
    };
    for (int k = 0; k < 300; ++k) {
        Vec3i v;
        for (int a = 0; a < 3; ++a) v[a] = f.indexMin[a] + int(rng.uniform() * float(f.resolution[a]));
        change(v, Label(int(rng.uniform() * 4) == 0 ? test::kTestVoid : int(rng.uniform() * 5)));
    }
    // A whole cell emptied, another filled with one label.
    for (int z = 0; z < kCell; ++z)
        for (int y = 0; y < kCell; ++y)
            for (int x = 0; x < kCell; ++x) {
                change(firstVoxel(f, {10, 5, 7}) + Vec3i{x, y, z}, test::kTestVoid);
                change(firstVoxel(f, {0, 0, 0}) + Vec3i{x, y, z}, Label(2));
            }
    LabelGrid next = grid.withChanges(changes);
    regions.update(next, voxels);
    UniformRegions full(next);
    for (int z = 0; z < f.resolution.z; z += kCell)
        for (int y = 0; y < f.resolution.y; y += kCell)
            for (int x = 0; x < f.resolution.x; x += kCell) {
                const Vec3i v = f.indexMin + Vec3i{x, y, z};
                ASSERT_EQ(regions.at(v).label, full.at(v).label) << x << "," << y << "," << z;
                ASSERT_EQ(regions.at(v).radius_mm, full.at(v).radius_mm) << x << "," << y << "," << z;
            }
    EXPECT_EQ(full.at(firstVoxel(f, {0, 0, 0})).label, 2);
}

}  // namespace
}  // namespace pl
