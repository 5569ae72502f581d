// Per-pixel, per-channel accumulators: running moments in float (the mean
// and the squared deviations from it, Welford's update) give the mean and
// the standard error of the mean. Each pixel is only touched by the thread that
// renders it, in sample order, so results do not depend on scheduling.
// A channel whose samples are all in can be settled: its accumulators (48
// bytes a pixel) give way to what the queries read (20 bytes).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <unordered_map>
#include <vector>

#include "core/rgb.h"

namespace pl {

class Sensor;
class ImageNeighbourhood;

// One sample of one channel as an estimator returns it: its value, and
// what its error has that the spread of a pixel's samples cannot show.
//  - sharedError: the standard error it shares with every other sample
//    that used the same estimated quantity (printpt's Monte Carlo control
//    means, the round-off of an exact one);
//  - poolKey, residual: the kind of sample (>= 0) and its random part
//    (printpt's control-variate residual f - g, zero until the two walks
//    part; or what an uncontrolled walk brought, mostly 0 in dark resin).
//    The variance of the residuals is what poolErrors shrinks towards the
//    neighbourhood's; where a whole neighbourhood's are equal, the key's,
//    pooled over the render, stands in (rare events no pixel met).
//  - poolWhereFlat: the key's pool is the residuals' variance (samples
//    without a control) rather than their second moment (a control's
//    residuals, whose mean is about 0: a bound).
//  - withinVariance (where hasWithinVariance): the variance of a part of
//    the value that the sample estimated from within, from many independent
//    pieces (a block of light paths: its particles' squared scores,
//    LightBlockScores). That part's error is this estimate, at any number
//    of samples, and the residual, the rest's random part, is pooled where
//    flat or else taken from its own spread.
//  - bias: the sample's own estimate of its value's bias, which no number
//    of samples averages out (a kernel estimator's, from two radii). The
//    pixel's shared error adds the bias their mean shows beyond its own
//    noise, sqrt(max(0, mean^2 - variance of the mean)): the difference is
//    an unbiased estimate of the squared bias, so that the error squared
//    estimates the mean squared error. Samples of one pixel come through
//    add(pixel, channel, ChannelSample) alike.
struct ChannelSample {
    float value = 0.0f;
    float sharedError = 0.0f;
    int32_t poolKey = -1;  // -1: none
    float residual = 0.0f;
    bool poolWhereFlat = false;
    bool hasWithinVariance = false;
    float withinVariance = 0.0f;
    float bias = 0.0f;
};

class Film {
public:
    // openChannels false: each channel's accumulators are allocated when
    // openChannel is called (a render that settles each pass opens each
    // channel as its pass starts).
    explicit Film(size_t pixelCount = 0, bool openChannels = true) : pixelCount_(pixelCount) {
        if (openChannels)
            for (int c = 0; c < kChannels; ++c) openChannel(c);
    }
    void openChannel(int channel) {
        if (!settled_[channel]) acc_[channel].resize(pixelCount_);
    }

    size_t pixelCount() const { return pixelCount_; }
    // Forgets a pixel's samples in every open channel (to add them again).
    void clearPixel(size_t pixel) {
        for (int c = 0; c < kChannels; ++c)
            if (!settled_[c] && !acc_[c].empty()) acc_[c][pixel] = Accumulator{};
    }
    void add(size_t pixel, int channel, float value) { addGroup(pixel, channel, value, 1); }
    void add(size_t pixel, int channel, const ChannelSample& sample) {
        addGroup(pixel, channel, sample.value, 1);
        Accumulator& a = acc_[channel][pixel];
        a.sharedErrorSum += sample.sharedError;
        // Welford over the pixel's samples (a bias of 0 keeps both at 0).
        const float biasStep = sample.bias - a.biasMean;
        a.biasMean += biasStep / float(a.count);
        a.biasM2 += biasStep * (sample.bias - a.biasMean);
        // A surface voxel's samples share its entry: the first key stands
        // for all. A camera pixel's may not (entries into other labels,
        // rays that miss): its residuals then do not hold its error, and it
        // is pooled on its values (pooledKeyOf).
        if (a.count == 1) {
            a.poolKey = sample.poolKey;
            a.poolWhereFlat = sample.poolWhereFlat;
        } else if (sample.poolKey != a.poolKey) {
            a.keysDiffer = true;
        }
        if (sample.poolKey >= 0) {
            a.pooledSamples += 1;
            const float d = sample.residual - a.residualMean;
            a.residualMean += d / float(a.pooledSamples);
            a.residualM2 += d * (sample.residual - a.residualMean);
        }
        if (sample.hasWithinVariance) {
            a.hasWithinVariance = true;
            a.withinVarianceSum += sample.withinVariance;
        }
    }
    // A group of k samples that must count as one unit for the variance:
    // samples drawn together by stratification (hero channels going round
    // three samples) are not independent, their group means are. The
    // mean and squared deviations are updated in float (Welford's update,
    // each unit weighted by its size): a float sum of squares less the
    // squared sum would cancel, this has nothing to cancel and stays 0
    // where every unit is equal.
    void addGroup(size_t pixel, int channel, double sumOfSamples, uint32_t k) {
        Accumulator& a = acc_[channel][pixel];
        a.count += k;
        a.units += 1;
        const float unitMean = float(sumOfSamples / k);
        const float d = unitMean - a.mean;
        a.mean += d * (float(k) / float(a.count));
        a.m2 += float(k) * d * (unitMean - a.mean);
    }
    // Sets the errors that pooling gives (call after adding samples; the
    // same bits whatever the threads). Each pixel's variance is shrunk
    // towards its neighbourhood's, the pixels within kWindowRadius in the
    // sensor's image whose samples are of the same kind (with a control,
    // pooled where flat, or neither): a pixel's own few samples say little
    // of its variance (from two, a ratio with Cauchy-like tails), its
    // neighbours, which see nearly the same light, say more. The variances
    // are of the samples' random parts (residuals) where they have a key,
    // of their values otherwise. Where the whole window's are flat (a
    // control's walks never parted, every walk was absorbed), the key's,
    // pooled over the render, stands in: for controlled samples the
    // residuals' second moment (a bound, and the least error they report),
    // for the others their variance. Without a sensor the window is the
    // pixel alone. Settled channels stay as they are.
    void poolErrors(const Sensor* sensor = nullptr);
    // Pools a channel's errors (as poolErrors) and keeps only what the
    // queries below read; no samples may be added to it after. A render
    // that opens each channel as its pass starts and settles it after
    // holds one channel's accumulators at a time; the values are those of
    // poolErrors (a channel never opened: no samples, 0).
    void settleChannel(int channel, const Sensor* sensor);
    bool settled(int channel) const { return settled_[channel]; }
    // The neighbourhood: pixels within this many image pixels along each
    // axis (a 5 x 5 window), and the most degrees of freedom its variance
    // counts for beside the pixel's own (units - 1).
    static constexpr int kWindowRadius = 2;
    static constexpr double kWindowDegreesOfFreedom = 8.0;

    uint32_t samples(size_t pixel, int channel) const {
        return settled(channel) ? settledValues_[channel][pixel].count : acc_[channel][pixel].count;
    }
    float mean(size_t pixel, int channel) const {
        return settled(channel) ? settledValues_[channel][pixel].mean : acc_[channel][pixel].mean;
    }
    // Standard error of the mean from the spread of the units (samples or
    // groups), each weighted by its size: sqrt(sample variance / n) when
    // every unit is one sample.
    float spreadError(size_t pixel, int channel) const {
        return settled(channel) ? settledValues_[channel][pixel].spreadError : spreadError(acc_[channel][pixel]);
    }
    // The error independent of other pixels':
    //  - with a part estimated from within (withinVariance): that estimate,
    //    and the rest's random part, pooled where flat or its own spread;
    //  - otherwise, once pooled, the variance shrunk towards the
    //    neighbourhood's (poolErrors); before, the spread.
    float independentError(size_t pixel, int channel) const {
        return settled(channel) ? settledValues_[channel][pixel].independentError
                                : independentError(acc_[channel][pixel]);
    }
    // The part of the mean's error that its samples share with others (a
    // bound: the mean of the samples' shared errors, as if all came from
    // one estimated quantity), and the bias their own estimates show
    // (ChannelSample::bias). Pixels that used the same one share it too.
    float sharedError(size_t pixel, int channel) const {
        return settled(channel) ? settledValues_[channel][pixel].sharedError : sharedError(acc_[channel][pixel]);
    }
    // The whole standard error of the mean: independent and shared parts.
    float standardError(size_t pixel, int channel) const {
        return std::hypot(independentError(pixel, channel), sharedError(pixel, channel));
    }
    // The accumulators of the listed pixels as bytes, and back into the
    // same pixels of another film (a render split across processes is
    // gathered pixel by pixel: the bits of one process's render). Not for
    // settled channels.
    std::vector<char> packPixels(const std::vector<uint32_t>& pixels) const {
        std::vector<char> bytes(pixels.size() * packedBytesPerPixel());
        for (size_t i = 0; i < pixels.size(); ++i)
            for (int c = 0; c < kChannels; ++c)
                std::memcpy(bytes.data() + (i * kChannels + size_t(c)) * sizeof(Accumulator), &acc_[c][pixels[i]],
                            sizeof(Accumulator));
        return bytes;
    }
    static size_t packedBytesPerPixel() { return kChannels * sizeof(Accumulator); }
    void unpackPixels(const std::vector<uint32_t>& pixels, const char* bytes) {
        for (size_t i = 0; i < pixels.size(); ++i)
            for (int c = 0; c < kChannels; ++c)
                std::memcpy(&acc_[c][pixels[i]], bytes + (i * kChannels + size_t(c)) * sizeof(Accumulator),
                            sizeof(Accumulator));
    }
    // Samples' moments, for a pixel or a window of pixels: their count,
    // units, sum and squared deviations from their mean.
    struct Moments {
        double count = 0, units = 0, sum = 0, m2 = 0;
        // Adds another's samples (Chan et al.'s pairwise update).
        void add(const Moments& o) {
            if (o.count == 0) return;
            if (count > 0) {
                const double d = o.sum / o.count - sum / count;
                m2 += d * d * count * o.count / (count + o.count);
            }
            count += o.count;
            units += o.units;
            sum += o.sum;
            m2 += o.m2;
        }
        // The variance of one sample about the moments' own mean, and
        // whether the samples were all equal (or fewer than two units).
        double perSampleVariance() const { return units < 2 ? 0.0 : std::max(0.0, m2) / (units - 1); }
        bool flat() const { return units < 2 || m2 <= 1e-12 * (m2 + sum * sum / count); }
    };

    // Error pooling over a film that holds one share of the pixels (an MPI
    // rank's): the pooling of one film over all of them, in pieces.
    //  - Each key's residuals over the render, added in pixel order
    //    (addResiduals over every share's residuals()).
    struct PixelResiduals {
        int32_t key = -1;  // -1: none
        uint32_t samples = 0;
        float mean = 0, m2 = 0;
    };
    using KeyPools = std::unordered_map<int32_t, Moments>;
    std::vector<PixelResiduals> residuals(int channel) const;
    static void addResiduals(KeyPools& pools, const PixelResiduals& r) {
        if (r.key >= 0) pools[r.key].add(residualMoments(r));
    }
    //  - A pixel's samples as its neighbours' windows take them (kind 0:
    //    in no window): their count, units, mean and squared deviations.
    struct WindowSamples {
        int32_t kind = 0;
        uint32_t count = 0, units = 0;
        float mean = 0, m2 = 0;
        Moments moments() const { return {double(count), double(units), double(mean) * count, double(m2)}; }
    };
    WindowSamples windowSamples(int channel, size_t i) const {
        return acc_[size_t(channel)].empty() ? WindowSamples{} : windowSamplesOf(acc_[size_t(channel)][i]);
    }
    //  - Then each share pools its pixels (film pixel i is the sensor's
    //    pixels[i]) with the keys' pools and its windows' pixels, wherever
    //    they are held (samplesOf: a sensor pixel's WindowSamples), and
    //    settles.
    void settleShare(int channel, const ImageNeighbourhood& near, const KeyPools& keys,
                     const std::vector<uint32_t>& pixels, const std::function<WindowSamples(uint32_t)>& samplesOf);
    // A settled channel's values (every pixel's, in order) as bytes, and
    // back into the listed pixels of another film (shares across MPI
    // ranks are gathered settled).
    std::vector<char> packSettled(int channel) const;
    void unpackSettled(int channel, const std::vector<uint32_t>& pixels, const char* bytes);

    // Bytes a pixel's channel holds before and after it is settled.
    static size_t bytesPerChannel() { return sizeof(Accumulator); }
    static size_t settledBytesPerChannel() { return sizeof(Settled); }

    RGB meanRGB(size_t pixel) const {
        return {mean(pixel, 0), mean(pixel, 1), mean(pixel, 2)};
    }
    RGB standardErrorRGB(size_t pixel) const {
        return {standardError(pixel, 0), standardError(pixel, 1), standardError(pixel, 2)};
    }

private:
    struct Accumulator;
    // The key a pixel's residuals are pooled under: -1 where its samples
    // had none or different ones.
    static int32_t pooledKeyOf(const Accumulator& a) { return a.keysDiffer ? -1 : a.poolKey; }
    // The kind of a pixel's samples, for its neighbourhood: 0 with a part
    // estimated from within (no window), 1 with a control, 2 pooled where
    // flat, 3 neither.
    static int windowKind(const Accumulator& a) {
        if (a.count == 0 || a.hasWithinVariance) return 0;
        return pooledKeyOf(a) < 0 ? 3 : a.poolWhereFlat ? 2 : 1;
    }
    // A pixel's pooled samples' residuals (every sample has one where it
    // has a key), and its samples: their residuals where they have a key,
    // their values otherwise.
    static PixelResiduals residualsOf(const Accumulator& a) {
        return {pooledKeyOf(a), a.pooledSamples, a.residualMean, a.residualM2};
    }
    static Moments residualMoments(const PixelResiduals& r) {
        return WindowSamples{0, r.samples, r.samples, r.mean, r.m2}.moments();
    }
    static Moments residualMoments(const Accumulator& a) { return residualMoments(residualsOf(a)); }
    static WindowSamples windowSamplesOf(const Accumulator& a) {
        if (pooledKeyOf(a) >= 0)
            return {windowKind(a), a.pooledSamples, a.pooledSamples, a.residualMean, a.residualM2};
        return {windowKind(a), a.count, a.units, a.mean, a.m2};
    }
    static Moments momentsOf(const Accumulator& a) { return windowSamplesOf(a).moments(); }
    static float spreadError(const Accumulator& a) {
        if (a.units < 2) return 0.0f;
        return float(std::sqrt(std::max(0.0, double(a.m2)) / (double(a.count) * (a.units - 1))));
    }
    static float sharedError(const Accumulator& a) {
        return a.count ? a.sharedErrorSum / float(a.count) + biasError(a) : 0.0f;
    }
    // The bias the samples' own estimates show beyond their noise (one
    // sample: its estimate as it is).
    static float biasError(const Accumulator& a) {
        const double mean = a.biasMean;
        if (a.count < 2) return float(std::abs(mean));
        const double varianceOfMean = double(a.biasM2) / (double(a.count) - 1.0) / double(a.count);
        return float(std::sqrt(std::max(0.0, mean * mean - varianceOfMean)));
    }
    static float independentError(const Accumulator& a) {
        if (a.hasWithinVariance) {
            const double rest = pooledKeyOf(a) < 0 ? 0.0 : residualFlat(a) ? a.pooledError : residualSpread(a);
            return float(std::sqrt(double(a.withinVarianceSum) / (double(a.count) * a.count) + rest * rest));
        }
        return a.pooledOverWindow ? a.pooledError : spreadError(a);
    }
    // Pools one channel's errors (poolErrors).
    void poolChannelErrors(int channel, const Sensor* sensor);
    // Pools a channel's errors with the keys' pools over the render: film
    // pixel i is the sensor's pixelOf(i), and a window's pixel q is seen
    // as samplesOf(q) (WindowSamples).
    template <class PixelOf, class SamplesOf>
    void poolWith(int channel, const KeyPools& keys, const ImageNeighbourhood& near, PixelOf pixelOf,
                  SamplesOf samplesOf);
    // Keeps what the queries read of a pooled channel.
    void keepSettled(int channel);
    // Whether a pixel's pooled samples' residuals were all equal (or fewer than two).
    static bool residualFlat(const Accumulator& a) { return residualMoments(a).flat(); }
    // The standard error of the mean that the spread of the residuals gives.
    static double residualSpread(const Accumulator& a) {
        const Moments m = residualMoments(a);
        return std::sqrt(m.perSampleVariance() * m.count) / a.count;
    }
    struct Accumulator {
        float mean = 0, m2 = 0;                  // of the units (addGroup)
        float residualMean = 0, residualM2 = 0;  // of the pooled samples' residuals
        float sharedErrorSum = 0;                // of the samples' shared standard errors
        float biasMean = 0, biasM2 = 0;          // of the samples' bias estimates (Welford)
        float withinVarianceSum = 0;             // of the samples' withinVariance
        float pooledError = 0;
        uint32_t count = 0;  // samples
        uint32_t units = 0;  // independent units (samples or groups)
        uint32_t pooledSamples = 0;
        int32_t poolKey = -1;
        bool poolWhereFlat = false;
        bool hasWithinVariance = false;
        bool pooledOverWindow = false;  // pooledError is the whole independent error
        bool keysDiffer = false;        // its samples came with different keys (or some without)
    };
    // What a settled channel keeps of a pixel.
    struct Settled {
        float mean, spreadError, independentError, sharedError;
        uint32_t count;
    };
    size_t pixelCount_;
    std::array<std::vector<Accumulator>, kChannels> acc_;  // per channel, per pixel; empty once settled
    std::array<std::vector<Settled>, kChannels> settledValues_;  // per channel, per pixel, once settled
    std::array<bool, kChannels> settled_{};                       // the same on every rank whatever its share
};

}  // namespace pl
