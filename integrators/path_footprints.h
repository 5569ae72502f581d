// Where each pixel's paths went, and what changed since: a pixel's paths
// depend on the labels only through what their trackers read
// (LabelMedium::Tracker::recordReads): the bounds of the majorant bricks
// their free flights entered and the labels of the voxels they looked up.
// A pixel none of whose bricks changed its bounds and none of whose reads
// a relabelling contradicts (a null collision stays null if the new
// label's extinction is no higher than the collision's threshold) renders
// the same paths after the change: the prediction API keeps its samples
// (api/predictor.h, CarryOver).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "media/label_medium.h"

namespace pl {

// What changed since samples were drawn: the bricks whose bounds changed,
// and the relabelled voxels by key (MajorantGrid::voxelKey), each with the
// label the samples are compared with (the current one for samples drawn
// before, the previous one for samples drawn now), a bit mask and a label
// for each place of a brick that holds any.
class LabelChanges {
public:
    LabelChanges() = default;
    LabelChanges(size_t bricks, const std::array<ChannelLut, 3>& luts);
    void markBoundsChanged(size_t brick) {
        boundsChanged_[brick] = 1;
        anyBounds_ = true;
    }
    // The voxel's label to compare with is `other` (replacing any before).
    void markRelabelled(uint64_t voxelKey, Label other);
    bool boundsChanged(size_t brick) const { return boundsChanged_[brick] != 0; }
    bool relabelled(uint64_t voxelKey) const { return otherLabel(voxelKey) != nullptr; }
    // Whether a read (LabelRead's terms) would have gone otherwise with
    // the other label.
    bool contradicts(uint64_t voxelKey, int channel, float sameUpTo_perMm) const {
        const Label* other = otherLabel(voxelKey);
        return other && !(sigmaT_perMm_[size_t(channel)][*other] <= sameUpTo_perMm);
    }
    bool empty() const { return changed_.empty() && !anyBounds_; }
    // Whether a path that read these would go otherwise.
    bool metBy(const LabelReads& reads) const;
    // Nothing changed (samples drawn from now on).
    void clear();

private:
    static constexpr uint32_t kNone = ~0u;
    struct BrickChanges {
        std::array<uint64_t, MajorantGrid::kBrickVoxels / 64> mask{};
        std::array<Label, MajorantGrid::kBrickVoxels> other{};
    };
    // The label to compare a relabelled voxel with; none if not relabelled.
    const Label* otherLabel(uint64_t voxelKey) const {
        const uint32_t m = brick_[voxelKey / MajorantGrid::kBrickVoxels];
        const uint64_t place = voxelKey % MajorantGrid::kBrickVoxels;
        if (m == kNone || !((changed_[m].mask[place / 64] >> (place % 64)) & 1u)) return nullptr;
        return &changed_[m].other[place];
    }
    std::vector<uint8_t> boundsChanged_;
    std::vector<uint32_t> brick_;  // per brick: its changes in changed_, or kNone
    std::vector<BrickChanges> changed_;
    std::array<decltype(ChannelLut::sigmaT_perMm), 3> sigmaT_perMm_{};  // per channel and label
    bool anyBounds_ = false;
};

// What each pixel's paths read, kept with its samples: per pixel the
// bricks whose bounds they entered, and per label read and channel the
// least extinction that would have changed them (LabelRead).
class PathFootprints {
public:
    explicit PathFootprints(size_t pixels = 0) : bricks_(pixels), reads_(pixels) {}

    // Whether a grid's voxel keys fit the footprints' 32-bit reads.
    static bool fits(const MajorantGrid& majorants) {
        return uint64_t(majorants.brickCount()) * MajorantGrid::kBrickVoxels * kSlots <= uint64_t(UINT32_MAX) + 1;
    }
    // Adds what a pixel's paths read.
    void add(size_t pixel, const LabelReads& reads);
    // Forgets a pixel's reads (its samples are traced again).
    void clear(size_t pixel);
    // Whether the pixel's paths would go otherwise after the changes.
    bool meets(size_t pixel, const LabelChanges& changes) const;

private:
    // A read in 8 bytes: voxel key x 4 + slot (the channel of a null
    // collision, 3 for a read of the label itself) and the least of the
    // slot's extinction bounds.
    static constexpr uint32_t kSlots = 4;
    struct Read {
        uint32_t voxelSlot;
        float sameUpTo_perMm;
    };
    std::vector<std::vector<uint32_t>> bricks_;
    std::vector<std::vector<Read>> reads_;
};

}  // namespace pl
