#include "integrators/photons/cell_grid.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>

namespace pl {

namespace {
// Cells per axis a key can tell apart.
constexpr int64_t kCellsPerAxis = int64_t(1) << 21;
}  // namespace

Vec3i CellGrid::cellOf(const Point3f& p) const {
    const Vec3f q = (p - origin_mm_) * (1.0f / side_mm_);
    return {int(std::floor(q.x)), int(std::floor(q.y)), int(std::floor(q.z))};
}

uint64_t CellGrid::keyOf(const Vec3i& cell) const {
    for (int a = 0; a < 3; ++a)
        if (cell[a] < 0 || cell[a] >= kCellsPerAxis) return kNoCell;
    return (uint64_t(cell.x) << 42) | (uint64_t(cell.y) << 21) | uint64_t(cell.z);
}

void CellGrid::fill(std::vector<std::pair<uint64_t, uint32_t>> entries) {
    // Sorted by (cell, item): one order whatever the threads.
    entries.erase(std::remove_if(entries.begin(), entries.end(), [](const auto& e) { return e.first == kNoCell; }),
                  entries.end());
    tbb::parallel_sort(entries.begin(), entries.end());
    keys_.clear();
    starts_.clear();
    items_.resize(entries.size());
    for (size_t i = 0; i < entries.size(); ++i) {
        items_[i] = entries[i].second;
        if (i == 0 || entries[i].first != entries[i - 1].first) {
            keys_.push_back(entries[i].first);
            starts_.push_back(uint32_t(i));
        }
    }
    starts_.push_back(uint32_t(items_.size()));
}

void CellGrid::cellsNear(const Ray& ray, float tMax_mm, std::vector<uint64_t>& keys) const {
    keys.clear();
    if (items_.empty()) return;
    // The segment in cell units (t stays in millimetres), walked cell by
    // cell inside the box of its ends, one cell wider.
    const float inv = 1.0f / side_mm_;
    const Vec3f o = (ray.o - origin_mm_) * inv, d = ray.d * inv;
    const Vec3f e = o + d * tMax_mm;
    Vec3i lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = int(std::floor(std::min(o[a], e[a]))) - 1;
        hi[a] = int(std::floor(std::max(o[a], e[a]))) + 2;
    }
    GridDda dda(o, d, 0.0f, tMax_mm, lo, hi);
    DdaSegment segment;
    while (dda.next(segment))
        for (int z = -1; z <= 1; ++z)
            for (int y = -1; y <= 1; ++y)
                for (int x = -1; x <= 1; ++x) {
                    const uint64_t key = keyOf(segment.cell + Vec3i{x, y, z});
                    if (key != kNoCell) keys.push_back(key);
                }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

void CellGrid::cellsAround(const Point3f& p, std::vector<uint64_t>& keys) const {
    keys.clear();
    if (items_.empty()) return;
    const Vec3i c = cellOf(p);
    // x outermost: the keys come out ascending (x in the high bits).
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) {
                const uint64_t key = keyOf(c + Vec3i{x, y, z});
                if (key != kNoCell) keys.push_back(key);
            }
}

}  // namespace pl
