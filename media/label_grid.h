// The label grid: one 8-bit material id per voxel, stored sparsely in an
// OpenVDB tree (5-4-3). OpenVDB types stay behind this interface; only
// media/*.cpp and io/grid_io.cpp see them (through media/label_tree.h).
// Spaces and placement: core/grid_frame.h.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/grid_frame.h"
#include "core/vecmath.h"

namespace pl {

using Label = uint8_t;

// Largest grid accepted, in voxels (a dense 2^36-voxel job is absurd for
// printer-resolution objects and would not fit in memory as a dense read).
constexpr uint64_t kMaxGridVoxels = uint64_t(1) << 36;

class LabelGrid {
public:
    struct Tree;  // the OpenVDB tree, defined in media/label_tree.h

    LabelGrid();
    LabelGrid(GridFrame frame, Label voidLabel, std::shared_ptr<Tree> tree);
    ~LabelGrid();
    LabelGrid(LabelGrid&&) noexcept;
    LabelGrid& operator=(LabelGrid&&) noexcept;

    // Builds the sparse tree from dense labels, x fastest, then y, then z.
    static LabelGrid fromDense(const GridFrame& frame, const std::vector<Label>& labels,
                               Label voidLabel);
    // A copy with some voxels relabelled (the void label empties a voxel);
    // voxels outside the frame are an error (std::out_of_range).
    struct Change {
        Vec3i voxel;
        Label label;
    };
    LabelGrid withChanges(const std::vector<Change>& changes) const;
    // Cheap, conservative: true only if both trees have the same active
    // (non-void) topology; false may still mean the same void voxels.
    bool hasSameOccupancyTree(const LabelGrid& other) const;

    const GridFrame& frame() const { return frame_; }
    // Moves the grid in the world (the voxels keep their indices).
    void placeCornerAt(const Point3f& cornerMin_mm) { frame_.cornerMin_mm = cornerMin_mm; }
    Label voidLabel() const { return voidLabel_; }
    // Label of a voxel (void outside the frame). Slow path: no cached accessor.
    Label label(const Vec3i& v) const;
    // Dense copy over the frame, x fastest.
    std::vector<Label> toDense() const;

    // Visits every constant region inside the frame: whole tiles once, leaf
    // voxels one by one. Bounds are inclusive voxel coordinates.
    void visitRegions(const std::function<void(const Vec3i& lo, const Vec3i& hi, Label)>& fn) const;
    // Visits the labels each block of 2^log2 voxels holds inside the frame
    // (block = (voxel - origin) >> log2), void included where no stored value
    // covers a voxel: fn(block, label), maybe more than once for a pair.
    void visitBlockLabels(int log2, const Vec3i& origin,
                          const std::function<void(const Vec3i& block, Label)>& fn) const;
    // Number of voxels of each label inside the frame.
    std::array<uint64_t, 256> histogram() const;
    // Non-void voxels with a face neighbour that is void or outside the frame,
    // sorted by (z, y, x).
    std::vector<SurfaceVoxel> surfaceVoxels() const;
    // Bytes held by the sparse tree.
    uint64_t memoryBytes() const;

    const Tree& tree() const { return *tree_; }
    std::shared_ptr<Tree> treePtr() const { return tree_; }

private:
    GridFrame frame_;
    Label voidLabel_ = 0;
    std::shared_ptr<Tree> tree_;
};

// A label grid read through a cached accessor: fast where reads stay near
// each other. One thread at a time; the grid must outlive it unchanged.
class LabelReader {
public:
    explicit LabelReader(const LabelGrid& grid);
    ~LabelReader();
    // Void outside the frame, as LabelGrid::label.
    Label at(const Vec3i& v) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Builds a label grid voxel by voxel (single thread), collapsing uniform
// blocks into tiles as it goes.
class LabelGridBuilder {
public:
    LabelGridBuilder(const GridFrame& frame, Label voidLabel);
    ~LabelGridBuilder();
    void set(const Vec3i& voxel, Label label);
    // Collapses finished regions; call now and then to bound memory.
    void compact();
    LabelGrid finish();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pl
