// Where each pixel's paths went: the majorant bricks (MajorantGrid's
// indices) whose bounds or voxels any of its samples' trackers read
// (LabelMedium::Tracker::recordBricks), sorted, once each. Every label a
// path depends on lies in its bricks, so a pixel none of whose bricks
// holds a relabelled voxel renders the same paths after the change: the
// prediction API keeps its samples (api/predictor.h, carry-over).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pl {

class PathFootprints {
public:
    explicit PathFootprints(size_t pixels = 0) : bricks_(pixels) {}

    // Adds bricks a pixel's paths read (any order, repeats allowed; the
    // vector is sorted in place).
    void add(size_t pixel, std::vector<uint32_t>& bricks);
    // Forgets a pixel's bricks (its samples are traced again).
    void clear(size_t pixel) { std::vector<uint32_t>().swap(bricks_[pixel]); }
    // Whether any of the pixel's bricks is marked in `changedBricks`
    // (indexed by brick).
    bool meets(size_t pixel, const std::vector<uint8_t>& changedBricks) const {
        for (uint32_t b : bricks_[pixel])
            if (changedBricks[b]) return true;
        return false;
    }
    const std::vector<uint32_t>& bricks(size_t pixel) const { return bricks_[pixel]; }
    size_t pixelCount() const { return bricks_.size(); }
    uint64_t memoryBytes() const;

private:
    std::vector<std::vector<uint32_t>> bricks_;
};

}  // namespace pl
