// The label grid as the trackers read it: one 32-bit slot per 8^3 brick
// (the majorant bricks), holding the brick's label where it has one and
// otherwise the index of its 512 labels in one contiguous array. A lookup
// is two loads with no branch on a cache, where OpenVDB's value accessor
// checks its cached leaf first. OpenVDB stays the storage and exchange
// format; this is built from it when the medium is (docs/performance.md,
// "A flat brick map for the trackers").
#pragma once

#include <cstdint>
#include <vector>

#include "media/label_grid.h"
#include "media/majorant_grid.h"

namespace pl {

class BrickLabels {
public:
    BrickLabels() = default;
    BrickLabels(const LabelGrid& grid, const MajorantGrid& majorants);
    // After relabelling `changed` voxels of `grid` (the majorants already
    // updated): a brick that was one label and is no longer gets its 512.
    void update(const LabelGrid& grid, const MajorantGrid& majorants, const std::vector<Vec3i>& changed);

    // The label of a voxel inside the grid frame.
    Label at(const Vec3i& v) const {
        const uint32_t slot = slots_[brickIndex(MajorantGrid::brickOf(v))];
        if (slot & kOneLabel) return Label(slot);
        constexpr int kB = MajorantGrid::kBrickSize, kMask = kB - 1;
        return voxels_[size_t(slot) * kB * kB * kB + size_t(((v.z & kMask) * kB + (v.y & kMask)) * kB + (v.x & kMask))];
    }
    // Bytes held.
    uint64_t memoryBytes() const { return slots_.size() * sizeof(uint32_t) + voxels_.size(); }

private:
    static constexpr uint32_t kOneLabel = 1u << 31;  // the slot holds the label in its low byte
    size_t brickIndex(const Vec3i& b) const {
        return (size_t(b.z - brickMin_.z) * size_t(brickCount_.y) + size_t(b.y - brickMin_.y)) * size_t(brickCount_.x) +
               size_t(b.x - brickMin_.x);
    }
    // Gives brick b its own 512 labels, read from the grid.
    void expand(const LabelGrid& grid, const Vec3i& b);

    Vec3i brickMin_{0, 0, 0}, brickCount_{0, 0, 0};
    std::vector<uint32_t> slots_;
    std::vector<Label> voxels_;  // 512 per brick of several labels, x fastest
};

}  // namespace pl
