// The pixels one call of the renderer renders: all, a list, or across MPI
// ranks this rank's part of a render the other ranks take part in.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/distributed.h"

namespace pl {

// With light paths a rank's part lies in its share (pixelsOfRank) and every
// rank renders in step (the light paths are shared round them); otherwise
// rank 0 pools the residuals once it has gathered the films.
struct PixelShare {
    std::vector<uint32_t> pixels;  // empty: all in one process, none across ranks
    bool acrossRanks = false;
    // The film holds the share's pixels alone, by position in the share
    // (across ranks: each rank's film only its own; settled on the ranks
    // and gathered settled on rank 0).
    bool filmOfShare = false;
    // This rank's share with more than one rank; else all pixels.
    static PixelShare ofThisRank(size_t pixelCount) {
        if (Distributed::ranks() == 1) return {};
        return {pixelsOfRank(pixelCount, Distributed::rank(), Distributed::ranks()), true};
    }
    size_t size(size_t pixelCount) const { return pixels.empty() && !acrossRanks ? pixelCount : pixels.size(); }
    size_t pixel(size_t i) const { return pixels.empty() ? i : pixels[i]; }
    // Where the share's pixel i stands in the film.
    size_t filmPixel(size_t i) const { return filmOfShare ? i : pixel(i); }
};

}  // namespace pl
