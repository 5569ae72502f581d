// 3D-DDA against brute-force dense stepping on random grids and rays,
// including axis-aligned rays, rays along voxel faces and grazing rays.
#include <gtest/gtest.h>

#include "core/rng.h"
#include "media/dda.h"

namespace pl {
namespace {

Vec3i floorCell(const Vec3f& p) {
    return {int(std::floor(p.x)), int(std::floor(p.y)), int(std::floor(p.z))};
}

// Checks the DDA's segments: contiguous, in order, inside the box, covering
// exactly the clipped ray; and at dense sample points the segment holding t
// names the cell floor(o + d t) (away from cell boundaries, where either
// neighbour is right).
void checkAgainstBruteForce(const Vec3f& o, const Vec3f& d, float tStart, float tEnd,
                            const Vec3i& lo, const Vec3i& hi) {
    std::vector<DdaSegment> segs;
    GridDda dda(o, d, tStart, tEnd, lo, hi);
    DdaSegment s;
    while (dda.next(s)) {
        segs.push_back(s);
        ASSERT_LT(segs.size(), 100000u);
    }
    float t0 = tStart, t1 = tEnd;
    bool hits = clipRayToBox(o, d, lo, hi, t0, t1);

    // Brute force: which cells does dense stepping see inside the box?
    const int steps = 20000;
    std::vector<std::pair<float, Vec3i>> dense;
    for (int i = 0; i < steps; ++i) {
        float t = tStart + (tEnd - tStart) * (i + 0.5f) / steps;
        Vec3i c = floorCell(o + d * t);
        bool inside = c.x >= lo.x && c.y >= lo.y && c.z >= lo.z && c.x < hi.x && c.y < hi.y && c.z < hi.z;
        if (inside) dense.push_back({t, c});
    }
    if (!hits) {
        EXPECT_TRUE(segs.empty());
        // Only boundary-grazing samples may fall inside.
        EXPECT_LE(dense.size(), 2u);
        return;
    }
    ASSERT_FALSE(segs.empty());
    const float tol = 1e-4f * std::max(1.0f, std::abs(t1));
    EXPECT_NEAR(segs.front().t0, t0, tol);
    EXPECT_NEAR(segs.back().t1, t1, tol);
    for (size_t i = 0; i < segs.size(); ++i) {
        const Vec3i& c = segs[i].cell;
        EXPECT_TRUE(c.x >= lo.x && c.y >= lo.y && c.z >= lo.z && c.x < hi.x && c.y < hi.y && c.z < hi.z);
        EXPECT_LE(segs[i].t0, segs[i].t1);
        if (i > 0) {
            EXPECT_EQ(segs[i].t0, segs[i - 1].t1);
            // Consecutive cells are face neighbours.
            const Vec3i& p = segs[i - 1].cell;
            EXPECT_EQ(std::abs(c.x - p.x) + std::abs(c.y - p.y) + std::abs(c.z - p.z), 1);
        }
    }
    size_t k = 0;
    for (const auto& [t, cell] : dense) {
        while (k + 1 < segs.size() && segs[k].t1 <= t) ++k;
        if (t < segs[k].t0 - tol || t > segs[k].t1 + tol) {
            ADD_FAILURE() << "sample t=" << t << " outside every segment";
            return;
        }
        bool nearBoundary = std::min(t - segs[k].t0, segs[k].t1 - t) < tol;
        if (!nearBoundary) {
            ASSERT_EQ(segs[k].cell, cell) << "t=" << t;
        }
    }
}

TEST(Dda, RandomRaysThroughRandomBoxes) {
    Rng rng(42, 1);
    for (int trial = 0; trial < 400; ++trial) {
        Vec3i lo{int(rng.next32() % 20) - 10, int(rng.next32() % 20) - 10, int(rng.next32() % 20) - 10};
        Vec3i hi{lo.x + 1 + int(rng.next32() % 30), lo.y + 1 + int(rng.next32() % 30), lo.z + 1 + int(rng.next32() % 30)};
        Vec3f o{rng.uniform() * 60 - 30, rng.uniform() * 60 - 30, rng.uniform() * 60 - 30};
        Vec3f d = normalize(Vec3f(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f));
        checkAgainstBruteForce(o, d, 0.0f, 100.0f, lo, hi);
    }
}

TEST(Dda, RaysStartingInsideAndStoppingEarly) {
    Rng rng(5, 9);
    for (int trial = 0; trial < 200; ++trial) {
        Vec3i lo{0, 0, 0}, hi{16, 16, 16};
        Vec3f o{rng.uniform() * 16, rng.uniform() * 16, rng.uniform() * 16};
        Vec3f d = normalize(Vec3f(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f));
        checkAgainstBruteForce(o, d, 0.0f, rng.uniform() * 10, lo, hi);
    }
}

TEST(Dda, AxisAlignedRaysWithZeroComponents) {
    Vec3i lo{-3, -3, -3}, hi{5, 6, 7};
    for (int a = 0; a < 3; ++a)
        for (float sign : {1.0f, -1.0f}) {
            Vec3f d(0, 0, 0);
            d[a] = sign;
            Vec3f o(0.3f, 0.6f, 0.9f);
            o[a] = sign > 0 ? -20.0f : 20.0f;
            checkAgainstBruteForce(o, d, 0.0f, 50.0f, lo, hi);
            // Exactly on voxel faces: the other two coordinates are integers.
            Vec3f onFace(1.0f, 2.0f, -1.0f);
            onFace[a] = o[a];
            checkAgainstBruteForce(onFace, d, 0.0f, 50.0f, lo, hi);
            // Visits exactly the cells of the line.
            GridDda dda(onFace, d, 0.0f, 50.0f, lo, hi);
            DdaSegment s;
            int count = 0;
            while (dda.next(s)) ++count;
            EXPECT_EQ(count, hi[a] - lo[a]);
        }
}

TEST(Dda, GrazingRays) {
    Rng rng(77, 3);
    Vec3i lo{0, 0, 0}, hi{32, 32, 32};
    for (int trial = 0; trial < 100; ++trial) {
        // Almost parallel to a face, at almost integer height.
        Vec3f d = normalize(Vec3f(1.0f, 1e-4f * (rng.uniform() - 0.5f), 1e-3f * rng.uniform()));
        Vec3f o(-5.0f, 3.0f + 1e-5f * (rng.uniform() - 0.5f), float(int(rng.next32() % 32)));
        checkAgainstBruteForce(o, d, 0.0f, 60.0f, lo, hi);
        // Along the box's own boundary plane.
        checkAgainstBruteForce({-5.0f, 0.0f, 7.5f}, normalize(Vec3f(1, 0, 1e-6f)), 0.0f, 60.0f, lo, hi);
    }
}

TEST(Dda, MissingTheBoxYieldsNothing) {
    GridDda dda({-5, -5, -5}, normalize(Vec3f(-1, 0.2f, 0.1f)), 0, 100, {0, 0, 0}, {4, 4, 4});
    DdaSegment s;
    EXPECT_FALSE(dda.next(s));
}

}  // namespace
}  // namespace pl
