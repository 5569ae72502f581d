// Halftoning by thresholds (prepare/halftone.h, prepare/threshold_matrix.h):
// the matrix holds every rank once and spreads any share of its voxels
// apart; a tile reproduces a mixture's fractions; a request that moves a
// little relabels as few voxels as the move's size says, where error
// diffusion relabels a large part of the block.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "prepare/halftone.h"
#include "prepare/threshold_matrix.h"

namespace pl {
namespace {


// Mean distance (mm) from each point to its nearest other on the tile's torus.
double meanNearestDistance_mm(const std::vector<Vec3i>& points, const Vec3i& tile, const Vec3f& voxel_mm) {
    double sum = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        double best = 1e30;
        for (size_t j = 0; j < points.size(); ++j) {
            if (i == j) continue;
            double d2 = 0;
            for (int a = 0; a < 3; ++a) {
                int d = std::abs(points[i][a] - points[j][a]);
                d = std::min(d, tile[a] - d);
                d2 += double(d * voxel_mm[a]) * double(d * voxel_mm[a]);
            }
            best = std::min(best, d2);
        }
        sum += std::sqrt(best);
    }
    return sum / double(points.size());
}

std::vector<Vec3i> voxelsOfTile(const Vec3i& tile) {
    std::vector<Vec3i> v;
    for (int z = 0; z < tile.z; ++z)
        for (int y = 0; y < tile.y; ++y)
            for (int x = 0; x < tile.x; ++x) v.push_back({x, y, z});
    return v;
}

TEST(ThresholdMatrix, HoldsEveryRankOnceAndIsTheSameWhenMadeAgain) {
    const Vec3i tile{16, 8, 24};
    const ThresholdMatrix a(tile, kPrinterVoxel_mm), b(tile, kPrinterVoxel_mm);
    const std::vector<Vec3i> voxels = voxelsOfTile(tile);
    std::vector<int> seen(voxels.size(), 0);
    for (const Vec3i& v : voxels) {
        ASSERT_EQ(a.at(v), b.at(v));
        const double rank = double(a.at(v)) * double(voxels.size()) - 0.5;
        const long r = std::lround(rank);
        ASSERT_NEAR(rank, double(r), 1e-2);
        ASSERT_GE(r, 0);
        ASSERT_LT(size_t(r), voxels.size());
        seen[size_t(r)] += 1;
        // The tile repeats.
        EXPECT_EQ(a.at(v), a.at(v + Vec3i{tile.x, -tile.y, 3 * tile.z}));
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
}

// The voxels below a threshold, and those of a band of thresholds (a middle
// material's share), lie further apart than as many voxels at random.
TEST(ThresholdMatrix, SpreadsAnyShareOfItsVoxelsApart) {
    const ThresholdMatrix& m = ThresholdMatrix::forVoxel(kPrinterVoxel_mm);
    const Vec3i tile = m.tile();
    const std::vector<Vec3i> voxels = voxelsOfTile(tile);
    Rng rng(11, 3);
    for (auto [lo, hi] : {std::pair{0.0f, 0.05f}, std::pair{0.40f, 0.45f}, std::pair{0.95f, 1.0f}}) {
        std::vector<Vec3i> chosen, random;
        for (const Vec3i& v : voxels)
            if (m.at(v) >= lo && m.at(v) < hi) chosen.push_back(v);
        while (random.size() < chosen.size()) random.push_back(voxels[rng.next32() % voxels.size()]);
        const double blue = meanNearestDistance_mm(chosen, tile, kPrinterVoxel_mm);
        const double white = meanNearestDistance_mm(random, tile, kPrinterVoxel_mm);
        EXPECT_GT(blue, 1.3 * white) << "thresholds [" << lo << ", " << hi << ")";
    }
}

// Counts of each material over one tile of a uniform mixture.
std::array<int, kPrintMaterials> countsOverTile(const ThresholdMatrix& m, const MaterialFractions& f) {
    std::array<int, kPrintMaterials> counts{};
    for (const Vec3i& v : voxelsOfTile(m.tile())) counts[size_t(materialAtThreshold(f, m.at(v)))] += 1;
    return counts;
}

TEST(Halftone, ThresholdsReproduceAMixtureTileByTile) {
    const ThresholdMatrix& m = ThresholdMatrix::forVoxel(kPrinterVoxel_mm);
    const double n = double(m.tile().x) * m.tile().y * m.tile().z;
    for (RGB color : {RGB{0.6f, 0.3f, 0.8f}, RGB{0.9f, 0.85f, 0.2f}, RGB{0.15f, 0.5f, 0.45f}, RGB{0.02f, 0.02f, 0.02f}}) {
        const MaterialFractions f = fractionsForColor(color);
        const std::array<int, kPrintMaterials> counts = countsOverTile(m, f);
        for (int k = 0; k < kPrintMaterials; ++k) EXPECT_NEAR(counts[size_t(k)], f[size_t(k)] * n, 2.0) << "material " << k;
    }
    // A pure material everywhere; an empty mixture takes the lightest.
    EXPECT_EQ(countsOverTile(m, MaterialFractions{0, 0, 0, 1, 0})[3], int(n));
    EXPECT_EQ(countsOverTile(m, MaterialFractions{0, 0, 0, 0, 0})[4], int(n));
}

// A move of the mixture by d relabels the voxels whose thresholds lie
// between the old and the new boundaries of the materials' shares: about
// the boundaries' moves times the voxels. Error diffusion of the same block
// relabels far more (each change travels along the rest of the slice).
TEST(Halftone, ThresholdsRelabelAsFewVoxelsAsTheMoveSays) {
    const ThresholdMatrix& m = ThresholdMatrix::forVoxel(kPrinterVoxel_mm);
    const std::vector<Vec3i> voxels = voxelsOfTile(m.tile());
    const MaterialFractions before{0.20f, 0.15f, 0.10f, 0.05f, 0.50f};
    const MaterialFractions after{0.21f, 0.15f, 0.10f, 0.05f, 0.49f};  // 1 % white to cyan
    // Shares from the lightest: white [0, .5), yellow, cyan: both boundaries
    // before cyan's move down by 0.01.
    const double expected = 2 * 0.01 * double(voxels.size());
    size_t relabelled = 0;
    for (const Vec3i& v : voxels) relabelled += materialAtThreshold(before, m.at(v)) != materialAtThreshold(after, m.at(v));
    EXPECT_NEAR(double(relabelled), expected, 4.0);

    const Vec3i& t = m.tile();
    auto diffuse = [&](const MaterialFractions& f) {
        ErrorDiffusionHalftoner h(t.x, t.y);
        std::vector<MaterialFractions> targets(size_t(t.x) * t.y, f);
        std::vector<uint8_t> active(targets.size(), 1), chosen, all;
        for (int z = 0; z < t.z; ++z) {
            h.halftoneSlice(z, targets, active, chosen);
            all.insert(all.end(), chosen.begin(), chosen.end());
        }
        return all;
    };
    const std::vector<uint8_t> a = diffuse(before), b = diffuse(after);
    size_t diffused = 0;
    for (size_t i = 0; i < a.size(); ++i) diffused += a[i] != b[i];
    EXPECT_GT(double(diffused), 10 * expected) << "error diffusion relabelled " << diffused;
}

// With hysteresis h a voxel keeps its material while that material's share
// comes within h of its threshold: a move smaller than h relabels nothing,
// a move d > h relabels the voxels beyond h of the new boundaries.
TEST(Halftone, HysteresisKeepsAMaterialWhileItsShareIsNear) {
    const ThresholdMatrix& m = ThresholdMatrix::forVoxel(kPrinterVoxel_mm);
    const std::vector<Vec3i> voxels = voxelsOfTile(m.tile());
    const MaterialFractions before{0.20f, 0.15f, 0.10f, 0.05f, 0.50f};
    const float h = 0.01f;
    for (float d : {0.005f, 0.03f}) {
        MaterialFractions after = before;
        after[0] += d;  // white to cyan: the two boundaries before cyan's move by d
        after[4] -= d;
        size_t relabelled = 0;
        for (const Vec3i& v : voxels) {
            const int now = materialAtThreshold(before, m.at(v));
            relabelled += materialAtThreshold(after, m.at(v), now, h) != now;
        }
        const double expected = 2 * std::max(0.0, double(d - h)) * double(voxels.size());
        EXPECT_NEAR(double(relabelled), expected, 4.0) << "move " << d;
    }
    EXPECT_EQ(printMaterialOf(kPrintMaterialLabel[2]), 2);
    EXPECT_EQ(printMaterialOf(Label(6)), -1);
}

}  // namespace
}  // namespace pl
