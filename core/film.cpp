#include "core/film.h"

#include "core/image_neighbourhood.h"
#include "core/sensors.h"

namespace pl {

template <class PixelOf, class SamplesOf>
void Film::poolWith(int channel, const KeyPools& keys, const ImageNeighbourhood& near, PixelOf pixelOf,
                    SamplesOf samplesOf) {
    std::vector<Accumulator>& acc = acc_[size_t(channel)];
    // Per sample: the second moment of a key's residuals (a bound on the
    // variance) or, pooled where flat, their variance.
    auto keyVariance = [&](const Accumulator& a) {
        const Moments& m = keys.at(a.poolKey);
        return a.poolWhereFlat ? m.perSampleVariance() : (m.m2 + m.sum * m.sum / m.count) / m.count;
    };
    for (Accumulator& a : acc) {
        if (pooledKeyOf(a) < 0 || a.count == 0) continue;
        a.pooledError = float(std::sqrt(keyVariance(a) * a.pooledSamples) / a.count);
    }

    // The neighbourhood in the sensor's image.
    for (size_t i = 0; i < acc.size(); ++i) {
        Accumulator& a = acc[i];
        const int kind = windowKind(a);
        if (kind == 0) continue;
        Moments window;
        near.forEachNear(pixelOf(i), kWindowRadius, [&](size_t q) {
            const WindowSamples b = samplesOf(q);
            if (b.kind == kind) window.add(b.moments());
        });
        // The window's variance (the key's where it is flat) as a prior
        // worth at most kWindowDegreesOfFreedom, and the pixel's own
        // with units - 1.
        const Moments own = momentsOf(a);
        double prior = window.perSampleVariance(), priorDof = std::min(window.units - 1, kWindowDegreesOfFreedom);
        if (window.flat() && pooledKeyOf(a) >= 0) {
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

void Film::poolErrors(const Sensor* sensor) {
    for (int c = 0; c < kChannels; ++c)
        if (!settled(c)) poolChannelErrors(c, sensor);
}

void Film::settleChannel(int channel, const Sensor* sensor) {
    if (settled(channel)) return;
    poolChannelErrors(channel, sensor);
    keepSettled(channel);
}

void Film::keepSettled(int channel) {
    std::vector<Accumulator>& acc = acc_[size_t(channel)];
    std::vector<Settled>& out = settledValues_[size_t(channel)];
    settled_[size_t(channel)] = true;
    out.assign(pixelCount_, Settled{0, 0, 0, 0, 0});  // a channel never opened: no samples
    for (size_t p = 0; p < acc.size(); ++p) {
        const Accumulator& a = acc[p];
        out[p] = {a.mean, spreadError(a), independentError(a), sharedError(a), a.count};
    }
    std::vector<Accumulator>().swap(acc);
}

void Film::poolChannelErrors(int channel, const Sensor* sensor) {
    const std::vector<Accumulator>& acc = acc_[size_t(channel)];
    // Each key's residuals over the render (a key is of one channel).
    KeyPools keys;
    for (const Accumulator& a : acc) addResiduals(keys, residualsOf(a));
    poolWith(channel, keys, ImageNeighbourhood(sensor, acc.size()), [](size_t i) { return i; },
             [&](size_t q) { return windowSamplesOf(acc[q]); });
}

std::vector<Film::PixelResiduals> Film::residuals(int channel) const {
    const std::vector<Accumulator>& acc = acc_[size_t(channel)];
    std::vector<PixelResiduals> out(pixelCount_);  // a channel never opened: none
    for (size_t i = 0; i < acc.size(); ++i) out[i] = residualsOf(acc[i]);
    return out;
}

void Film::settleShare(int channel, const ImageNeighbourhood& near, const KeyPools& keys,
                       const std::vector<uint32_t>& pixels, const std::function<WindowSamples(uint32_t)>& samplesOf) {
    poolWith(channel, keys, near, [&](size_t i) { return pixels[i]; }, [&](size_t q) { return samplesOf(uint32_t(q)); });
    keepSettled(channel);
}

std::vector<char> Film::packSettled(int channel) const {
    const std::vector<Settled>& values = settledValues_[size_t(channel)];
    std::vector<char> bytes(values.size() * sizeof(Settled));
    if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

void Film::unpackSettled(int channel, const std::vector<uint32_t>& pixels, const char* bytes) {
    std::vector<Settled>& values = settledValues_[size_t(channel)];
    if (!settled_[size_t(channel)]) values.assign(pixelCount_, Settled{0, 0, 0, 0, 0});
    settled_[size_t(channel)] = true;
    std::vector<Accumulator>().swap(acc_[size_t(channel)]);
    for (size_t i = 0; i < pixels.size(); ++i) std::memcpy(&values[pixels[i]], bytes + i * sizeof(Settled), sizeof(Settled));
}

}  // namespace pl
