// Per-pixel, per-channel accumulators: running sums give the mean and the
// standard error of the mean. Each pixel is only touched by the thread that
// renders it, in sample order, so results do not depend on scheduling.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/rgb.h"

namespace pl {

// One sample of one channel as an estimator returns it: its value, and
// what its error has that the spread of a pixel's samples cannot show.
//  - sharedError: the standard error it shares with every other sample
//    that used the same estimated quantity (printpt's Monte Carlo control
//    means, the round-off of an exact one);
//  - poolKey, residual: a sample whose randomness is concentrated in rare
//    events (printpt's control-variate residual f - g, zero until the two
//    walks part; or what an uncontrolled walk brought, mostly 0 in dark
//    resin) names the kind it belongs to (>= 0) and its random part;
//    the second moment of the residuals is pooled over every sample of
//    that kind in the render, since a pixel's own few samples may not have
//    met one of the events.
//  - poolWhereFlat: the pooled error stands in only where a pixel's
//    samples are all equal (a walk that is almost always absorbed gives
//    the same value every time, and its spread 0 says nothing of the rare
//    walks that bring light); otherwise it is a bound beside the spread.
struct ChannelSample {
    float value = 0.0f;
    float sharedError = 0.0f;
    int32_t poolKey = -1;  // -1: none
    float residual = 0.0f;
    bool poolWhereFlat = false;
};

class Film {
public:
    explicit Film(size_t pixelCount = 0) : acc_(pixelCount) {}

    size_t pixelCount() const { return acc_.size(); }
    void add(size_t pixel, int channel, float value) { addGroup(pixel, channel, value, 1); }
    void add(size_t pixel, int channel, const ChannelSample& sample) {
        addGroup(pixel, channel, sample.value, 1);
        Accumulator& a = acc_[pixel][channel];
        a.sharedErrorSum += sample.sharedError;
        if (sample.poolKey >= 0) {
            // A pixel's samples share its entry: the first key stands for all.
            if (a.poolKey < 0) {
                a.poolKey = sample.poolKey;
                a.poolWhereFlat = sample.poolWhereFlat;
            }
            a.residualSum += sample.residual;
            a.residualSqSum += double(sample.residual) * sample.residual;
            a.pooledSamples += 1;
        }
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
    // Pools the residuals' second moments per key over all pixels (in pixel
    // order: the same bits whatever the threads) and sets every pooled
    // pixel's pooledError: from the second moment (a bound; control
    // residuals, whose mean is about 0), or for keys pooled where flat from
    // the variance over the key's samples (samples that never vary, as in
    // a white furnace, have none). Call after adding samples.
    void poolResiduals();

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
    // The standard error of the mean from the pooled second moment of its
    // samples' residuals (poolResiduals); 0 where none was pooled.
    float pooledError(size_t pixel, int channel) const { return acc_[pixel][channel].pooledError; }
    // The error independent of other pixels': the larger of the spread and
    // the pooled estimate (both estimate it; the pooled one also where the
    // pixel's samples missed the rare events), or, for samples pooled
    // where flat, the spread unless the samples are all equal.
    float independentError(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        const float spread = spreadError(pixel, channel);
        if (a.poolWhereFlat) {
            // Flat: the random parts were all equal (the values may still
            // differ by deterministic parts, as F Le with shading normals).
            const double n = a.pooledSamples;
            const bool flat = n < 2 || a.residualSqSum - a.residualSum * a.residualSum / n <= 1e-12 * a.residualSqSum;
            return flat ? pooledError(pixel, channel) : spread;
        }
        return std::max(spread, pooledError(pixel, channel));
    }
    // The part of the mean's error that its samples share with others (a
    // bound: the mean of the samples' shared errors, as if all came from
    // one estimated quantity). Pixels that used the same one share it too.
    float sharedError(size_t pixel, int channel) const {
        const Accumulator& a = acc_[pixel][channel];
        return a.count ? float(a.sharedErrorSum / a.count) : 0.0f;
    }
    // The whole standard error of the mean: independent and shared parts.
    float standardError(size_t pixel, int channel) const {
        return std::hypot(independentError(pixel, channel), sharedError(pixel, channel));
    }
    // The accumulators of the listed pixels as bytes, and back into the
    // same pixels of another film (a render split across processes is
    // gathered pixel by pixel: the bits of one process's render).
    std::vector<char> packPixels(const std::vector<uint32_t>& pixels) const {
        std::vector<char> bytes(pixels.size() * sizeof(acc_[0]));
        for (size_t i = 0; i < pixels.size(); ++i)
            std::memcpy(bytes.data() + i * sizeof(acc_[0]), &acc_[pixels[i]], sizeof(acc_[0]));
        return bytes;
    }
    static size_t packedBytesPerPixel() { return sizeof(std::array<Accumulator, kChannels>); }
    void unpackPixels(const std::vector<uint32_t>& pixels, const char* bytes) {
        for (size_t i = 0; i < pixels.size(); ++i)
            std::memcpy(&acc_[pixels[i]], bytes + i * sizeof(acc_[0]), sizeof(acc_[0]));
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
        double residualSum = 0;     // of the pooled samples' residuals
        double residualSqSum = 0;   // of the pooled samples' residuals squared
        uint32_t count = 0;         // samples
        uint32_t units = 0;         // independent units (samples or groups)
        uint32_t pooledSamples = 0;
        int32_t poolKey = -1;
        bool poolWhereFlat = false;
        float pooledError = 0;
    };
    std::vector<std::array<Accumulator, kChannels>> acc_;
};

}  // namespace pl
