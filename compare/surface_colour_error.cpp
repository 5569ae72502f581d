#include "compare/surface_colour_error.h"

#include <algorithm>
#include <cmath>

#include "compare/colour_difference.h"
#include "compare/surface_gaussian.h"
#include "core/rng.h"

namespace pl {

DeltaEStats meanAndP95(std::vector<float> values) {
    if (values.empty()) return {0, 0};
    double sum = 0;
    for (float v : values) sum += v;
    const size_t k = std::min(values.size() - 1, size_t(std::ceil(0.95 * double(values.size()))) - 1);
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return {sum / double(values.size()), values[k]};
}

namespace {

std::vector<float> deltaEs(const std::vector<RGB>& a, const std::vector<RGB>& b) {
    std::vector<float> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = float(ciede2000(labFromLinearSrgb(a[i]), labFromLinearSrgb(b[i])));
    return d;
}

// The error from its per-voxel values and those over the footprint.
SurfaceColourError errorOf(std::vector<float> perVoxel, const std::vector<float>& filtered) {
    SurfaceColourError e;
    const DeltaEStats raw = meanAndP95(perVoxel), over = meanAndP95(filtered);
    e.mean = raw.mean, e.p95 = raw.p95, e.meanFiltered = over.mean, e.p95Filtered = over.p95;
    e.perVoxel = std::move(perVoxel);
    return e;
}

}  // namespace

DeltaEStats deltaEStats(const std::vector<RGB>& a, const std::vector<RGB>& b) { return meanAndP95(deltaEs(a, b)); }

RGB deltaEColour(float deltaE) {
    const RGB stops[] = {{0.02f, 0.05f, 0.6f}, {0.05f, 0.5f, 0.1f}, {0.9f, 0.8f, 0.05f}, {0.8f, 0.02f, 0.02f}};
    const float at[] = {0.0f, 2.5f, 5.0f, 10.0f};
    if (!(deltaE > 0.0f)) return stops[0];
    for (int k = 1; k < 4; ++k)
        if (deltaE < at[k]) {
            const float f = (deltaE - at[k - 1]) / (at[k] - at[k - 1]);
            RGB c;
            for (int ch = 0; ch < 3; ++ch) c[ch] = stops[k - 1][ch] + f * (stops[k][ch] - stops[k - 1][ch]);
            return c;
        }
    return stops[3];
}

SurfaceColourError surfaceColourError(const std::vector<Point3f>& points_mm, const std::vector<RGB>& predicted,
                                      const std::vector<RGB>& reference, float footprintSigma_mm) {
    return surfaceColourError(SurfaceGaussian(points_mm, footprintSigma_mm), predicted, reference);
}

SurfaceColourError surfaceColourError(const SurfaceGaussian& footprint, const std::vector<RGB>& predicted,
                                      const std::vector<RGB>& reference) {
    return errorOf(deltaEs(predicted, reference), deltaEs(footprint.apply(predicted), footprint.apply(reference)));
}

std::vector<RGB> reflectance(const std::vector<RGB>& radiance, const RGB& environment) {
    std::vector<RGB> out(radiance.size());
    for (size_t i = 0; i < out.size(); ++i)
        for (int c = 0; c < 3; ++c) out[i][c] = environment[c] > 0 ? radiance[i][c] / environment[c] : 0.0f;
    return out;
}

std::vector<RGB> movedByNoise(const std::vector<RGB>& colours, const std::vector<RGB>& standardErrors, uint64_t seed) {
    std::vector<RGB> moved(colours);
    for (size_t i = 0; i < moved.size(); ++i) {
        Rng rng(seed, i);
        for (int c = 0; c < 3; ++c) {
            // Box-Muller: one normal deviate from two uniforms.
            const float u1 = std::max(rng.uniform(), 1e-12f), u2 = rng.uniform();
            moved[i][c] += standardErrors[i][c] * std::sqrt(-2.0f * std::log(u1)) * std::cos(2.0f * kPi * u2);
        }
    }
    return moved;
}

SurfaceColourError noiseColourError(const std::vector<Point3f>& points_mm, const std::vector<RGB>& colours,
                                    const std::vector<RGB>& standardErrors, uint64_t seed, float footprintSigma_mm) {
    return noiseColourError(SurfaceGaussian(points_mm, footprintSigma_mm), colours, standardErrors, seed);
}

SurfaceColourError noiseColourError(const SurfaceGaussian& footprint, const std::vector<RGB>& colours,
                                    const std::vector<RGB>& standardErrors, uint64_t seed) {
    const std::vector<RGB> moved = movedByNoise(colours, standardErrors, seed);
    return surfaceColourError(footprint, moved, colours);
}

namespace {
// (q(dA + dB) - q(dA - dB)) / 4 in CIELAB, q the squared CIEDE2000 from
// the reference (splitRenderError).
double squareNoiseRemoved(const RGB& halfA, const RGB& halfB, const RGB& reference) {
    const Lab r = labFromLinearSrgb(reference), a = labFromLinearSrgb(halfA), b = labFromLinearSrgb(halfB);
    const double dA[3] = {a.L - r.L, a.a - r.a, a.b - r.b}, dB[3] = {b.L - r.L, b.a - r.a, b.b - r.b};
    auto q = [&](double sign) {
        const Lab x{float(r.L + dA[0] + sign * dB[0]), float(r.a + dA[1] + sign * dB[1]), float(r.b + dA[2] + sign * dB[2])};
        const double e = ciede2000(r, x);
        return e * e;
    };
    return 0.25 * (q(1) - q(-1));
}
}  // namespace

SplitRenderError splitRenderError(const SurfaceGaussian& footprint, const std::vector<RGB>& halfA,
                                  const std::vector<RGB>& halfB, const std::vector<RGB>& reference) {
    const size_t n = reference.size();
    // The mean moved by half the halves' difference is half A itself.
    std::vector<RGB> mean(n);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) mean[i][c] = 0.5f * (halfA[i][c] + halfB[i][c]);
    // One pass of the footprint: it is linear, so the mean's follows.
    const std::vector<std::vector<RGB>> seen = footprint.apply(std::vector<const std::vector<RGB>*>{&halfA, &halfB, &reference});
    SplitRenderError out;
    out.meanSeen.resize(n);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) out.meanSeen[i][c] = 0.5f * (seen[0][i][c] + seen[1][i][c]);
    out.deltaESeen = deltaEs(out.meanSeen, seen[2]);
    out.error = errorOf(deltaEs(mean, reference), out.deltaESeen);
    out.noise = errorOf(deltaEs(halfA, mean), deltaEs(seen[0], out.meanSeen));
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += squareNoiseRemoved(seen[0][i], seen[1][i], seen[2][i]);
    out.rmsFilteredNoiseRemoved = std::sqrt(std::max(0.0, sum / double(std::max<size_t>(n, 1))));
    return out;
}

FootprintError footprintError(const RGB& a, const RGB& b, const RGB& reference) {
    RGB mean;
    for (int c = 0; c < 3; ++c) mean[c] = 0.5f * (a[c] + b[c]);
    const Lab m = labFromLinearSrgb(mean);
    return {ciede2000(labFromLinearSrgb(reference), m), ciede2000(labFromLinearSrgb(a), m),
            squareNoiseRemoved(a, b, reference)};
}

}  // namespace pl
