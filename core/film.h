// Per-pixel, per-channel accumulators: running sums give the mean and the
// standard error of the mean. Each pixel is only touched by the thread that
// renders it, in sample order, so results do not depend on scheduling.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/rgb.h"

namespace pl {

class Film {
public:
    explicit Film(size_t pixelCount = 0) : acc_(pixelCount) {}

    size_t pixelCount() const { return acc_.size(); }
    void add(size_t pixel, int channel, float value) {
        Accumulator& a = acc_[pixel][channel];
        a.sum += value;
        a.sumSq += double(value) * value;
        a.count += 1;
    }
    uint32_t samples(size_t pixel, int channel) const { return acc_[pixel][channel].count; }
    float mean(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        return a.count ? float(a.sum / a.count) : 0.0f;
    }
    // Standard error of the mean: sqrt(sample variance / n).
    float standardError(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        if (a.count < 2) return 0.0f;
        double m = a.sum / a.count;
        double var = std::max(0.0, (a.sumSq - a.count * m * m) / (a.count - 1));
        return float(std::sqrt(var / a.count));
    }
    RGB meanRGB(size_t pixel) const {
        return {mean(pixel, 0), mean(pixel, 1), mean(pixel, 2)};
    }
    RGB standardErrorRGB(size_t pixel) const {
        return {standardError(pixel, 0), standardError(pixel, 1), standardError(pixel, 2)};
    }

private:
    struct Accumulator {
        double sum = 0, sumSq = 0;
        uint32_t count = 0;
    };
    std::vector<std::array<Accumulator, kChannels>> acc_;
};

}  // namespace pl
