#include "core/surface_patches.h"

#include "core/nearest_surface_voxel.h"
#include "core/sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace pl {

namespace {

// A convex polygon in cell coordinates: a triangle cut by at most six
// planes, each of which adds at most one corner (room for rounding's).
struct Polygon {
    std::array<Point3f, 16> corner;
    size_t n = 0;
    size_t size() const { return n; }
    const Point3f& operator[](size_t i) const { return corner[i]; }
    Point3f& operator[](size_t i) { return corner[i]; }
    void push_back(const Point3f& p) {
        if (n == corner.size()) throw std::logic_error("SurfacePatches: a cut polygon has too many corners");
        corner[n++] = p;
    }
};

// The part of the convex polygon with coordinate `axis` >= value (keepAbove)
// or <= value (Sutherland-Hodgman against one plane).
Polygon clip(const Polygon& poly, int axis, float value, bool keepAbove) {
    Polygon out;
    const size_t n = poly.size();
    for (size_t i = 0; i < n; ++i) {
        const Point3f& p = poly[i];
        const Point3f& q = poly[(i + 1) % n];
        const float dp = keepAbove ? p[axis] - value : value - p[axis];
        const float dq = keepAbove ? q[axis] - value : value - q[axis];
        if (dp >= 0.0f) out.push_back(p);
        if ((dp >= 0.0f) != (dq >= 0.0f)) {
            Point3f x = p + (q - p) * (dp / (dp - dq));
            x[axis] = value;  // exactly on the plane
            out.push_back(x);
        }
    }
    return out;
}

// The first and last cells the polygon reaches along an axis.
std::pair<int, int> cellSpan(const Polygon& poly, int axis) {
    float lo = 1e30f, hi = -1e30f;
    for (size_t i = 0; i < poly.size(); ++i) {
        lo = std::min(lo, poly[i][axis]);
        hi = std::max(hi, poly[i][axis]);
    }
    return {int(std::floor(lo)), int(std::floor(hi))};
}

// The polygon's part in cell k along an axis (itself if it lies in one).
Polygon slabOf(const Polygon& poly, int axis, int k, bool inOneCell) {
    return inOneCell ? poly : clip(clip(poly, axis, float(k), true), axis, float(k + 1), false);
}

// Calls visit(cell, polygon) for the non-empty parts of the polygon in each
// unit cell it crosses, cutting along z, then y, then x.
template <class Visit>
void cutIntoCells(const Polygon& poly, int axis, Vec3i cell, Visit&& visit) {
    if (axis < 0) {
        visit(cell, poly);
        return;
    }
    const auto [first, last] = cellSpan(poly, axis);
    for (int k = first; k <= last; ++k) {
        Polygon slab = slabOf(poly, axis, k, first == last);
        if (slab.size() < 3) continue;
        cell[axis] = k;
        cutIntoCells(slab, axis - 1, cell, visit);
    }
}

// The part of the polygon in one cell, by the same operations as
// cutIntoCells (so the same bits); fewer than 3 corners if none.
Polygon cellPart(Polygon poly, const Vec3i& cell) {
    for (int axis = 2; axis >= 0 && poly.size() >= 3; --axis) {
        const auto [first, last] = cellSpan(poly, axis);
        poly = slabOf(poly, axis, cell[axis], first == last);
    }
    return poly;
}


// A cell's part of a triangle and the pixel it is given to.
struct CellOwner {
    Vec3i cell;
    uint32_t pixel;
};

}  // namespace

Vec3i SurfacePatches::cellOf(const Point3f& x_mm) const {
    const Vec3f scale = frame_.worldToCellScale(), offset = frame_.worldToCellOffset();
    return {int(std::floor(x_mm.x * scale.x + offset.x)), int(std::floor(x_mm.y * scale.y + offset.y)),
            int(std::floor(x_mm.z * scale.z + offset.z))};
}

Vec3i SurfacePatches::widenedCell(const Vec3i& cell) const {
    return cell - frame_.indexMin + Vec3i{kCellMargin, kCellMargin, kCellMargin};
}

SurfacePatches::PieceSlot SurfacePatches::pieceSlot(uint32_t prim, const Vec3i& cell) const {
    // The cell's brick's index in the widened frame below 2^40, the
    // triangle above.
    const Vec3i c = widenedCell(cell);
    const Vec3i r = widenedResolution();
    const Vec3i bricks{(r.x + 7) >> 3, (r.y + 7) >> 3, (r.z + 7) >> 3};
    const Vec3i b{c.x >> 3, c.y >> 3, c.z >> 3};
    const uint64_t brick = (uint64_t(b.z) * uint64_t(bricks.y) + uint64_t(b.y)) * uint64_t(bricks.x) + uint64_t(b.x);
    return {(uint64_t(prim) << 40) | brick, uint16_t((c.x & 7) | (c.y & 7) << 3 | (c.z & 7) << 6)};
}

uint64_t SurfacePatches::partKey(uint32_t prim, const Vec3i& cell) const {
    const Vec3i c = widenedCell(cell);
    const Vec3i r = widenedResolution();
    // A key out of range would name another triangle or cell.
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= r.x || c.y >= r.y || c.z >= r.z)
        throw std::logic_error("SurfacePatches: a part more than kCellMargin cells beyond the frame");
    return (uint64_t(prim) << 40) | ((uint64_t(c.z) * uint64_t(r.y) + uint64_t(c.y)) * uint64_t(r.x) + uint64_t(c.x));
}

std::optional<uint32_t> SurfacePatches::pixelAt(uint32_t prim, const Point3f& x_mm) const {
    const PieceSlot slot = pieceSlot(prim, cellOf(x_mm));
    auto it = brickCells_.find(slot.brickKey);
    if (it == brickCells_.end()) return std::nullopt;
    const uint16_t* b = cellInBrick_.data() + it->second.first;
    const uint16_t* e = b + it->second.count;
    const uint16_t* at = std::lower_bound(b, e, slot.cellInBrick);
    if (at == e || *at != slot.cellInBrick) return std::nullopt;
    return ownerOfCell_[at - cellInBrick_.data()];
}

Point3f SurfacePatches::toCell(const Point3f& p_mm) const {
    const Vec3f scale = frame_.worldToCellScale(), offset = frame_.worldToCellOffset();
    return Point3f(p_mm.x * scale.x + offset.x, p_mm.y * scale.y + offset.y, p_mm.z * scale.z + offset.z);
}

Point3f SurfacePatches::toWorld(const Point3f& c) const {
    const Vec3f scale = frame_.worldToCellScale(), offset = frame_.worldToCellOffset();
    return Point3f((c.x - offset.x) / scale.x, (c.y - offset.y) / scale.y, (c.z - offset.z) / scale.z);
}

namespace {

// A cell's part of a triangle fanned into pieces in millimetres (none of
// no area): visit gets each; returns false as soon as visit does.
template <class ToWorld, class Visit>
bool fanPieces(uint32_t prim, const Polygon& cellPoly, ToWorld&& toWorld, Visit&& visit) {
    Polygon w;
    for (size_t i = 0; i < cellPoly.size(); ++i) w.push_back(toWorld(cellPoly[i]));
    for (size_t i = 1; i + 1 < w.size(); ++i) {
        const float pieceArea = 0.5f * length(cross(w[i] - w[0], w[i + 1] - w[0]));
        if (!(pieceArea > 0.0f)) continue;
        if (!visit(SurfacePatches::Piece{w[0], w[i], w[i + 1], pieceArea, prim})) return false;
    }
    return true;
}

// A patch's area from its pieces, added in order in double: the same bits
// wherever it is asked for.
double patchArea_mm2(const std::vector<SurfacePatches::Piece>& pieces) {
    double area_mm2 = 0.0;
    for (const SurfacePatches::Piece& p : pieces) area_mm2 += p.area_mm2;
    return area_mm2;
}

// Triangle prim of the mesh in cell coordinates.
template <class ToCell>
Polygon trianglePolygon(const TriangleMesh& mesh, uint32_t prim, ToCell&& toCell) {
    const uint32_t* idx = &mesh.indices[3 * size_t(prim)];
    Polygon poly;
    for (int k = 0; k < 3; ++k) poly.push_back(toCell(mesh.positions_mm[idx[k]]));
    return poly;
}

}  // namespace

bool SurfacePatches::forEachPieceOfPart(uint64_t part, absl::FunctionRef<bool(const Piece&)> visit) const {
    const uint32_t prim = uint32_t(part >> 40);
    const uint64_t index = part & ((uint64_t(1) << 40) - 1);
    const Vec3i r = widenedResolution();
    const Vec3i c{int(index % uint64_t(r.x)), int(index / uint64_t(r.x) % uint64_t(r.y)),
                  int(index / (uint64_t(r.x) * uint64_t(r.y)))};
    const Polygon triangle = trianglePolygon(mesh_, prim, [&](const Point3f& p) { return toCell(p); });
    const Polygon poly = cellPart(triangle, c + frame_.indexMin - Vec3i{kCellMargin, kCellMargin, kCellMargin});
    return fanPieces(prim, poly, [&](const Point3f& p) { return toWorld(p); }, visit);
}

void SurfacePatches::forEachPiece(size_t pixel, absl::FunctionRef<bool(const Piece&)> visit) const {
    for (uint32_t k = firstPart_[pixel]; k < firstPart_[pixel + 1]; ++k)
        if (!forEachPieceOfPart(parts_[k], visit)) return;
}

SurfacePatches::SurfacePatches(const TriangleMesh& mesh, const GridFrame& frame, const std::vector<Vec3i>& voxels)
    : frame_(frame), mesh_(mesh) {
    const Vec3i w = widenedResolution();
    if (mesh.triangleCount() >= (size_t(1) << 24) || double(w.x) * w.y * w.z >= 0x1p40)
        throw std::runtime_error("the patch footprint takes at most 2^24 triangles and about 10^12 voxels");
    const NearestSurfaceVoxel table(frame, voxels);
    // The surface voxel whose centre is nearest to p (mm), within two voxels of p's cell.
    auto ownerOf = [&](const Point3f& p) -> std::optional<uint32_t> {
        const Vec3i at = cellOf(p);
        std::optional<uint32_t> best;
        float bestDistance2 = 1e30f;
        for (int reach = 1; reach <= 2 && !best; ++reach)
            for (int dz = -reach; dz <= reach; ++dz)
                for (int dy = -reach; dy <= reach; ++dy)
                    for (int dx = -reach; dx <= reach; ++dx) {
                        const Vec3i v{at.x + dx, at.y + dy, at.z + dz};
                        const std::optional<uint32_t> pixel = table.pixelOf(v);
                        if (!pixel) continue;
                        const Vec3f d = frame.voxelCenter_mm(v) - p;
                        const float d2 = dot(d, d);
                        // Ties go to the lower pixel index: the same owner whatever the order.
                        if (d2 < bestDistance2 || (d2 == bestDistance2 && *pixel < *best)) {
                            bestDistance2 = d2;
                            best = *pixel;
                        }
                    }
        return best;
    };

    const size_t triangles = mesh.triangleCount();
    triangleNormal_.assign(triangles, Vec3f(0, 0, 0));
    // Each triangle's cut: its cells' parts and their owners, in cut order.
    std::vector<std::vector<CellOwner>> cellOwners(triangles);
    std::vector<double> unassigned(triangles, 0.0);
    tbb::parallel_for(size_t(0), triangles, [&](size_t t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        const Point3f& a = mesh.positions_mm[idx[0]];
        const Vec3f e = cross(mesh.positions_mm[idx[1]] - a, mesh.positions_mm[idx[2]] - a);
        if (!(length(e) > 0.0f)) return;  // no area, no normal: no pieces
        triangleNormal_[t] = normalize(e);
        const Polygon triangle = trianglePolygon(mesh, uint32_t(t), [&](const Point3f& p) { return toCell(p); });
        cutIntoCells(triangle, 2, Vec3i{0, 0, 0}, [&](const Vec3i& cell, const Polygon& cellPoly) {
            double area = 0.0;
            Vec3f centroid(0, 0, 0);
            fanPieces(uint32_t(t), cellPoly, [&](const Point3f& p) { return toWorld(p); }, [&](const Piece& piece) {
                area += piece.area_mm2;
                centroid = centroid + (piece.a + piece.b + piece.c) * (piece.area_mm2 / 3.0f);
                return true;
            });
            if (area == 0.0) return;
            auto owner = ownerOf(centroid / float(area));
            if (!owner) {
                unassigned[t] += area;
                return;
            }
            cellOwners[t].push_back({cell, *owner});
        });
    });

    // Group by pixel, in triangle order within a pixel (deterministic).
    std::vector<uint64_t> count(voxels.size() + 1, 0);
    for (const auto& list : cellOwners)
        for (const CellOwner& o : list) count[o.pixel + 1] += 1;
    for (size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
    if (count.back() >= (uint64_t(1) << 32))
        throw std::runtime_error("the patch footprint takes at most 2^32 (triangle, voxel) parts");
    firstPart_.assign(count.begin(), count.end());
    count = {};
    parts_.resize(firstPart_.back());
    std::vector<uint32_t> next(firstPart_.begin(), firstPart_.end() - 1);
    for (size_t t = 0; t < triangles; ++t)
        for (const CellOwner& o : cellOwners[t]) parts_[next[o.pixel]++] = partKey(uint32_t(t), o.cell);
    next = {};
    area_mm2_.assign(voxels.size(), 0.0);
    tbb::parallel_for(size_t(0), voxels.size(), [&](size_t i) {
        thread_local std::vector<Piece> pieces;
        piecesOf(i, pieces);
        area_mm2_[i] = patchArea_mm2(pieces);
    });
    for (size_t i = 0; i < voxels.size(); ++i) emptyPatches_ += firstPart_[i] == firstPart_[i + 1];
    for (double a : unassigned) unassignedArea_mm2_ += a;
    struct SlotOwner {
        PieceSlot slot;
        uint32_t pixel;
    };
    std::vector<SlotOwner> owners;
    owners.reserve(parts_.size());
    for (size_t t = 0; t < triangles; ++t) {
        for (const CellOwner& o : cellOwners[t]) owners.push_back({pieceSlot(uint32_t(t), o.cell), o.pixel});
        cellOwners[t] = {};
    }
    std::sort(owners.begin(), owners.end(), [](const SlotOwner& a, const SlotOwner& b) {
        return a.slot.brickKey != b.slot.brickKey ? a.slot.brickKey < b.slot.brickKey
                                                  : a.slot.cellInBrick < b.slot.cellInBrick;
    });
    cellInBrick_.reserve(owners.size());
    ownerOfCell_.reserve(owners.size());
    for (size_t i = 0; i < owners.size(); ++i) {
        BrickCells& cells = brickCells_[owners[i].slot.brickKey];
        if (cells.count == 0) cells.first = uint32_t(i);
        cells.count += 1;
        cellInBrick_.push_back(owners[i].slot.cellInBrick);
        ownerOfCell_.push_back(owners[i].pixel);
    }
}

void SurfacePatches::piecesOf(size_t pixel, std::vector<Piece>& pieces) const {
    pieces.clear();
    forEachPiece(pixel, [&](const Piece& p) {
        pieces.push_back(p);
        return true;
    });
}

std::optional<SurfacePatches::PatchPoint> SurfacePatches::sample(size_t pixel, float u0, float u1) const {
    thread_local std::vector<Piece> pieces;
    piecesOf(pixel, pieces);
    return sample(pieces, u0, u1);
}

std::optional<SurfacePatches::PatchPoint> SurfacePatches::sample(const std::vector<Piece>& pieces, float u0,
                                                                 float u1) const {
    if (pieces.empty()) return std::nullopt;
    // A piece picked by area with u0, and what is left of u0 reused inside it.
    float target = u0 * float(patchArea_mm2(pieces));
    auto p = pieces.begin();
    for (; p + 1 != pieces.end() && target >= p->area_mm2; ++p) target -= p->area_mm2;
    const float v0 = std::min(target / p->area_mm2, 0x1.fffffep-1f);
    const TriangleSample bary = sampleUniformTriangle(v0, u1);
    const Point3f x = p->a * bary.b0 + p->b * bary.b1 + p->c * bary.b2;
    return PatchPoint{x, triangleNormal_[p->prim], p->prim};
}

}  // namespace pl
