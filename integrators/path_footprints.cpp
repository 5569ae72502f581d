#include "integrators/path_footprints.h"

#include <algorithm>
#include <iterator>

namespace pl {

LabelChanges::LabelChanges(size_t bricks, const std::array<ChannelLut, 3>& luts)
    : boundsChanged_(bricks, 0), brick_(bricks, kNone) {
    for (int c = 0; c < 3; ++c) sigmaT_perMm_[size_t(c)] = luts[size_t(c)].sigmaT_perMm;
}

void LabelChanges::markRelabelled(uint64_t voxelKey, Label other) {
    uint32_t& m = brick_[voxelKey / MajorantGrid::kBrickVoxels];
    if (m == kNone) {
        m = uint32_t(changed_.size());
        changed_.emplace_back();
    }
    const uint64_t place = voxelKey % MajorantGrid::kBrickVoxels;
    changed_[m].mask[place / 64] |= uint64_t(1) << (place % 64);
    changed_[m].other[place] = other;
}

void LabelChanges::clear() {
    std::fill(boundsChanged_.begin(), boundsChanged_.end(), uint8_t(0));
    std::fill(brick_.begin(), brick_.end(), kNone);
    changed_.clear();
    anyBounds_ = false;
}

bool LabelChanges::metBy(const LabelReads& reads) const {
    if (empty()) return false;
    for (uint32_t b : reads.bricks)
        if (boundsChanged(b)) return true;
    for (const LabelRead& r : reads.labels)
        if (contradicts(r.voxel, r.channel, r.sameUpTo_perMm)) return true;
    return false;
}

void PathFootprints::add(size_t pixel, LabelReads& reads) {
    std::vector<uint32_t>& bricks = bricks_[pixel];
    bricks.insert(bricks.end(), reads.bricks.begin(), reads.bricks.end());
    std::sort(bricks.begin(), bricks.end());
    bricks.erase(std::unique(bricks.begin(), bricks.end()), bricks.end());
    bricks.shrink_to_fit();
    // One read per voxel and slot, holding the least bound.
    std::vector<Read>& held = reads_[pixel];
    for (const LabelRead& r : reads.labels) {
        const uint32_t slot = r.sameUpTo_perMm < 0 ? kSlots - 1 : uint32_t(r.channel);
        held.push_back({uint32_t(r.voxel * kSlots + slot), r.sameUpTo_perMm});
    }
    std::sort(held.begin(), held.end(), [](const Read& a, const Read& b) {
        return a.voxelSlot < b.voxelSlot || (a.voxelSlot == b.voxelSlot && a.sameUpTo_perMm < b.sameUpTo_perMm);
    });
    held.erase(std::unique(held.begin(), held.end(),
                           [](const Read& a, const Read& b) { return a.voxelSlot == b.voxelSlot; }),
               held.end());
    held.shrink_to_fit();
}

void PathFootprints::clear(size_t pixel) {
    std::vector<uint32_t>().swap(bricks_[pixel]);
    std::vector<Read>().swap(reads_[pixel]);
}

bool PathFootprints::meets(size_t pixel, const LabelChanges& changes) const {
    if (changes.empty()) return false;
    for (uint32_t b : bricks_[pixel])
        if (changes.boundsChanged(b)) return true;
    for (const Read& r : reads_[pixel]) {
        const uint32_t slot = r.voxelSlot % kSlots;
        if (changes.contradicts(r.voxelSlot / kSlots, slot == kSlots - 1 ? 0 : int(slot), r.sameUpTo_perMm))
            return true;
    }
    return false;
}

}  // namespace pl
