// Which mesh triangles' inward normal lines pass through a point inside the
// object: the triangles extruded inward along their outward normal n to a
// depth, as prisms, in an Embree BVH (user geometry, point queries). A
// point y lies on triangle T's line through x when x = y + s n lies on T
// with 0 < s <= depth. The prisms know no inside: whether the segment from
// y to x meets another surface first is the caller's to check. Light tracing into the surface-voxel sensor's
// patches connects a collision at y to every such x (docs/lighttrace.md,
// "The measurement, split three ways"): near an edge a point lies
// on the lines of both faces, where the mesh is curved it may lie on none.
#pragma once

#include <cstdint>
#include <memory>

#include "core/geometry.h"

namespace pl {

class PrismIndex {
public:
    PrismIndex(const TriangleMesh& mesh, float depth_mm);
    ~PrismIndex();
    PrismIndex(const PrismIndex&) = delete;
    PrismIndex& operator=(const PrismIndex&) = delete;

    // A triangle whose inward normal line passes through the point.
    struct Line {
        uint32_t prim;
        float s_mm;      // from the point to the triangle, along normal
        Point3f x_mm;    // where the line meets the triangle
        Vec3f normal;    // the triangle's outward normal
    };
    // visit(line) for each such triangle, in no particular order.
    template <class Visit>
    void forEachLine(const Point3f& y, Visit&& visit) const {
        linesThrough(y, [](void* f, const Line& line) { (*static_cast<Visit*>(f))(line); }, &visit);
    }
    float depth_mm() const;
    struct Impl;  // the prisms and the Embree scene (prism_index.cpp)

private:
    void linesThrough(const Point3f& y, void (*call)(void*, const Line&), void* visit) const;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pl
