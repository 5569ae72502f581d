#include "media/uniform_regions.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
    std::vector<uint32_t> covered(count, 0);
    // Stored tiles and voxels, cell by cell of their box.
    grid.visitRegions([&](const Vec3i& lo, const Vec3i& hi, Label l) {
        Vec3i clo, chi;
        for (int a = 0; a < 3; ++a) {
            clo[a] = (lo[a] - indexMin_[a]) >> kCellLog2;
            chi[a] = (hi[a] - indexMin_[a]) >> kCellLog2;
        }
        for (int z = clo.z; z <= chi.z; ++z)
            for (int y = clo.y; y <= chi.y; ++y)
                for (int x = clo.x; x <= chi.x; ++x) {
                    const int c[3] = {x, y, z};
                    uint32_t n = 1;
                    for (int a = 0; a < 3; ++a) {
                        const int first = indexMin_[a] + (c[a] << kCellLog2);
                        n *= uint32_t(std::min(hi[a], first + kCellSize - 1) - std::max(lo[a], first) + 1);
                    }
                    const size_t i = index({x, y, z});
                    covered[i] += n;
                    label_[i] = int16_t(see(label_[i], l));
                }
    });
    // Voxels no stored value covers hold the void label.
    for (int z = 0; z < cells_.z; ++z)
        for (int y = 0; y < cells_.y; ++y)
            for (int x = 0; x < cells_.x; ++x) {
                const int c[3] = {x, y, z};
                uint32_t n = 1;
                for (int a = 0; a < 3; ++a) n *= uint32_t(std::min(kCellSize, resolution_[a] - (c[a] << kCellLog2)));
                const size_t i = index({x, y, z});
                if (covered[i] < n) label_[i] = int16_t(see(label_[i], grid.voidLabel()));
            }
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
    for (const Vec3i& v : changed) {
        Vec3i c;
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            const int r = v[a] - indexMin_[a];
            inside = inside && r >= 0 && r < resolution_[a];
            c[a] = r >> kCellLog2;
        }
        if (inside) label_[index(c)] = int16_t(countCell(grid, c));
    }
    computeRadii(grid.voidLabel());
}

void UniformRegions::computeRadii(Label voidLabel) {
    // Per label: the squared gap to the nearest cell not of that label is a
    // sum over axes of per-axis terms, so three passes of one-dimensional
    // minima give it exactly (Saito and Toriwaki 1994). Void needs none:
    // nothing walks balls there.
    radius_mm_.assign(label_.size(), 0.0f);
    if (label_.empty()) return;
    constexpr float inf = std::numeric_limits<float>::infinity();
    Vec3f cell_mm;
    for (int a = 0; a < 3; ++a) cell_mm[a] = float(kCellSize) * voxel_mm_[a];
    // Squared gap along axis a between cells k apart (adjacent cells touch).
    auto gapSq = [&](int a, int k) {
        const float g = float(std::max(0, k - 1)) * cell_mm[a];
        return g * g;
    };
    // Squared gap from cell k along axis a to the outside of the frame.
    auto edgeGapSq = [&](int a, int k) {
        const int first = k << kCellLog2, end = first + kCellSize;
        const float g = float(std::max(0, std::min(first, resolution_[a] - end))) * voxel_mm_[a];
        return g * g;
    };
    std::vector<int> labels;
    for (int16_t l : label_)
        if (l >= 0 && l != int(voidLabel) && std::find(labels.begin(), labels.end(), int(l)) == labels.end())
            labels.push_back(l);
    std::vector<float> d(label_.size()), line;
    for (int label : labels) {
        for (size_t i = 0; i < d.size(); ++i) d[i] = label_[i] == label ? inf : 0.0f;
        for (int a = 0; a < 3; ++a) {
            const int n = cells_[a], b1 = (a + 1) % 3, b2 = (a + 2) % 3;
            // Stride of axis a, and the start of each line of cells along it.
            const size_t stride = a == 0 ? 1 : a == 1 ? size_t(cells_.x) : size_t(cells_.x) * cells_.y;
            line.resize(size_t(n));
            for (int v = 0; v < cells_[b2]; ++v)
                for (int u = 0; u < cells_[b1]; ++u) {
                    Vec3i c;
                    c[a] = 0;
                    c[b1] = u;
                    c[b2] = v;
                    const size_t start = index(c);
                    for (int k = 0; k < n; ++k) line[size_t(k)] = d[start + size_t(k) * stride];
                    for (int k = 0; k < n; ++k) {
                        float best = std::min(line[size_t(k)], edgeGapSq(a, k));
                        // Outwards until the gap alone is no better.
                        for (int j = 1; j < n; ++j) {
                            const float g = gapSq(a, j);
                            if (g >= best) break;
                            if (k - j >= 0) best = std::min(best, g + line[size_t(k - j)]);
                            if (k + j < n) best = std::min(best, g + line[size_t(k + j)]);
                        }
                        d[start + size_t(k) * stride] = best;
                    }
                }
        }
        for (size_t i = 0; i < d.size(); ++i)
            if (label_[i] == label) radius_mm_[i] = std::sqrt(d[i]);
    }
}

}  // namespace pl
