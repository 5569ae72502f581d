#include "media/uniform_regions.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace pl {

namespace {

constexpr int kNoLabelYet = -2;

// Adds label l to the labels a cell was seen to hold.
int see(int cellLabel, int l) {
    return cellLabel == kNoLabelYet || cellLabel == l ? l : UniformRegions::kMixed;
}

}  // namespace

UniformRegions::UniformRegions(const LabelGrid& grid) {
    const GridFrame& f = grid.frame();
    indexMin_ = f.indexMin;
    resolution_ = f.resolution;
    voxel_mm_ = f.voxelSize_mm;
    for (int a = 0; a < 3; ++a) cells_[a] = (resolution_[a] + kCellSize - 1) >> kCellLog2;
    const size_t count = f.voxelCount() == 0 ? 0 : size_t(cells_.x) * cells_.y * cells_.z;
    label_.assign(count, kNoLabelYet);
    grid.visitBlockLabels(kCellLog2, indexMin_, [&](const Vec3i& cell, Label l) {
        int16_t& label = label_[index(cell)];
        label = int16_t(see(label, l));
    });
    computeRadii(grid.voidLabel());
}

int UniformRegions::countCell(const LabelGrid& grid, const Vec3i& c) const {
    int l = kNoLabelYet;
    Vec3i first, last;
    for (int a = 0; a < 3; ++a) {
        first[a] = indexMin_[a] + (c[a] << kCellLog2);
        last[a] = std::min(first[a] + kCellSize, indexMin_[a] + resolution_[a]);
    }
    for (int z = first.z; z < last.z; ++z)
        for (int y = first.y; y < last.y; ++y)
            for (int x = first.x; x < last.x; ++x) l = see(l, grid.label({x, y, z}));
    return l;
}

void UniformRegions::update(const LabelGrid& grid, const std::vector<Vec3i>& changed) {
    bool cellsChanged = false;
    for (const Vec3i& v : changed) {
        Vec3i c;
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            const int r = v[a] - indexMin_[a];
            inside = inside && r >= 0 && r < resolution_[a];
            c[a] = r >> kCellLog2;
        }
        if (!inside) continue;
        const int16_t l = int16_t(countCell(grid, c));
        cellsChanged = cellsChanged || l != label_[index(c)];
        label_[index(c)] = l;
    }
    // The radii are a function of the interior cells alone: relabelling the
    // voxels of a halftone's mixed cells, or cells next to them, changes none.
    if (cellsChanged) computeRadii(grid.voidLabel());
}

std::vector<int16_t> UniformRegions::interiorCells() const {
    // Erosion by the 3x3x3 box, one axis at a time: after the pass along
    // axis a, same[i] is the cell's label if the cells around it along the
    // axes done so far (and inside the frame) all hold it, else kMixed.
    std::vector<int16_t> same(label_), next(label_.size());
    for (int a = 0; a < 3; ++a) {
        const size_t stride = a == 0 ? 1 : a == 1 ? size_t(cells_.x) : size_t(cells_.x) * cells_.y;
        size_t i = 0;
        for (int z = 0; z < cells_.z; ++z)
            for (int y = 0; y < cells_.y; ++y)
                for (int x = 0; x < cells_.x; ++x, ++i) {
                    const int c = a == 0 ? x : a == 1 ? y : z;
                    const bool edge = c == 0 || c == cells_[a] - 1;
                    next[i] = !edge && same[i - stride] == same[i] && same[i + stride] == same[i] ? same[i]
                                                                                                 : int16_t(kMixed);
                }
        std::swap(same, next);
    }
    return same;
}

void UniformRegions::computeRadii(Label voidLabel) {
    // The gap from cell b to the nearest cell o not of b's label,
    // sum over axes of (max(0, |b - o| - 1) x cell edge)^2, equals the
    // distance between cell centres from b to the nearest cell that is not
    // interior (all 26 neighbours of its label): growing the other cells by
    // one in every direction is what the "- 1" does. So the radii depend on
    // the interior cells alone (updates that leave them as they were change
    // nothing, bit for bit), and a squared centre distance is a sum over
    // axes: three passes of one-dimensional minima give it exactly (Saito
    // and Toriwaki 1994). Cells that are not interior have radius 0.
    std::vector<int16_t> interior = interiorCells();
    if (interior == interior_ && radius_mm_.size() == label_.size()) return;
    interior_ = std::move(interior);
    radius_mm_.assign(label_.size(), 0.0f);
    if (label_.empty()) return;
    constexpr float inf = std::numeric_limits<float>::infinity();
    Vec3f cell_mm;
    for (int a = 0; a < 3; ++a) cell_mm[a] = float(kCellSize) * voxel_mm_[a];
    // Squared gap from cell k along axis a to the outside of the frame (the
    // last cell may be cut by the frame).
    auto edgeGapSq = [&](int a, int k) {
        const int first = k << kCellLog2, end = first + kCellSize;
        const float g = float(std::max(0, std::min(first, resolution_[a] - end))) * voxel_mm_[a];
        return g * g;
    };
    std::vector<int> labels;  // void aside: nothing walks balls there
    for (int16_t l : interior_)
        if (l >= 0 && l != int(voidLabel) && std::find(labels.begin(), labels.end(), int(l)) == labels.end())
            labels.push_back(l);
    const float maxSq = kMaxRadius_mm * kMaxRadius_mm;
    std::vector<float> d(label_.size());
    for (int label : labels) {
        for (size_t i = 0; i < d.size(); ++i) d[i] = interior_[i] == label ? inf : 0.0f;
        for (int a = 0; a < 3; ++a) {
            // Lines along axis a; neighbouring lines (along b1, the faster of
            // the other two axes) lie next to each other in memory.
            const int n = cells_[a], b1 = a == 0 ? 1 : 0, b2 = a == 2 ? 1 : 2;
            const size_t stride = a == 0 ? 1 : a == 1 ? size_t(cells_.x) : size_t(cells_.x) * cells_.y;
            // Lines are independent: planes of them side by side (the same
            // result for any thread count).
            tbb::parallel_for(0, cells_[b2], [&](int v) {
                std::vector<float> line(static_cast<size_t>(n));
                for (int u = 0; u < cells_[b1]; ++u) {
                    Vec3i c;
                    c[a] = 0;
                    c[b1] = u;
                    c[b2] = v;
                    const size_t start = index(c);
                    for (int k = 0; k < n; ++k) line[size_t(k)] = d[start + size_t(k) * stride];
                    for (int k = 0; k < n; ++k) {
                        float best = std::min({line[size_t(k)], edgeGapSq(a, k), maxSq});
                        // Outwards until the distance alone is no better.
                        for (int j = 1; j < n; ++j) {
                            const float g = float(j) * cell_mm[a] * (float(j) * cell_mm[a]);
                            if (g >= best) break;
                            if (k - j >= 0) best = std::min(best, g + line[size_t(k - j)]);
                            if (k + j < n) best = std::min(best, g + line[size_t(k + j)]);
                        }
                        d[start + size_t(k) * stride] = best;
                    }
                }
            });
        }
        for (size_t i = 0; i < d.size(); ++i)
            if (interior_[i] == label) radius_mm_[i] = std::sqrt(d[i]);
    }
}

}  // namespace pl
