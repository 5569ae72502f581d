#include "media/majorant_grid.h"

#include <algorithm>
#include <limits>

namespace pl {

MajorantGrid::MajorantGrid(const LabelGrid& grid, const std::array<ChannelLut, 3>& luts) {
    const GridFrame& f = grid.frame();
    Vec3i vmaxIncl{f.indexMax().x - 1, f.indexMax().y - 1, f.indexMax().z - 1};
    brickMin_ = brickOf(f.indexMin);
    Vec3i bLast = brickOf(vmaxIncl);
    brickMax_ = {bLast.x + 1, bLast.y + 1, bLast.z + 1};
    Vec3i r{brickMax_.x - brickMin_.x, brickMax_.y - brickMin_.y, brickMax_.z - brickMin_.z};
    size_t count = size_t(r.x) * r.y * r.z;
    if (f.voxelCount() == 0) count = 0;

    constexpr float inf = std::numeric_limits<float>::infinity();
    std::vector<Bounds> b(count);
    for (Bounds& x : b) x = {{-inf, -inf, -inf}, {inf, inf, inf}, kNoLabelYet, kOnlyVoid};
    std::vector<uint32_t> covered(count, 0);
    auto include = [&](size_t i, Label l, uint32_t n) {
        for (int c = 0; c < 3; ++c) {
            float s = luts[c].sigmaT_perMm[l];
            b[i].maxSigmaT[c] = std::max(b[i].maxSigmaT[c], s);
            b[i].minSigmaT[c] = std::min(b[i].minSigmaT[c], s);
        }
        covered[i] += n;
        b[i].see(int(l), grid.voidLabel());
    };

    // Stored tiles and voxels.
    grid.visitRegions([&](const Vec3i& lo, const Vec3i& hi, Label l) {
        Vec3i blo = brickOf(lo), bhi = brickOf(hi);
        for (int bz = blo.z; bz <= bhi.z; ++bz)
            for (int by = blo.y; by <= bhi.y; ++by)
                for (int bx = blo.x; bx <= bhi.x; ++bx) {
                    // Voxels of the region inside this brick.
                    uint64_t n = 1;
                    int bc[3] = {bx, by, bz};
                    for (int a = 0; a < 3; ++a) {
                        int s = std::max(lo[a], bc[a] << kBrickLog2);
                        int e = std::min(hi[a], ((bc[a] + 1) << kBrickLog2) - 1);
                        n *= uint64_t(e - s + 1);
                    }
                    include(brickIndex({bx, by, bz}), l, uint32_t(n));
                }
    });

    // Voxels no stored value covers hold the void label.
    for (int bz = brickMin_.z; bz < brickMax_.z; ++bz)
        for (int by = brickMin_.y; by < brickMax_.y; ++by)
            for (int bx = brickMin_.x; bx < brickMax_.x; ++bx) {
                uint64_t n = 1;
                int bc[3] = {bx, by, bz};
                for (int a = 0; a < 3; ++a) {
                    int s = std::max(f.indexMin[a], bc[a] << kBrickLog2);
                    int e = std::min(vmaxIncl[a], ((bc[a] + 1) << kBrickLog2) - 1);
                    n *= uint64_t(e - s + 1);
                }
                size_t i = brickIndex({bx, by, bz});
                if (covered[i] < n) include(i, grid.voidLabel(), 0);
                for (int c = 0; c < 3; ++c) globalMax_[c] = std::max(globalMax_[c], b[i].maxSigmaT[c]);
            }
    bricks_ = std::move(b);
}

void MajorantGrid::update(const LabelGrid& grid, const std::array<ChannelLut, 3>& luts,
                          const std::vector<Vec3i>& changed) {
    const GridFrame& f = grid.frame();
    const Vec3i lo = f.indexMin, hi = f.indexMax();
    std::vector<uint8_t> done(bricks_.size(), 0);
    constexpr float inf = std::numeric_limits<float>::infinity();
    for (const Vec3i& v : changed) {
        if (!f.contains(v)) continue;
        Vec3i b = brickOf(v);
        size_t i = brickIndex(b);
        if (done[i]) continue;
        done[i] = 1;
        // The brick's voxels inside the frame, one by one.
        Bounds x{{-inf, -inf, -inf}, {inf, inf, inf}, kNoLabelYet, kOnlyVoid};
        for (int z = std::max(lo.z, b.z << kBrickLog2); z < std::min(hi.z, (b.z + 1) << kBrickLog2); ++z)
            for (int y = std::max(lo.y, b.y << kBrickLog2); y < std::min(hi.y, (b.y + 1) << kBrickLog2); ++y)
                for (int xx = std::max(lo.x, b.x << kBrickLog2); xx < std::min(hi.x, (b.x + 1) << kBrickLog2); ++xx) {
                    Label l = grid.label({xx, y, z});
                    for (int c = 0; c < 3; ++c) {
                        x.maxSigmaT[c] = std::max(x.maxSigmaT[c], luts[c].sigmaT_perMm[l]);
                        x.minSigmaT[c] = std::min(x.minSigmaT[c], luts[c].sigmaT_perMm[l]);
                    }
                    x.see(int(l), grid.voidLabel());
                }
        bricks_[i] = x;
    }
    globalMax_ = {0, 0, 0};
    for (const Bounds& x : bricks_)
        for (int c = 0; c < 3; ++c) globalMax_[c] = std::max(globalMax_[c], x.maxSigmaT[c]);
}

}  // namespace pl
