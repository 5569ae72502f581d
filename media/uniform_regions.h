// Where the label grid is one material, and how far: per cell of 4^3 voxels
// its one label (or none) and a radius (mm) such that the ball of that radius
// around any point of the cell holds only that label. printpt walks such
// balls without grid lookups (media/ball_walk.h). The radius is the gap
// between the cell's box and the nearest cell that is mixed or holds another
// label, or the frame's edge (at most kMaxRadius_mm): exact as a lower
// bound, in mm with the voxels' own edges per axis. Cells are finer than the
// majorant bricks so that the ring of mixed cells at the surface (resin and
// the void skin) costs little depth.
#pragma once

#include <cstdint>
#include <vector>

#include "media/label_grid.h"

namespace pl {

class UniformRegions {
public:
    static constexpr int kCellLog2 = 2;
    static constexpr int kCellSize = 1 << kCellLog2;
    static constexpr int kMixed = -1;
    // Radii stop here: a ball walk of 12 mean free paths of red in white
    // resin already takes ~150 collisions, and the transform's cost grows
    // with the radius (it runs on every update of the prediction API).
    static constexpr float kMaxRadius_mm = 2.0f;

    UniformRegions() = default;
    explicit UniformRegions(const LabelGrid& grid);
    // After relabelling `changed` voxels of `grid`: their cells are recounted
    // and the radii recomputed where the interior cells changed (the result
    // of a full construction).
    void update(const LabelGrid& grid, const std::vector<Vec3i>& changed);

    // The one label of the voxel's cell (kMixed if several or outside the
    // frame) and the radius of its balls (0 where mixed, and for void).
    struct Cell {
        int label = kMixed;
        float radius_mm = 0.0f;
    };
    Cell at(const Vec3i& voxel) const {
        Vec3i c;
        for (int a = 0; a < 3; ++a) {
            const int v = voxel[a] - indexMin_[a];
            if (v < 0 || v >= resolution_[a]) return {};
            c[a] = v >> kCellLog2;
        }
        const size_t i = index(c);
        return {label_[i], radius_mm_[i]};
    }
    const Vec3i& cells() const { return cells_; }

private:
    size_t index(const Vec3i& c) const { return (size_t(c.z) * cells_.y + c.y) * cells_.x + c.x; }
    // The label of cell c from the grid's voxels, one by one.
    int countCell(const LabelGrid& grid, const Vec3i& c) const;
    // Per cell its label if the cell and its 26 neighbours (inside the
    // frame) all hold it, else kMixed.
    std::vector<int16_t> interiorCells() const;
    // The radii from the interior cells (nothing to do if they are as when
    // last computed).
    void computeRadii(Label voidLabel);
    Vec3i indexMin_{0, 0, 0}, resolution_{0, 0, 0}, cells_{0, 0, 0};
    Vec3f voxel_mm_{1, 1, 1};
    std::vector<int16_t> label_, interior_;
    std::vector<float> radius_mm_;
};

}  // namespace pl
