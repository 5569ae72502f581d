#include "integrators/path_footprints.h"

#include <algorithm>
#include <iterator>

namespace pl {

void LabelChanges::markRelabelled(uint64_t voxelKey) {
    uint32_t& m = mask_[voxelKey / MajorantGrid::kBrickVoxels];
    if (m == kNone) {
        m = uint32_t(masks_.size());
        masks_.push_back(BrickMask{});
    }
    const uint64_t bit = voxelKey % MajorantGrid::kBrickVoxels;
    masks_[m][bit / 64] |= uint64_t(1) << (bit % 64);
}

void LabelChanges::clear() {
    std::fill(boundsChanged_.begin(), boundsChanged_.end(), uint8_t(0));
    std::fill(mask_.begin(), mask_.end(), kNone);
    masks_.clear();
    anyBounds_ = false;
}

namespace {
// held := held union the sorted, once-each values of `more` (sorted in place).
template <class T>
void mergeSorted(std::vector<uint32_t>& held, std::vector<T>& more) {
    std::sort(more.begin(), more.end());
    more.erase(std::unique(more.begin(), more.end()), more.end());
    std::vector<uint32_t> both;
    both.reserve(held.size() + more.size());
    std::set_union(held.begin(), held.end(), more.begin(), more.end(), std::back_inserter(both));
    both.shrink_to_fit();
    held.swap(both);
}
}  // namespace

void PathFootprints::add(size_t pixel, LabelReads& reads) {
    mergeSorted(bricks_[pixel], reads.bricks);
    mergeSorted(voxels_[pixel], reads.voxels);
}

void PathFootprints::clear(size_t pixel) {
    std::vector<uint32_t>().swap(bricks_[pixel]);
    std::vector<uint32_t>().swap(voxels_[pixel]);
}

}  // namespace pl
