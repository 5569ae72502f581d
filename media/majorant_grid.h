// Per-brick bounds of sigma_t for each channel. A brick is 8^3 voxels,
// aligned with OpenVDB's leaf nodes, so clear resin and void regions get
// their own (small or zero) majorant instead of the global maximum
// (the transparent-material problem, Brecka 4.6).
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "media/label_grid.h"
#include "media/materials.h"

namespace pl {

class MajorantGrid {
public:
    static constexpr int kBrickLog2 = 3;
    static constexpr int kBrickSize = 1 << kBrickLog2;

    static constexpr int kSeveralLabels = -1, kOnlyVoid = -2;  // solidLabel's (below)
    // What a region of the grid holds: bounds of sigma_t per channel and its labels.
    struct Bounds {
        static constexpr int kNoLabelYet = -2;  // soleLabel before any voxel is seen
        RGB maxSigmaT{0, 0, 0};
        RGB minSigmaT{0, 0, 0};
        int soleLabel = -1;  // the label of every voxel, or -1 (several)
        int solidLabel = kOnlyVoid;
        // Nothing seen yet.
        static Bounds none() {
            constexpr float inf = std::numeric_limits<float>::infinity();
            return {{-inf, -inf, -inf}, {inf, inf, inf}, kNoLabelYet, kOnlyVoid};
        }
        // Adds label l (and its sigma_t per channel) to what the region holds.
        void include(Label l, const std::array<ChannelLut, 3>& luts, Label voidLabel) {
            for (int c = 0; c < 3; ++c) {
                maxSigmaT[c] = std::max(maxSigmaT[c], luts[c].sigmaT_perMm[l]);
                minSigmaT[c] = std::min(minSigmaT[c], luts[c].sigmaT_perMm[l]);
            }
            soleLabel = soleLabel == kNoLabelYet || soleLabel == int(l) ? int(l) : -1;
            if (l != voidLabel) solidLabel = solidLabel == kOnlyVoid || solidLabel == int(l) ? int(l) : kSeveralLabels;
        }
    };

    MajorantGrid() = default;
    MajorantGrid(const LabelGrid& grid, const std::array<ChannelLut, 3>& luts);
    // After relabelling `changed` voxels of `grid`: recomputes only their
    // bricks (and the global maximum), with the result of a full
    // construction; or, with `majorantsOnlyRise`, keeping each brick's
    // majorant where its labels now need less (still a bound, and the
    // same to free flights that crossed the brick before: a loop whose
    // labels come and go stops changing its bricks' bounds; a brick so
    // raised has no sole label, its collisions decided one by one).
    void update(const LabelGrid& grid, const std::array<ChannelLut, 3>& luts, const std::vector<Vec3i>& changed,
                bool majorantsOnlyRise = false);

    // Bricks [brickMin, brickMax) cover the grid frame.
    const Vec3i& brickMin() const { return brickMin_; }
    const Vec3i& brickMax() const { return brickMax_; }
    float maxSigmaT(const Vec3i& brick, int channel) const { return at(brick).maxSigmaT[channel]; }
    float minSigmaT(const Vec3i& brick, int channel) const { return at(brick).minSigmaT[channel]; }
    const RGB& maxSigmaT(const Vec3i& brick) const { return at(brick).maxSigmaT; }
    // The label of every voxel of the brick, or -1 if it holds several:
    // trackers need no grid lookup in a one-label brick.
    int soleLabel(const Vec3i& brick) const { return at(brick).soleLabel; }
    // The one label other than void the brick holds: kSeveralLabels if it
    // holds several, kOnlyVoid if none. printpt's control variate asks
    // whether a region is one resin (the void skin between the mesh and the
    // voxels aside).
    int solidLabel(const Vec3i& brick) const { return at(brick).solidLabel; }
    // The same for the brick of a voxel; void surrounds the grid.
    int solidLabelAt(const Vec3i& voxel) const {
        const Vec3i b = brickOf(voxel);
        const bool inside = b.x >= brickMin_.x && b.y >= brickMin_.y && b.z >= brickMin_.z && b.x < brickMax_.x &&
                            b.y < brickMax_.y && b.z < brickMax_.z;
        return inside ? solidLabel(b) : kOnlyVoid;
    }
    // The largest sigma_t anywhere, per channel.
    float globalMaxSigmaT(int channel) const { return wholeGrid_.maxSigmaT[channel]; }
    // A brick's bounds; the whole grid's (its largest sigma_t, several labels).
    const Bounds& bounds(const Vec3i& brick) const { return at(brick); }
    const Bounds& wholeGrid() const { return wholeGrid_; }

    // The index of a brick's bounds (as bounds(brick) returns them).
    size_t brickIndexOf(const Bounds& b) const { return size_t(&b - bricks_.data()); }
    size_t brickCount() const { return bricks_.size(); }
    size_t brickIndex(const Vec3i& b) const {
        return (size_t(b.z - brickMin_.z) * (brickMax_.y - brickMin_.y) + (b.y - brickMin_.y)) *
                   (brickMax_.x - brickMin_.x) + (b.x - brickMin_.x);
    }
    // A voxel's key: its brick's index times the brick's voxels plus its
    // place in the brick (so a set of keys is checked brick by brick).
    static constexpr int kBrickVoxels = kBrickSize * kBrickSize * kBrickSize;
    uint64_t voxelKey(const Vec3i& v) const {
        const uint64_t local = uint64_t(((v.z & (kBrickSize - 1)) << (2 * kBrickLog2)) |
                                        ((v.y & (kBrickSize - 1)) << kBrickLog2) | (v.x & (kBrickSize - 1)));
        return uint64_t(brickIndex(brickOf(v))) * kBrickVoxels + local;
    }
    static Vec3i brickOf(const Vec3i& voxel) {
        return {voxel.x >> kBrickLog2, voxel.y >> kBrickLog2, voxel.z >> kBrickLog2};
    }

private:
    const Bounds& at(const Vec3i& b) const { return bricks_[brickIndex(b)]; }
    // The whole grid's bounds from the bricks' (its minimum left at 0).
    void boundWholeGrid();
    Vec3i brickMin_, brickMax_;
    std::vector<Bounds> bricks_;
    Bounds wholeGrid_{{0, 0, 0}, {0, 0, 0}, -1, kSeveralLabels};
};

}  // namespace pl
