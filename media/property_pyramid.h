// The label grid's optical properties averaged over isotropic cubic cells
// of edge cellSize_mm(level) = base x 2^level: per cell the share of the
// volume the object fills, and the scattering and absorption coefficients
// averaged over the cell's volume (void counts as zero). The learned
// predictor's descriptor reads them at points of a stencil (trilinear),
// whatever the printer's (anisotropic) voxels.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "media/label_medium.h"

namespace pl {

struct CellProperties {
    float filled = 0;                       // share of the cell's volume inside the object
    std::array<float, 3> sigmaS_perMm{};    // per channel, averaged over the cell
    std::array<float, 3> sigmaA_perMm{};
};

class PropertyPyramid {
public:
    // Refuses (std::length_error) a pyramid over maxBytes.
    PropertyPyramid(const LabelMedium& medium, float baseCell_mm, int levels, uint64_t maxBytes);

    int levels() const { return int(levels_.size()); }
    float cellSize_mm(int level) const { return levels_[size_t(level)].cell_mm; }
    // Trilinear between cell centres; zero outside the grid.
    CellProperties at(int level, const Point3f& p_mm) const;
    uint64_t memoryBytes() const;

private:
    struct Level {
        float cell_mm = 0;
        Vec3i size{0, 0, 0};
        std::vector<CellProperties> cells;  // x fastest
        const CellProperties* cell(int x, int y, int z) const {
            if (x < 0 || y < 0 || z < 0 || x >= size.x || y >= size.y || z >= size.z) return nullptr;
            return &cells[(size_t(z) * size_t(size.y) + size_t(y)) * size_t(size.x) + size_t(x)];
        }
    };
    Point3f origin_mm_;  // lower corner of every level's cell (0, 0, 0)
    std::vector<Level> levels_;
};

}  // namespace pl
