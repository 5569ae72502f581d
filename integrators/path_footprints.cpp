#include "integrators/path_footprints.h"

#include <algorithm>
#include <functional>
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

namespace {
// held := held merged with `more`, both sorted by `less`, keeping the
// first of the values `same` calls equal.
template <class T, class Less, class Same>
void mergeSorted(std::vector<T>& held, std::vector<T>& more, Less less, Same same) {
    std::sort(more.begin(), more.end(), less);
    std::vector<T> both;
    both.reserve(held.size() + more.size());
    std::merge(held.begin(), held.end(), more.begin(), more.end(), std::back_inserter(both), less);
    both.erase(std::unique(both.begin(), both.end(), same), both.end());
    both.shrink_to_fit();
    held.swap(both);
}
}  // namespace

void PathFootprints::add(size_t pixel, const LabelReads& reads) {
    std::vector<uint32_t> bricks(reads.bricks);
    mergeSorted(bricks_[pixel], bricks, std::less<uint32_t>(), std::equal_to<uint32_t>());
    // One read per voxel and slot, holding the least bound.
    std::vector<Read> more;
    more.reserve(reads.labels.size());
    for (const LabelRead& r : reads.labels) {
        const uint32_t slot = r.sameUpTo_perMm < 0 ? kSlots - 1 : uint32_t(r.channel);
        more.push_back({uint32_t(r.voxel * kSlots + slot), r.sameUpTo_perMm});
    }
    mergeSorted(
        reads_[pixel], more,
        [](const Read& a, const Read& b) {
            return a.voxelSlot < b.voxelSlot || (a.voxelSlot == b.voxelSlot && a.sameUpTo_perMm < b.sameUpTo_perMm);
        },
        [](const Read& a, const Read& b) { return a.voxelSlot == b.voxelSlot; });
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
