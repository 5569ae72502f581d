#include "media/brick_labels.h"

#include <algorithm>

namespace pl {

namespace {
constexpr int kB = MajorantGrid::kBrickSize;
constexpr size_t kBrickVoxels = size_t(kB) * kB * kB;
}  // namespace

BrickLabels::BrickLabels(const LabelGrid& grid, const MajorantGrid& majorants)
    : brickMin_(majorants.brickMin()),
      brickCount_{majorants.brickMax().x - brickMin_.x, majorants.brickMax().y - brickMin_.y,
                  majorants.brickMax().z - brickMin_.z} {
    if (grid.frame().voxelCount() == 0) return;
    slots_.assign(size_t(brickCount_.x) * brickCount_.y * brickCount_.z, 0);
    uint32_t mixed = 0;
    for (int z = 0; z < brickCount_.z; ++z)
        for (int y = 0; y < brickCount_.y; ++y)
            for (int x = 0; x < brickCount_.x; ++x) {
                const Vec3i b{brickMin_.x + x, brickMin_.y + y, brickMin_.z + z};
                const int sole = majorants.soleLabel(b);
                slots_[brickIndex(b)] = sole >= 0 ? kOneLabel | uint32_t(sole) : mixed++;
            }
    voxels_.assign(size_t(mixed) * kBrickVoxels, grid.voidLabel());
    // Stored tiles and voxels, written into the bricks of several labels.
    grid.visitRegions([&](const Vec3i& lo, const Vec3i& hi, Label label) {
        const Vec3i blo = MajorantGrid::brickOf(lo), bhi = MajorantGrid::brickOf(hi);
        for (int bz = blo.z; bz <= bhi.z; ++bz)
            for (int by = blo.y; by <= bhi.y; ++by)
                for (int bx = blo.x; bx <= bhi.x; ++bx) {
                    const uint32_t slot = slots_[brickIndex({bx, by, bz})];
                    if (slot & kOneLabel) continue;
                    Label* brick = &voxels_[size_t(slot) * kBrickVoxels];
                    for (int z = std::max(lo.z, bz * kB); z <= std::min(hi.z, bz * kB + kB - 1); ++z)
                        for (int y = std::max(lo.y, by * kB); y <= std::min(hi.y, by * kB + kB - 1); ++y)
                            for (int x = std::max(lo.x, bx * kB); x <= std::min(hi.x, bx * kB + kB - 1); ++x)
                                brick[((z & (kB - 1)) * kB + (y & (kB - 1))) * kB + (x & (kB - 1))] = label;
                }
    });
}

void BrickLabels::expand(const LabelGrid& grid, const Vec3i& b) {
    const uint32_t slot = uint32_t(voxels_.size() / kBrickVoxels);
    voxels_.resize(voxels_.size() + kBrickVoxels, grid.voidLabel());
    Label* brick = &voxels_[size_t(slot) * kBrickVoxels];
    const Vec3i lo = grid.frame().indexMin, hi = grid.frame().indexMax();
    for (int z = std::max(lo.z, b.z * kB); z < std::min(hi.z, b.z * kB + kB); ++z)
        for (int y = std::max(lo.y, b.y * kB); y < std::min(hi.y, b.y * kB + kB); ++y)
            for (int x = std::max(lo.x, b.x * kB); x < std::min(hi.x, b.x * kB + kB); ++x)
                brick[((z & (kB - 1)) * kB + (y & (kB - 1))) * kB + (x & (kB - 1))] = grid.label({x, y, z});
    slots_[brickIndex(b)] = slot;
}

void BrickLabels::update(const LabelGrid& grid, const MajorantGrid& majorants, const std::vector<Vec3i>& changed) {
    for (const Vec3i& v : changed) {
        if (!grid.frame().contains(v)) continue;
        const Vec3i b = MajorantGrid::brickOf(v);
        uint32_t& slot = slots_[brickIndex(b)];
        if (slot & kOneLabel) {
            // Still one label (all of the brick changed alike): its new label.
            const int sole = majorants.soleLabel(b);
            if (sole >= 0) {
                slot = kOneLabel | uint32_t(sole);
                continue;
            }
            expand(grid, b);
            continue;
        }
        voxels_[size_t(slot) * kBrickVoxels +
                size_t(((v.z & (kB - 1)) * kB + (v.y & (kB - 1))) * kB + (v.x & (kB - 1)))] = grid.label(v);
    }
}

}  // namespace pl
