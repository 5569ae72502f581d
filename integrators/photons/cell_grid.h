// A uniform grid of cubic cells that files items (photons, beams) by the
// cells they lie in, for the photon estimators' range queries: a query
// within one cell side of a point or a segment visits the cells within one
// cell of those the point or segment is in. Cells are keyed by their
// coordinates; only occupied cells take memory (a sorted key list, not an
// array over the box), so its memory follows the items, whatever the
// object's size. Keys tell 2^21 cells a side apart (57 m at a 0.027 mm
// radius); items beyond are not filed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/vecmath.h"
#include "media/dda.h"

namespace pl {

class CellGrid {
public:
    // Cells of side side_mm from origin_mm (every item at or above it).
    CellGrid(float side_mm, const Point3f& origin_mm) : side_mm_(side_mm), origin_mm_(origin_mm) {}

    static constexpr uint64_t kNoCell = ~uint64_t(0);
    Vec3i cellOf(const Point3f& p) const;
    // kNoCell for a cell the keys cannot tell apart (below the origin or
    // 2^21 cells beyond it): no item is filed there.
    uint64_t keyOf(const Vec3i& cell) const;

    // Files the items: (cell key, item) pairs, in any order; an item may be
    // in several cells. A cell's items are then visited by ascending item.
    void fill(std::vector<std::pair<uint64_t, uint32_t>> entries);
    size_t entries() const { return items_.size(); }

    // The keys of the cells within one cell of those ray.at([0, tMax_mm])
    // crosses, ascending, each once.
    void cellsNear(const Ray& ray, float tMax_mm, std::vector<uint64_t>& keys) const;
    // The keys of the 27 cells around p's, ascending.
    void cellsAround(const Point3f& p, std::vector<uint64_t>& keys) const;
    // Calls f(key) for each cell ray.at([0, tMax_mm]) crosses, in order.
    template <class F>
    void forEachCellCrossed(const Ray& ray, float tMax_mm, F&& f) const;

    // Calls f(position, item) for the items filed in the cells `keys`
    // (ascending), in (key, item) order; position counts the entries in
    // that order (items filed once each can be stored in it).
    template <class F>
    void forEachItem(const std::vector<uint64_t>& keys, F&& f) const {
        auto from = keys_.begin();
        for (uint64_t key : keys) {
            from = std::lower_bound(from, keys_.end(), key);
            if (from == keys_.end()) return;
            if (*from != key) continue;
            const size_t k = size_t(from - keys_.begin());
            for (uint32_t i = starts_[k]; i < starts_[k + 1]; ++i) f(i, items_[i]);
        }
    }
    // The item at a position of the (key, item) order.
    uint32_t itemAt(size_t position) const { return items_[position]; }

private:
    float side_mm_;
    Point3f origin_mm_;
    std::vector<uint64_t> keys_;    // each occupied cell's key, ascending
    std::vector<uint32_t> starts_;  // where each key's items start (one more at the end)
    std::vector<uint32_t> items_;   // by (key, item)
};

template <class F>
void CellGrid::forEachCellCrossed(const Ray& ray, float tMax_mm, F&& f) const {
    const float inv = 1.0f / side_mm_;
    const Vec3f o = (ray.o - origin_mm_) * inv, d = ray.d * inv;
    const Vec3f e = o + d * tMax_mm;
    Vec3i lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = int(std::floor(std::min(o[a], e[a])));
        hi[a] = int(std::floor(std::max(o[a], e[a]))) + 1;
    }
    GridDda dda(o, d, 0.0f, tMax_mm, lo, hi);
    DdaSegment segment;
    while (dda.next(segment)) f(keyOf(segment.cell));
}

}  // namespace pl
