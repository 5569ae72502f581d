#include "compare/footprint_sample.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "compare/student_t.h"
#include "core/rng.h"

namespace pl {

namespace {
// Interleaves the low 21 bits of x, y, z (Morton order).
uint64_t spreadBits(uint32_t v) {
    uint64_t x = v & 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

Vec3i cellOf(const Point3f& p, float cell_mm) {
    return {int(std::floor(p.x / cell_mm)), int(std::floor(p.y / cell_mm)), int(std::floor(p.z / cell_mm))};
}

uint64_t cellKey(const Vec3i& c) {
    return (uint64_t(uint32_t(c.x) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y) & 0x1fffff) << 21) |
           uint64_t(uint32_t(c.z) & 0x1fffff);
}
}  // namespace

FootprintSample::FootprintSample(const std::vector<Point3f>& points_mm, float sigma_mm, size_t count, uint64_t seed) {
    const size_t n = points_mm.size();
    count = std::min(count, n);
    if (count == 0 || !(sigma_mm > 0)) return;
    // Strata: equal runs of the points in Morton order of cells of sigma.
    Point3f lo = points_mm.front();
    for (const Point3f& p : points_mm) lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    std::vector<std::pair<uint64_t, uint32_t>> order(n);
    for (size_t i = 0; i < n; ++i) {
        const Point3f& p = points_mm[i];
        const Vec3i c = cellOf({p.x - lo.x, p.y - lo.y, p.z - lo.z}, sigma_mm);
        order[i] = {spreadBits(uint32_t(c.x)) | spreadBits(uint32_t(c.y)) << 1 | spreadBits(uint32_t(c.z)) << 2,
                    uint32_t(i)};
    }
    std::sort(order.begin(), order.end());
    Rng rng(seed, 0x666f6f74ULL);
    for (size_t k = 0; k < count; ++k) {
        const size_t begin = k * n / count, end = (k + 1) * n / count;
        const size_t pick = std::min(end - 1, begin + size_t(rng.uniform() * double(end - begin)));
        centres_.push_back(order[pick].second);
    }
    // Each centre's neighbours within 3 sigma, found through cells of 3 sigma.
    const float reach_mm = 3.0f * sigma_mm;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
    for (size_t i = 0; i < n; ++i) cells[cellKey(cellOf(points_mm[i], reach_mm))].push_back(uint32_t(i));
    weights_.resize(count);
    for (size_t k = 0; k < count; ++k) {
        const Point3f& c = points_mm[centres_[k]];
        const Vec3i at = cellOf(c, reach_mm);
        double total = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    auto found = cells.find(cellKey({at.x + dx, at.y + dy, at.z + dz}));
                    if (found == cells.end()) continue;
                    for (uint32_t j : found->second) {
                        const Point3f& p = points_mm[j];
                        const float d2 = (p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y) + (p.z - c.z) * (p.z - c.z);
                        if (d2 > reach_mm * reach_mm) continue;
                        const float w = std::exp(-d2 / (2 * sigma_mm * sigma_mm));
                        weights_[k].push_back({j, w});
                        total += w;
                        points_.push_back(j);
                    }
                }
        std::sort(weights_[k].begin(), weights_[k].end(), [](const Weight& a, const Weight& b) { return a.point < b.point; });
        for (Weight& w : weights_[k]) w.weight = float(w.weight / total);
    }
    std::sort(points_.begin(), points_.end());
    points_.erase(std::unique(points_.begin(), points_.end()), points_.end());
}

std::vector<RGB> FootprintSample::apply(const std::vector<RGB>& values) const {
    std::vector<RGB> out(centres_.size(), RGB{0, 0, 0});
    for (size_t k = 0; k < centres_.size(); ++k) {
        double sum[3] = {0, 0, 0};
        for (const Weight& w : weights_[k])
            for (int c = 0; c < 3; ++c) sum[c] += double(w.weight) * values[w.point][c];
        for (int c = 0; c < 3; ++c) out[k][c] = float(sum[c]);
    }
    return out;
}

SampledMean stratifiedMean(const std::vector<double>& values) {
    SampledMean m;
    const size_t n = values.size();
    if (n == 0) return m;
    for (double v : values) m.mean += v;
    m.mean /= double(n);
    if (n < 2) return m;
    // Pairs (0, 1), (2, 3), ...; an odd last stratum pairs with the one
    // before it, its half of that pair's difference counted.
    double sumSquares = 0;
    for (size_t k = 0; k + 1 < n; k += 2) sumSquares += (values[k] - values[k + 1]) * (values[k] - values[k + 1]);
    if (n % 2 == 1) sumSquares += 0.5 * (values[n - 1] - values[n - 2]) * (values[n - 1] - values[n - 2]);
    const double standardError = std::sqrt(sumSquares) / double(n);
    const double pairs = double(n / 2);
    // Student's t quantile for 95 % two-sided, by bisection on its tail.
    double lo = 0, hi = 100;
    for (int i = 0; i < 100; ++i) {
        const double t = 0.5 * (lo + hi);
        (studentTTwoSidedP(t, pairs) > 0.05 ? lo : hi) = t;
    }
    m.halfWidth95 = 0.5 * (lo + hi) * standardError;
    return m;
}

}  // namespace pl
