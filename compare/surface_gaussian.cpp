#include "compare/surface_gaussian.h"

#include <algorithm>
#include <cmath>

#include "runtime/scheduler.h"

namespace pl {

namespace {

// exp(-t) for t in [0, 4.5] (3 sigma's reach), tabulated with linear
// interpolation (relative error under 3e-6): the filter's every weight
// otherwise costs an exp.
class ExpTable {
public:
    static constexpr int kSteps = 1024;
    static constexpr float kEnd = 4.5f;
    ExpTable() {
        for (int k = 0; k <= kSteps + 1; ++k) value_[size_t(k)] = std::exp(-kEnd * float(k) / kSteps);
    }
    float operator()(float t) const {
        const float x = t * (kSteps / kEnd);
        const int k = std::min(int(x), kSteps);
        const float f = x - float(k);
        return value_[size_t(k)] + f * (value_[size_t(k) + 1] - value_[size_t(k)]);
    }

private:
    std::array<float, kSteps + 2> value_;
};

const ExpTable& expTable() {
    static const ExpTable table;
    return table;
}

uint64_t cellKey(const Vec3i& c) {
    return (uint64_t(uint32_t(c.x) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y) & 0x1fffff) << 21) |
           uint64_t(uint32_t(c.z) & 0x1fffff);
}
}  // namespace

SurfaceGaussian::SurfaceGaussian(const std::vector<Point3f>& points_mm, float sigma_mm) : sigma_mm_(sigma_mm) {
    const float cell_mm = 3.0f * sigma_mm;
    auto cellOf = [&](const Point3f& p) {
        return Vec3i{int(std::floor(p.x / cell_mm)), int(std::floor(p.y / cell_mm)), int(std::floor(p.z / cell_mm))};
    };
    std::vector<std::pair<uint64_t, uint32_t>> keyed(points_mm.size());
    for (size_t i = 0; i < points_mm.size(); ++i) keyed[i] = {cellKey(cellOf(points_mm[i])), uint32_t(i)};
    std::sort(keyed.begin(), keyed.end());
    absl::flat_hash_map<uint64_t, int32_t> cellAt;
    std::vector<Vec3i> cellCoords;
    for (size_t k = 0; k < keyed.size(); ++k) {
        const uint32_t i = keyed[k].second;
        order_.push_back(i);
        sorted_mm_.push_back(points_mm[i]);
        if (k == 0 || keyed[k].first != keyed[k - 1].first) {
            cellAt[keyed[k].first] = int32_t(cells_.size());
            cells_.push_back({uint32_t(k), 0, {}});
            cellCoords.push_back(cellOf(points_mm[i]));
        }
        ++cells_.back().count;
        cellOf_.push_back(uint32_t(cells_.size() - 1));
    }
    placeOf_.resize(order_.size());
    for (size_t k = 0; k < order_.size(); ++k) placeOf_[order_[k]] = uint32_t(k);
    for (size_t c = 0; c < cells_.size(); ++c) {
        int n = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const Vec3i& at = cellCoords[c];
                    auto found = cellAt.find(cellKey({at.x + dx, at.y + dy, at.z + dz}));
                    cells_[c].neighbours[size_t(n++)] = found == cellAt.end() ? -1 : found->second;
                }
    }
}

template <class Visit>
void SurfaceGaussian::forEachNeighbour(uint32_t place, const Cell& cell, Visit&& visit) const {
    const float inverseTwoSigmaSq = 1.0f / (2.0f * sigma_mm_ * sigma_mm_), reachSq = 9.0f * sigma_mm_ * sigma_mm_;
    const ExpTable& expOf = expTable();
    const Point3f& x = sorted_mm_[place];
    for (int32_t n : cell.neighbours) {
        if (n < 0) continue;
        const Cell& other = cells_[size_t(n)];
        for (uint32_t j = other.first; j < other.first + other.count; ++j) {
            const Vec3f d = sorted_mm_[j] - x;
            const float dSq = dot(d, d);
            if (dSq <= reachSq) visit(j, expOf(dSq * inverseTwoSigmaSq));
        }
    }
}

std::vector<RGB> SurfaceGaussian::apply(const std::vector<RGB>& values) const {
    return std::move(apply(std::vector<const std::vector<RGB>*>{&values}).front());
}

std::vector<std::vector<RGB>> SurfaceGaussian::apply(const std::vector<const std::vector<RGB>*>& lists) const {
    const size_t m = lists.size();
    // Values cell by cell, the lists' values of one point side by side.
    std::vector<RGB> sortedValues(order_.size() * m);
    for (size_t k = 0; k < order_.size(); ++k)
        for (size_t l = 0; l < m; ++l) sortedValues[k * m + l] = (*lists[l])[order_[k]];
    std::vector<std::vector<RGB>> out(m, std::vector<RGB>(order_.size()));
    parallelForTiles(cells_.size(), 16, [&](size_t begin, size_t end) {
        std::vector<double> sum(3 * m);
        for (size_t c = begin; c < end; ++c) {
            const Cell& cell = cells_[c];
            for (uint32_t k = cell.first; k < cell.first + cell.count; ++k) {
                std::fill(sum.begin(), sum.end(), 0.0);
                double weights = 0;
                forEachNeighbour(k, cell, [&](uint32_t j, float w) {
                    weights += w;
                    const RGB* v = &sortedValues[size_t(j) * m];
                    for (size_t l = 0; l < m; ++l)
                        for (int ch = 0; ch < 3; ++ch) sum[3 * l + size_t(ch)] += w * v[l][size_t(ch)];
                });
                for (size_t l = 0; l < m; ++l)
                    for (int ch = 0; ch < 3; ++ch) out[l][order_[k]][size_t(ch)] = float(sum[3 * l + size_t(ch)] / weights);
            }
        }
    });
    return out;
}

std::vector<SurfaceGaussian::Weight> SurfaceGaussian::footprintOf(uint32_t point) const {
    const uint32_t k = placeOf_[point];
    std::vector<Weight> out;
    double weights = 0;
    forEachNeighbour(k, cells_[cellOf_[k]], [&](uint32_t j, float w) {
        weights += w;
        out.push_back({order_[j], w});
    });
    for (Weight& w : out) w.weight = float(w.weight / weights);
    return out;
}

CellSurfaceGaussian::CellSurfaceGaussian(const std::vector<Point3f>& points_mm, float sigma_mm, float cell_mm)
    : points_mm_(points_mm), cellOfPoint_(points_mm.size()), sigma_mm_(sigma_mm) {
    auto cellOf = [&](const Point3f& p) {
        return Vec3i{int(std::floor(p.x / cell_mm)), int(std::floor(p.y / cell_mm)), int(std::floor(p.z / cell_mm))};
    };
    absl::flat_hash_map<uint64_t, uint32_t> cellAt;
    std::vector<Vec3i> coords;
    std::vector<std::array<double, 3>> sums;
    for (size_t i = 0; i < points_mm.size(); ++i) {
        const Vec3i c = cellOf(points_mm[i]);
        auto [it, fresh] = cellAt.try_emplace(cellKey(c), uint32_t(coords.size()));
        if (fresh) {
            coords.push_back(c);
            sums.push_back({0, 0, 0});
            pointCount_.push_back(0);
        }
        cellOfPoint_[i] = it->second;
        sums[it->second][0] += points_mm[i].x, sums[it->second][1] += points_mm[i].y, sums[it->second][2] += points_mm[i].z;
        ++pointCount_[it->second];
    }
    for (size_t c = 0; c < coords.size(); ++c)
        centroid_mm_.push_back({float(sums[c][0] / pointCount_[c]), float(sums[c][1] / pointCount_[c]),
                                float(sums[c][2] / pointCount_[c])});
    const int reach = int(std::ceil(3.0f * sigma_mm / cell_mm)) + 1;
    nearCells_.resize(coords.size());
    parallelForTiles(coords.size(), 16, [&](size_t begin, size_t end) {
        for (size_t c = begin; c < end; ++c)
            for (int dz = -reach; dz <= reach; ++dz)
                for (int dy = -reach; dy <= reach; ++dy)
                    for (int dx = -reach; dx <= reach; ++dx) {
                        if (dx * dx + dy * dy + dz * dz > reach * reach) continue;
                        const Vec3i& at = coords[c];
                        auto found = cellAt.find(cellKey({at.x + dx, at.y + dy, at.z + dz}));
                        if (found != cellAt.end()) nearCells_[c].push_back(found->second);
                    }
    });
}

std::vector<RGB> CellSurfaceGaussian::apply(const std::vector<RGB>& values) const {
    std::vector<std::array<double, 3>> cellSum(centroid_mm_.size(), {0, 0, 0});
    for (size_t i = 0; i < values.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) cellSum[cellOfPoint_[i]][size_t(ch)] += values[i][size_t(ch)];
    std::vector<RGB> out(values.size());
    const float inverseTwoSigmaSq = 1.0f / (2.0f * sigma_mm_ * sigma_mm_), reachSq = 9.0f * sigma_mm_ * sigma_mm_;
    parallelForTiles(values.size(), 256, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            double sum[3] = {0, 0, 0}, weights = 0;
            for (uint32_t c : nearCells_[cellOfPoint_[i]]) {
                const Vec3f d = centroid_mm_[c] - points_mm_[i];
                const float dSq = dot(d, d);
                if (dSq > reachSq) continue;
                const double w = std::exp(-dSq * inverseTwoSigmaSq);  // per point of the cell
                weights += w * pointCount_[c];
                for (int ch = 0; ch < 3; ++ch) sum[ch] += w * cellSum[c][size_t(ch)];
            }
            for (int ch = 0; ch < 3; ++ch) out[i][size_t(ch)] = float(sum[ch] / weights);
        }
    });
    return out;
}

std::vector<RGB> gaussianOnSurface(const std::vector<Point3f>& points_mm, const std::vector<RGB>& values,
                                   float sigma_mm) {
    if (!(sigma_mm > 0)) return values;
    return SurfaceGaussian(points_mm, sigma_mm).apply(values);
}

}  // namespace pl
