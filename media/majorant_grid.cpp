#include "media/majorant_grid.h"

#include <algorithm>
#include <limits>

namespace pl {

MajorantGrid::MajorantGrid(const LabelGrid& grid, const std::array<ChannelLut, 3>& luts) {
    const GridFrame& f = grid.frame();
    const Vec3i vmaxIncl{f.indexMax().x - 1, f.indexMax().y - 1, f.indexMax().z - 1};
    brickMin_ = brickOf(f.indexMin);
    Vec3i bLast = brickOf(vmaxIncl);
    brickMax_ = {bLast.x + 1, bLast.y + 1, bLast.z + 1};
    Vec3i r{brickMax_.x - brickMin_.x, brickMax_.y - brickMin_.y, brickMax_.z - brickMin_.z};
    size_t count = size_t(r.x) * r.y * r.z;
    if (f.voxelCount() == 0) count = 0;

    std::vector<Bounds> b(count, Bounds::none());
    grid.visitBlockLabels(kBrickLog2, {0, 0, 0}, [&](const Vec3i& brick, Label l) {
        b[brickIndex(brick)].include(l, luts, grid.voidLabel());
    });
    bricks_ = std::move(b);
    boundWholeGrid();
}

void MajorantGrid::boundWholeGrid() {
    wholeGrid_.maxSigmaT = {0, 0, 0};
    for (const Bounds& x : bricks_)
        for (int c = 0; c < 3; ++c) wholeGrid_.maxSigmaT[c] = std::max(wholeGrid_.maxSigmaT[c], x.maxSigmaT[c]);
}

void MajorantGrid::update(const LabelGrid& grid, const std::array<ChannelLut, 3>& luts,
                          const std::vector<Vec3i>& changed, bool majorantsOnlyRise) {
    const GridFrame& f = grid.frame();
    const Vec3i lo = f.indexMin, hi = f.indexMax();
    std::vector<uint8_t> done(bricks_.size(), 0);
    for (const Vec3i& v : changed) {
        if (!f.contains(v)) continue;
        Vec3i b = brickOf(v);
        size_t i = brickIndex(b);
        if (done[i]) continue;
        done[i] = 1;
        // The brick's voxels inside the frame, one by one.
        Bounds x = Bounds::none();
        for (int z = std::max(lo.z, b.z << kBrickLog2); z < std::min(hi.z, (b.z + 1) << kBrickLog2); ++z)
            for (int y = std::max(lo.y, b.y << kBrickLog2); y < std::min(hi.y, (b.y + 1) << kBrickLog2); ++y)
                for (int xx = std::max(lo.x, b.x << kBrickLog2); xx < std::min(hi.x, (b.x + 1) << kBrickLog2); ++xx)
                    x.include(grid.label({xx, y, z}), luts, grid.voidLabel());
        if (majorantsOnlyRise)
            for (int c = 0; c < 3; ++c)
                if (bricks_[i].maxSigmaT[c] > x.maxSigmaT[c]) {
                    x.maxSigmaT[c] = bricks_[i].maxSigmaT[c];
                    // Above the sole label's extinction, a tentative
                    // collision is no longer always real.
                    x.soleLabel = -1;
                }
        bricks_[i] = x;
    }
    boundWholeGrid();
}

}  // namespace pl
