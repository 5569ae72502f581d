#include "compare/surface_colour_error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <absl/container/flat_hash_map.h>

#include "compare/color_difference.h"
#include "runtime/scheduler.h"

namespace pl {

namespace {

struct Percentiles {
    double mean, p95;
};
Percentiles meanAndP95(std::vector<float> values) {
    if (values.empty()) return {0, 0};
    double sum = 0;
    for (float v : values) sum += v;
    const size_t k = std::min(values.size() - 1, size_t(0.95 * double(values.size())));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return {sum / double(values.size()), values[k]};
}

std::vector<float> deltaEs(const std::vector<RGB>& a, const std::vector<RGB>& b) {
    std::vector<float> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = float(ciede2000(labFromLinearSrgb(a[i]), labFromLinearSrgb(b[i])));
    return d;
}

}  // namespace

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

std::vector<RGB> gaussianOnSurface(const std::vector<Point3f>& points_mm, const std::vector<RGB>& values,
                                   float sigma_mm) {
    if (!(sigma_mm > 0)) return values;
    // Points binned in cells of 3 sigma: a point's neighbours lie in its
    // cell and the 26 around it.
    const float cell_mm = 3.0f * sigma_mm;
    auto cellOf = [&](const Point3f& p) {
        return Vec3i{int(std::floor(p.x / cell_mm)), int(std::floor(p.y / cell_mm)), int(std::floor(p.z / cell_mm))};
    };
    auto key = [](const Vec3i& c) {
        return (uint64_t(uint32_t(c.x) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y) & 0x1fffff) << 21) |
               uint64_t(uint32_t(c.z) & 0x1fffff);
    };
    absl::flat_hash_map<uint64_t, std::vector<uint32_t>> cells;
    for (size_t i = 0; i < points_mm.size(); ++i) cells[key(cellOf(points_mm[i]))].push_back(uint32_t(i));
    std::vector<RGB> out(values.size());
    const float inverseTwoSigmaSq = 1.0f / (2.0f * sigma_mm * sigma_mm), reachSq = cell_mm * cell_mm;
    parallelForTiles(points_mm.size(), 1024, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const Vec3i c = cellOf(points_mm[i]);
            double sum[3] = {0, 0, 0}, weights = 0;
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        auto found = cells.find(key({c.x + dx, c.y + dy, c.z + dz}));
                        if (found == cells.end()) continue;
                        for (uint32_t j : found->second) {
                            const Vec3f d = points_mm[j] - points_mm[i];
                            const float dSq = dot(d, d);
                            if (dSq > reachSq) continue;
                            const double w = std::exp(-dSq * inverseTwoSigmaSq);
                            weights += w;
                            for (int k = 0; k < 3; ++k) sum[k] += w * values[j][k];
                        }
                    }
            for (int k = 0; k < 3; ++k) out[i][k] = float(sum[k] / weights);
        }
    });
    return out;
}

SurfaceColourError surfaceColourError(const std::vector<Point3f>& points_mm, const std::vector<RGB>& predicted,
                                      const std::vector<RGB>& reference, float footprintSigma_mm) {
    SurfaceColourError e;
    e.perVoxel = deltaEs(predicted, reference);
    const Percentiles raw = meanAndP95(e.perVoxel);
    e.mean = raw.mean;
    e.p95 = raw.p95;
    const Percentiles filtered = meanAndP95(deltaEs(gaussianOnSurface(points_mm, predicted, footprintSigma_mm),
                                                    gaussianOnSurface(points_mm, reference, footprintSigma_mm)));
    e.meanFiltered = filtered.mean;
    e.p95Filtered = filtered.p95;
    return e;
}

}  // namespace pl
