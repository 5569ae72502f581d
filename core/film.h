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
    void add(size_t pixel, int channel, float value) { addGroup(pixel, channel, value, 1); }
    // A sample with a standard error that it shares with other samples
    // (an estimated quantity they all use): added to the pixel's error.
    void add(size_t pixel, int channel, float value, float sharedError) {
        addGroup(pixel, channel, value, 1);
        acc_[pixel][channel].sharedErrorSum += sharedError;
    }
    // A group of k samples that must count as one unit for the variance:
    // samples drawn together by stratification (hero channels going round
    // three samples) are not independent, their group means are.
    void addGroup(size_t pixel, int channel, double sumOfSamples, uint32_t k) {
        Accumulator& a = acc_[pixel][channel];
        a.sum += sumOfSamples;
        a.sumSq += sumOfSamples * sumOfSamples / k;  // k x (group mean)^2
        a.count += k;
        a.units += 1;
    }
    uint32_t samples(size_t pixel, int channel) const { return acc_[pixel][channel].count; }
    float mean(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        return a.count ? float(a.sum / a.count) : 0.0f;
    }
    // Standard error of the mean from the spread of the units (samples or
    // groups), each weighted by its size: sqrt(sample variance / n) when
    // every unit is one sample.
    float spreadError(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        if (a.units < 2) return 0.0f;
        double m = a.sum / a.count;
        double var = std::max(0.0, (a.sumSq - a.count * m * m) / (double(a.count) * (a.units - 1)));
        return float(std::sqrt(var));
    }
    // The part of the mean's error that its samples share with others (a
    // bound: the mean of the samples' shared errors, as if all came from
    // one estimated quantity). Pixels that used the same one share it too.
    float sharedError(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        return a.count ? float(a.sharedErrorSum / a.count) : 0.0f;
    }
    // The whole standard error of the mean: spread and shared parts.
    float standardError(size_t pixel, int channel) const {
        return std::hypot(spreadError(pixel, channel), sharedError(pixel, channel));
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
        double sharedErrorSum = 0;  // of the samples' shared standard errors
        uint32_t count = 0;  // samples
        uint32_t units = 0;  // independent units (samples or groups)
    };
    std::vector<std::array<Accumulator, kChannels>> acc_;
};

}  // namespace pl
