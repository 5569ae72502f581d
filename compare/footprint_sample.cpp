#include "compare/footprint_sample.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
}  // namespace

FootprintSample::FootprintSample(const std::vector<Point3f>& points_mm, const SurfaceGaussian& eye, float sigma_mm,
                                 size_t count, uint64_t seed) {
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
        weights_.push_back(eye.footprintOf(order[pick].second));
        for (const SurfaceGaussian::Weight& w : weights_.back()) points_.push_back(w.point);
    }
    std::sort(points_.begin(), points_.end());
    points_.erase(std::unique(points_.begin(), points_.end()), points_.end());
}

std::vector<RGB> FootprintSample::apply(const std::vector<RGB>& values) const {
    std::vector<RGB> out(centres_.size(), RGB{0, 0, 0});
    for (size_t k = 0; k < centres_.size(); ++k) {
        double sum[3] = {0, 0, 0};
        for (const SurfaceGaussian::Weight& w : weights_[k])
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
    if (n < 2) {  // one stratum says nothing of the spread
        m.halfWidth95 = std::numeric_limits<double>::infinity();
        return m;
    }
    // Pairs (0, 1), (2, 3), ...; an odd last stratum pairs with the one
    // before it, its half of that pair's difference counted.
    double sumSquares = 0;
    for (size_t k = 0; k + 1 < n; k += 2) sumSquares += (values[k] - values[k + 1]) * (values[k] - values[k + 1]);
    if (n % 2 == 1) sumSquares += 0.5 * (values[n - 1] - values[n - 2]) * (values[n - 1] - values[n - 2]);
    const double standardError = std::sqrt(sumSquares) / double(n);
    m.halfWidth95 = studentTTwoSidedQuantile(0.05, double(n / 2)) * standardError;
    return m;
}

}  // namespace pl
