// Where each pixel's paths went, and what changed since: a pixel's paths
// depend on the labels only through what their trackers read
// (LabelMedium::Tracker::recordReads): the bounds of the majorant bricks
// their free flights entered and the labels of the voxels they looked up.
// A pixel none of whose bricks changed its bounds and none of whose voxels
// was relabelled renders the same paths after the change: the prediction
// API keeps its samples (api/predictor.h, CarryOver).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "media/label_medium.h"

namespace pl {

// What changed since samples were drawn: the bricks whose bounds changed,
// and the relabelled voxels by key (MajorantGrid::voxelKey), a bit mask
// for each brick that holds any.
class LabelChanges {
public:
    explicit LabelChanges(size_t bricks = 0) : boundsChanged_(bricks, 0), mask_(bricks, kNone) {}
    void markBoundsChanged(size_t brick) {
        boundsChanged_[brick] = 1;
        anyBounds_ = true;
    }
    void markRelabelled(uint64_t voxelKey);
    bool boundsChanged(size_t brick) const { return boundsChanged_[brick] != 0; }
    bool relabelled(uint64_t voxelKey) const {
        const uint32_t m = mask_[voxelKey / MajorantGrid::kBrickVoxels];
        const uint64_t bit = voxelKey % MajorantGrid::kBrickVoxels;
        return m != kNone && ((masks_[m][bit / 64] >> (bit % 64)) & 1u);
    }
    bool empty() const { return masks_.empty() && !anyBounds_; }
    // Whether paths that read these bricks' bounds and these voxels
    // (keys) read anything that changed.
    template <class Bricks, class Voxels>
    bool metBy(const Bricks& bricks, const Voxels& voxels) const {
        if (empty()) return false;
        for (auto b : bricks)
            if (boundsChanged(b)) return true;
        for (auto v : voxels)
            if (relabelled(v)) return true;
        return false;
    }
    bool metBy(const LabelReads& reads) const { return metBy(reads.bricks, reads.voxels); }
    // Nothing changed (samples drawn from now on).
    void clear();

private:
    static constexpr uint32_t kNone = ~0u;
    using BrickMask = std::array<uint64_t, MajorantGrid::kBrickVoxels / 64>;
    std::vector<uint8_t> boundsChanged_;
    std::vector<uint32_t> mask_;  // per brick: its mask in masks_, or kNone
    std::vector<BrickMask> masks_;
    bool anyBounds_ = false;
};

class PathFootprints {
public:
    explicit PathFootprints(size_t pixels = 0) : bricks_(pixels), voxels_(pixels) {}

    // Adds what a pixel's paths read (the reads are sorted in place).
    // Voxel keys must be below 2^32 (Predictor checks the grid).
    void add(size_t pixel, LabelReads& reads);
    // Forgets a pixel's reads (its samples are traced again).
    void clear(size_t pixel);
    // Whether the pixel's paths read anything that changed.
    bool meets(size_t pixel, const LabelChanges& changes) const {
        return changes.metBy(bricks_[pixel], voxels_[pixel]);
    }

private:
    std::vector<std::vector<uint32_t>> bricks_, voxels_;
};

}  // namespace pl
