// A Gaussian filter over surface points (3D distances between the surface
// voxels' points): the eye's footprint for colour scores
// (surface_colour_error.h) and the optimisation loop's update. Built once
// for a set of points, applied to any values on them.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <absl/container/flat_hash_map.h>

#include "core/rgb.h"
#include "core/vecmath.h"

namespace pl {

class SurfaceGaussian {
public:
    SurfaceGaussian(const std::vector<Point3f>& points_mm, float sigma_mm);
    // values averaged with weights exp(-d^2 / (2 sigma^2)) over the points
    // within 3 sigma of each point (the same bits whatever the threads).
    std::vector<RGB> apply(const std::vector<RGB>& values) const;
    // The same for several lists of values at once (the weights are
    // computed once).
    std::vector<std::vector<RGB>> apply(const std::vector<const std::vector<RGB>*>& lists) const;
    // One point's footprint: the points within 3 sigma and their weights,
    // normalised (the weights apply() gives that point).
    struct Weight {
        uint32_t point;
        float weight;
    };
    std::vector<Weight> footprintOf(uint32_t point) const;

private:
    float sigma_mm_;
    // Points binned in cells of 3 sigma, stored cell by cell: a point's
    // neighbours lie in its cell and the 26 around it.
    struct Cell {
        uint32_t first, count;                // into order_ / sorted_
        std::array<int32_t, 27> neighbours;  // cell indices, -1: empty
    };
    std::vector<uint32_t> order_;   // point index, cell by cell
    std::vector<uint32_t> placeOf_;  // per point: its place in order_
    std::vector<uint32_t> cellOf_;   // per place: its cell
    std::vector<Point3f> sorted_mm_;
    std::vector<Cell> cells_;
    // visit(place, weight) for the points within 3 sigma of the one at
    // `place` (in `cell`), by their places.
    template <class Visit>
    void forEachNeighbour(uint32_t place, const Cell& cell, Visit&& visit) const;
};

// A wide Gaussian over surface points, for scales several times the eye's
// footprint where SurfaceGaussian's every pair of points would cost too
// much: the points' values are averaged per cell of cell_mm, and each
// point takes the cells' means weighted by their point counts and a
// Gaussian of the distance to the cells' centroids (within 3 sigma).
class CellSurfaceGaussian {
public:
    CellSurfaceGaussian(const std::vector<Point3f>& points_mm, float sigma_mm, float cell_mm);
    std::vector<RGB> apply(const std::vector<RGB>& values) const;

private:
    std::vector<Point3f> points_mm_;
    std::vector<uint32_t> cellOfPoint_;
    std::vector<Point3f> centroid_mm_;
    std::vector<uint32_t> pointCount_;
    std::vector<std::vector<uint32_t>> nearCells_;  // per cell: the cells within 3 sigma plus a cell's diagonal
    float sigma_mm_;
};

// One-off: SurfaceGaussian(points_mm, sigma_mm).apply(values); sigma 0
// returns the values.
std::vector<RGB> gaussianOnSurface(const std::vector<Point3f>& points_mm, const std::vector<RGB>& values,
                                   float sigma_mm);

}  // namespace pl
