#include "core/surface_patches.h"

#include "core/nearest_surface_voxel.h"
#include "core/sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace pl {

namespace {

using Polygon = std::vector<Point3f>;  // in cell coordinates

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

// Calls visit(cell, polygon) for the non-empty parts of the polygon in each
// unit cell it crosses, cutting along z, then y, then x.
template <class Visit>
void cutIntoCells(const Polygon& poly, int axis, Vec3i cell, Visit&& visit) {
    if (axis < 0) {
        visit(cell, poly);
        return;
    }
    float lo = 1e30f, hi = -1e30f;
    for (const Point3f& p : poly) {
        lo = std::min(lo, p[axis]);
        hi = std::max(hi, p[axis]);
    }
    const int first = int(std::floor(lo)), last = int(std::floor(hi));
    for (int k = first; k <= last; ++k) {
        Polygon slab = first == last ? poly : clip(clip(poly, axis, float(k), true), axis, float(k + 1), false);
        if (slab.size() < 3) continue;
        cell[axis] = k;
        cutIntoCells(slab, axis - 1, cell, visit);
    }
}


// A cell's part of a triangle: the pixel it is given to, how many pieces
// it gives, and where the first goes in the pixels' pieces.
struct CellOwner {
    Vec3i cell;
    uint32_t pixel;
    uint32_t pieces;
    uint64_t firstPiece;
};

}  // namespace

Vec3i SurfacePatches::cellOf(const Point3f& x_mm) const {
    const Vec3f scale = frame_.worldToCellScale(), offset = frame_.worldToCellOffset();
    return {int(std::floor(x_mm.x * scale.x + offset.x)), int(std::floor(x_mm.y * scale.y + offset.y)),
            int(std::floor(x_mm.z * scale.z + offset.z))};
}

SurfacePatches::PieceSlot SurfacePatches::pieceSlot(uint32_t prim, const Vec3i& cell) const {
    // The cell's index in the frame widened by 2 cells each side (the mesh
    // lies within a cell of the frame); its brick's index below 2^40, the
    // triangle above.
    const Vec3i c = cell - frame_.indexMin + Vec3i{2, 2, 2};
    const Vec3i r = frame_.resolution;
    const Vec3i bricks{(r.x + 4 + 7) >> 3, (r.y + 4 + 7) >> 3, (r.z + 4 + 7) >> 3};
    const Vec3i b{c.x >> 3, c.y >> 3, c.z >> 3};
    const uint64_t brick = (uint64_t(b.z) * uint64_t(bricks.y) + uint64_t(b.y)) * uint64_t(bricks.x) + uint64_t(b.x);
    return {(uint64_t(prim) << 40) | brick, uint16_t((c.x & 7) | (c.y & 7) << 3 | (c.z & 7) << 6)};
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

SurfacePatches::SurfacePatches(const TriangleMesh& mesh, const GridFrame& frame, const std::vector<Vec3i>& voxels)
    : frame_(frame) {
    const Vec3i& r = frame.resolution;
    if (mesh.triangleCount() >= (size_t(1) << 24) || double(r.x + 4) * (r.y + 4) * (r.z + 4) >= 0x1p40)
        throw std::runtime_error("the patch footprint takes at most 2^24 triangles and about 10^12 voxels");
    const NearestSurfaceVoxel table(frame, voxels);
    const Vec3f scale = frame.worldToCellScale(), offset = frame.worldToCellOffset();
    auto toCell = [&](const Point3f& p) {
        return Point3f(p.x * scale.x + offset.x, p.y * scale.y + offset.y, p.z * scale.z + offset.z);
    };
    auto toWorld = [&](const Point3f& c) {
        return Point3f((c.x - offset.x) / scale.x, (c.y - offset.y) / scale.y, (c.z - offset.z) / scale.z);
    };
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
    // Each cell's part of a triangle, fanned into pieces in millimetres
    // (none of no area), with their total area and centroid.
    auto fanOf = [&](size_t t, const Polygon& cellPoly, std::vector<Piece>& fan, double& area, Vec3f& centroid) {
        Polygon w(cellPoly.size());
        for (size_t i = 0; i < w.size(); ++i) w[i] = toWorld(cellPoly[i]);
        fan.clear();
        area = 0.0;
        centroid = Vec3f(0, 0, 0);
        for (size_t i = 1; i + 1 < w.size(); ++i) {
            const float pieceArea = 0.5f * length(cross(w[i] - w[0], w[i + 1] - w[0]));
            if (!(pieceArea > 0.0f)) continue;
            fan.push_back({w[0], w[i], w[i + 1], pieceArea, uint32_t(t)});
            area += pieceArea;
            centroid = centroid + (w[0] + w[i] + w[i + 1]) * (pieceArea / 3.0f);
        }
    };
    auto cellPolygons = [&](size_t t, auto&& visit) {
        const uint32_t* idx = &mesh.indices[3 * t];
        const Point3f& a = mesh.positions_mm[idx[0]];
        if (!(length(triangleNormal_[t]) > 0.0f)) return;
        Polygon poly{toCell(a), toCell(mesh.positions_mm[idx[1]]), toCell(mesh.positions_mm[idx[2]])};
        cutIntoCells(poly, 2, Vec3i{0, 0, 0}, visit);
    };
    // Two passes over the cut, so that the pieces are held once: the
    // first finds each cell's owner and how many pieces it gives it, the
    // second (the same cut again) writes the pieces in their places.
    std::vector<std::vector<CellOwner>> cellOwners(triangles);
    std::vector<double> unassigned(triangles, 0.0);
    tbb::parallel_for(size_t(0), triangles, [&](size_t t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        const Point3f& a = mesh.positions_mm[idx[0]];
        const Vec3f e = cross(mesh.positions_mm[idx[1]] - a, mesh.positions_mm[idx[2]] - a);
        if (length(e) > 0.0f) triangleNormal_[t] = normalize(e);  // else 0: cellPolygons skips it
        std::vector<Piece> fan;
        cellPolygons(t, [&](const Vec3i& cell, const Polygon& cellPoly) {
            double area;
            Vec3f centroid;
            fanOf(t, cellPoly, fan, area, centroid);
            if (fan.empty()) return;
            auto owner = ownerOf(centroid / float(area));
            if (!owner) {
                unassigned[t] += area;
                return;
            }
            cellOwners[t].push_back({cell, *owner, uint32_t(fan.size()), 0});
        });
    });

    // Group by pixel, in triangle order within a pixel (deterministic).
    std::vector<uint64_t> count(voxels.size() + 1, 0);
    for (const auto& list : cellOwners)
        for (const CellOwner& o : list) count[o.pixel + 1] += o.pieces;
    for (size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
    first_ = count;
    count = {};
    pieces_.resize(first_.back());
    std::vector<uint64_t> next(first_.begin(), first_.end() - 1);
    for (auto& list : cellOwners)
        for (CellOwner& o : list) {
            o.firstPiece = next[o.pixel];
            next[o.pixel] += o.pieces;
        }
    next = {};
    tbb::parallel_for(size_t(0), triangles, [&](size_t t) {
        // The cells come in the first pass's order; those it gave no owner
        // (or no pieces) are not in the list.
        size_t k = 0;
        const std::vector<CellOwner>& owners = cellOwners[t];
        std::vector<Piece> fan;
        cellPolygons(t, [&](const Vec3i& cell, const Polygon& cellPoly) {
            if (k == owners.size() || owners[k].cell != cell) return;
            double area;
            Vec3f centroid;
            fanOf(t, cellPoly, fan, area, centroid);
            // The same cut as the first pass's, so the same pieces.
            if (fan.size() != owners[k].pieces) throw std::logic_error("SurfacePatches: the second cut differs");
            std::copy(fan.begin(), fan.end(), pieces_.begin() + std::ptrdiff_t(owners[k].firstPiece));
            ++k;
        });
    });
    area_mm2_.assign(voxels.size(), 0.0);
    for (size_t i = 0; i < voxels.size(); ++i) {
        for (const Piece* p = begin(i); p != end(i); ++p) area_mm2_[i] += p->area_mm2;
        emptyPatches_ += first_[i] == first_[i + 1];
    }
    for (double a : unassigned) unassignedArea_mm2_ += a;
    struct SlotOwner {
        PieceSlot slot;
        uint32_t pixel;
    };
    std::vector<SlotOwner> owners;
    for (size_t t = 0; t < triangles; ++t)
        for (const CellOwner& o : cellOwners[t]) owners.push_back({pieceSlot(uint32_t(t), o.cell), o.pixel});
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

std::optional<SurfacePatches::PatchPoint> SurfacePatches::sample(size_t pixel, float u0, float u1) const {
    const Piece* b = begin(pixel);
    const Piece* e = end(pixel);
    if (b == e) return std::nullopt;
    // Pick a piece by area with u0, and reuse what is left of u0 inside it.
    float target = u0 * float(area_mm2_[pixel]);
    const Piece* p = b;
    for (; p + 1 != e && target >= p->area_mm2; ++p) target -= p->area_mm2;
    const float v0 = std::min(target / p->area_mm2, 0x1.fffffep-1f);
    const TriangleSample bary = sampleUniformTriangle(v0, u1);
    const Point3f x = p->a * bary.b0 + p->b * bary.b1 + p->c * bary.b2;
    return PatchPoint{x, triangleNormal_[p->prim], p->prim};
}

}  // namespace pl
