#include "core/film.h"

#include <unordered_map>

#include "core/sensors.h"

namespace pl {

void Film::poolErrors(const Sensor* sensor) {
    for (int c = 0; c < kChannels; ++c)
        if (!settled(c)) poolChannelErrors(c, sensor);
}

void Film::settleChannel(int channel, const Sensor* sensor) {
    if (settled(channel)) return;
    poolChannelErrors(channel, sensor);
    std::vector<Accumulator>& acc = acc_[size_t(channel)];
    std::vector<Settled>& out = settled_[size_t(channel)];
    out.assign(pixelCount_, Settled{0, 0, 0, 0, 0});  // a channel never opened: no samples
    for (size_t p = 0; p < acc.size(); ++p) {
        const Accumulator& a = acc[p];
        out[p] = {a.mean, spreadError(a), independentError(a), sharedError(a), a.count};
    }
    std::vector<Accumulator>().swap(acc);
}

void Film::poolChannelErrors(int channel, const Sensor* sensor) {
    std::vector<Accumulator>& acc = acc_[size_t(channel)];
    // Each key's residuals over the render (a key is of one channel).
    std::unordered_map<int32_t, Moments> moments;
    for (const Accumulator& a : acc)
        if (a.poolKey >= 0) moments[a.poolKey].add(residualMoments(a));
    // Per sample: the second moment of a key's residuals (a bound on the
    // variance) or, pooled where flat, their variance.
    auto keyVariance = [&](const Accumulator& a) {
        const Moments& m = moments[a.poolKey];
        return a.poolWhereFlat ? m.perSampleVariance() : (m.m2 + m.sum * m.sum / m.count) / m.count;
    };
    for (Accumulator& a : acc) {
        if (a.poolKey < 0 || a.count == 0) continue;
        a.pooledError = float(std::sqrt(keyVariance(a) * a.pooledSamples) / a.count);
    }

    // The neighbourhood in the sensor's image: pixel by image position.
    const int width = sensor ? sensor->imageWidth() : 0, height = sensor ? sensor->imageHeight() : 0;
    std::vector<int32_t> pixelAt(size_t(width) * size_t(height), -1);
    for (size_t p = 0; sensor && p < acc.size(); ++p)
        if (const int64_t i = sensor->pixelImageIndex(p); i >= 0) pixelAt[size_t(i)] = int32_t(p);
    for (size_t p = 0; p < acc.size(); ++p) {
        Accumulator& a = acc[p];
        const int kind = windowKind(a);
        if (kind == 0) continue;
        Moments window;
        auto addPixel = [&](size_t q) {
            const Accumulator& b = acc[q];
            if (windowKind(b) != kind) return;
            window.add(momentsOf(b));
        };
        const int64_t imageIndex = sensor ? sensor->pixelImageIndex(p) : -1;
        if (imageIndex < 0) addPixel(p);
        else {
            const int x = int(imageIndex % width), y = int(imageIndex / width);
            for (int dy = -kWindowRadius; dy <= kWindowRadius; ++dy)
                for (int dx = -kWindowRadius; dx <= kWindowRadius; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
                    const int32_t q = pixelAt[size_t(qy) * size_t(width) + size_t(qx)];
                    if (q >= 0) addPixel(size_t(q));
                }
        }
        // The window's variance (the key's where it is flat) as a prior
        // worth at most kWindowDegreesOfFreedom, and the pixel's own
        // with units - 1.
        const Moments own = momentsOf(a);
        double prior = window.perSampleVariance(), priorDof = std::min(window.units - 1, kWindowDegreesOfFreedom);
        if (window.flat() && a.poolKey >= 0) {
            prior = keyVariance(a);
            priorDof = kWindowDegreesOfFreedom;
        }
        const double ownDof = own.units - 1;
        const double perSample = priorDof + ownDof > 0
                                     ? (priorDof * prior + ownDof * own.perSampleVariance()) / (priorDof + ownDof)
                                     : 0.0;
        // The mean's variance: own.count random parts in a.count samples.
        // Under a control, at least the key's bound: where the key's
        // pixels are alike (a half-space control) the whole render sees
        // its rare partings better than any window.
        const double shrunk = std::sqrt(perSample * own.count) / double(a.count);
        a.pooledError = float(kind == 1 ? std::max(shrunk, double(a.pooledError)) : shrunk);
        a.pooledOverWindow = true;
    }
}

}  // namespace pl
