// The surface-voxel sensor's patches (sensor key "footprint": "patch"): the
// mesh surface cut along the voxel grid's cells, each cut piece given to the
// surface voxel whose centre is nearest to the piece's centroid (within two
// voxels; pieces with none nearer are left out and counted). A voxel's
// patch is the union of its pieces; its measurement is the radiance
// leaving the patch along each piece's outward (geometric) normal,
// averaged over the patch's area: what the eye integrates over the voxel's
// bit of surface, where the "ray" footprint takes one fixed ray
// (docs/surface-voxel-sensor.md). A patch keeps only which (triangle,
// cell) parts it owns, 8 bytes each; its pieces, the parts' polygons
// fanned into triangles with their areas, are cut again when asked for
// (the same operations, so the same bits as the first cut), so a patch is
// sampled uniformly by area without holding its geometry.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <absl/container/flat_hash_map.h>
#include <absl/functional/function_ref.h>

#include "core/geometry.h"
#include "core/grid_frame.h"

namespace pl {

class SurfacePatches {
public:
    // voxels: the surface voxels in sensor-pixel order.
    SurfacePatches(const TriangleMesh& mesh, const GridFrame& frame, const std::vector<Vec3i>& voxels);

    struct Piece {
        Point3f a, b, c;
        float area_mm2;
        uint32_t prim;  // the mesh triangle it was cut from
    };
    // The outward normal of a piece: its triangle's.
    const Vec3f& normal(const Piece& piece) const { return triangleNormal_[piece.prim]; }
    // Calls visit with pixel i's pieces in order until it returns false.
    void forEachPiece(size_t pixel, absl::FunctionRef<bool(const Piece&)> visit) const;
    // Pixel i's patch's area (0: no piece).
    double area_mm2(size_t pixel) const { return area_mm2_[pixel]; }

    // A point of pixel i's patch, uniform by area, from two uniform numbers,
    // and the normal there; none if the patch is empty.
    struct PatchPoint {
        Point3f p;
        Vec3f normal;
        uint32_t prim;
    };
    std::optional<PatchPoint> sample(size_t pixel, float u0, float u1) const;
    // The same from a pixel's pieces, cut once for many samples (piecesOf).
    void piecesOf(size_t pixel, std::vector<Piece>& pieces) const;
    std::optional<PatchPoint> sample(const std::vector<Piece>& pieces, float u0, float u1) const;

    // The pixel whose patch holds point x of triangle prim (light tracing
    // scores there); none where no piece of that triangle in x's cell has
    // an owner.
    std::optional<uint32_t> pixelAt(uint32_t prim, const Point3f& x_mm) const;

    // What the cut could not give to a surface voxel, and the voxels it
    // gave nothing (they keep the ray footprint).
    double unassignedArea_mm2() const { return unassignedArea_mm2_; }
    size_t emptyPatches() const { return emptyPatches_; }

private:
    // The cell a point of the mesh is in (cell coordinates floored).
    Vec3i cellOf(const Point3f& x_mm) const;
    // Where a (triangle, cell) pair is kept: the key of its triangle and
    // 8^3-cell brick, and the cell's slot in that brick.
    struct PieceSlot {
        uint64_t brickKey;
        uint16_t cellInBrick;
    };
    PieceSlot pieceSlot(uint32_t prim, const Vec3i& cell) const;
    // A part, (triangle, cell), as one number: the triangle above bit 40,
    // the cell's index in the frame widened by kCellMargin each side below.
    uint64_t partKey(uint32_t prim, const Vec3i& cell) const;
    // Parts lie within this many cells of the frame: their owner is within
    // two voxels of their centroid's cell (and rounding may add one).
    static constexpr int kCellMargin = 3;
    // A cell's coordinates in the widened frame (all >= 0 for a part).
    Vec3i widenedCell(const Vec3i& cell) const;
    Vec3i widenedResolution() const { return frame_.resolution + Vec3i{2 * kCellMargin, 2 * kCellMargin, 2 * kCellMargin}; }
    // Calls visit with a part's pieces in fan order; false once visit is.
    bool forEachPieceOfPart(uint64_t part, absl::FunctionRef<bool(const Piece&)> visit) const;
    // A point in millimetres to cell coordinates (voxel indices, continuous) and back.
    Point3f toCell(const Point3f& p_mm) const;
    Point3f toWorld(const Point3f& cell) const;

    GridFrame frame_;
    const TriangleMesh& mesh_;  // outlives the patches (the scene's)
    // The owners of the pieces, by (triangle, brick) and then by cell:
    // light tracing looks a pixel up per connection, and one particle's
    // track points fall in few bricks, whose entries stay in cache (a
    // table keyed by cell missed the cache on nearly every lookup).
    struct BrickCells {
        uint32_t first, count;  // into cellInBrick_ / ownerOfCell_, sorted by cell
    };
    absl::flat_hash_map<uint64_t, BrickCells> brickCells_;
    std::vector<uint16_t> cellInBrick_;
    std::vector<uint32_t> ownerOfCell_;
    std::vector<uint64_t> parts_;  // grouped by pixel, in triangle and then cut order
    std::vector<Vec3f> triangleNormal_;
    std::vector<uint32_t> firstPart_;
    std::vector<double> area_mm2_;
    double unassignedArea_mm2_ = 0;
    size_t emptyPatches_ = 0;
};

}  // namespace pl
