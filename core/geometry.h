// The printed object's boundary: one closed triangle mesh behind Embree.
// Embree types stay in geometry.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/vecmath.h"

namespace pl {

// Triangles wound counter-clockwise seen from outside (outward normals).
struct TriangleMesh {
    std::vector<Point3f> positions_mm;
    std::vector<Vec3f> normals;  // per vertex, optional (empty if absent)
    std::vector<uint32_t> indices;
    size_t triangleCount() const { return indices.size() / 3; }
    double triangleArea_mm2(size_t t) const {
        const Point3f& a = positions_mm[indices[3 * t]];
        const Point3f& b = positions_mm[indices[3 * t + 1]];
        const Point3f& c = positions_mm[indices[3 * t + 2]];
        return 0.5 * double(length(cross(b - a, c - a)));
    }
};

// Axis-aligned box with outward counter-clockwise winding.
TriangleMesh boxMesh(const Point3f& lo, const Point3f& hi);

// Whether the closed mesh bounds a convex body: every vertex on the inner
// side of every triangle's plane, within 1e-5 of the mesh's diagonal. Light
// that leaves a convex object never meets it again, so there re-entry is
// nothing. Meshes with over 2e8 triangle-vertex pairs are not tested (false).
bool isConvex(const TriangleMesh& mesh);

struct Bounds3f {
    Point3f lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    void expand(const Point3f& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    bool empty() const { return lo.x > hi.x; }
};

struct SurfaceHit {
    float t;
    Point3f p;
    Vec3f ng;  // outward geometric normal (unit)
    Vec3f ns;  // outward shading normal (unit; equals ng without file normals)
    uint32_t prim;
};

struct ClosestSurfacePoint {
    Point3f p;
    Vec3f ng;  // outward normal of the triangle the point lies on
    float distance_mm;
    uint32_t prim;
};

class Geometry {
public:
    explicit Geometry(TriangleMesh mesh);
    ~Geometry();
    Geometry(const Geometry&) = delete;
    Geometry& operator=(const Geometry&) = delete;

    // Closest hit along the ray with t in [tMin, tMax].
    std::optional<SurfaceHit> intersect(const Ray& ray, float tMax = 1e30f, float tMin = 0.0f) const;  // from max(tMin, ray.tMin)
    // Closest hit, up to tMax, of a ray that starts inside the object (at a
    // collision in the medium). Round-off can put such a start on the
    // surface, which the ray then meets at t ~ 0 from outside: that hit is
    // passed over (the start is inside), not taken for a way out.
    std::optional<SurfaceHit> intersectFromInside(const Ray& ray, float tMax = 1e30f) const {
        auto hit = intersect(ray, tMax);
        if (hit && hit->t <= rayEpsilon_mm_ && dot(ray.d, hit->ng) < 0)
            hit = intersect(ray, tMax, hit->t + rayEpsilon_mm_);
        return hit;
    }
    // A ray that spawnRay started inside near an edge can leave through the
    // other face before its tMin, which skips the face it started on: the
    // nearest such exit (a face it leaves through, from its origin up to
    // tMin), or none.
    std::optional<SurfaceHit> exitBeforeTMin(const Ray& ray) const {
        Ray fromOrigin = ray;
        fromOrigin.tMin = 0.0f;
        auto hit = intersect(fromOrigin, ray.tMin);
        if (hit && dot(ray.d, hit->ng) > 0) return hit;
        return std::nullopt;
    }
    // The point of triangle prim at barycentrics (u, v) (v0 + u e1 + v e2),
    // with its normals; t is 0.
    SurfaceHit pointOn(uint32_t prim, float u, float v) const;
    // The same for a point p of triangle prim.
    SurfaceHit pointAt(uint32_t prim, const Point3f& p) const;
    // Closest point on the mesh within radius_mm of p.
    std::optional<ClosestSurfacePoint> closestPoint(const Point3f& p, float radius_mm) const;
    // Whether any triangle intersects the axis-aligned box [lo, hi].
    bool surfaceCrossesBox(const Point3f& lo, const Point3f& hi) const;

    const TriangleMesh& mesh() const { return mesh_; }
    Point3f triangleCentroid(uint32_t prim) const {
        const uint32_t* i = &mesh_.indices[3 * size_t(prim)];
        return (mesh_.positions_mm[i[0]] + mesh_.positions_mm[i[1]] + mesh_.positions_mm[i[2]]) / 3.0f;
    }
    Bounds3f bounds() const { return bounds_; }
    // Offset that moves a point off the surface robustly for this mesh's scale.
    float rayEpsilon_mm() const { return rayEpsilon_mm_; }
    // A few float ulps at the mesh's largest coordinate: how far off the
    // surface a spawned ray's origin sits (surely on the side it leaves to).
    float surfaceLift_mm() const { return surfaceLift_mm_; }

    // A ray leaving the surface point p (geometric normal ng) in direction d
    // (unit). Its origin is only surfaceLift off the surface, so the medium
    // right behind the surface is not skipped (at sigma_t 1e4/mm a
    // rayEpsilon offset would skip a mean free path); the surface itself is
    // skipped by tMin, the distance along d at which the ray is rayEpsilon
    // off the plane (capped at 16 rayEpsilon for grazing directions, whose
    // origin then lifts further). Into the object, the medium between the
    // surface and the origin is the ray's mediumBefore_mm (its flights
    // count it: flightFromSurface).
    Ray spawnRay(const Point3f& p, const Vec3f& ng, const Vec3f& d) const {
        float cosine = dot(d, ng);
        float side = cosine > 0 ? 1.0f : -1.0f;
        float back = (rayEpsilon_mm_ - surfaceLift_mm_) / std::max(std::abs(cosine), 1.0f / 16.0f);
        Ray r{p + ng * (side * rayEpsilon_mm_) - d * back, d, back};
        if (cosine < 0) r.mediumBefore_mm = (rayEpsilon_mm_ + cosine * back) / -cosine;  // depth below the plane / |cos|
        return r;
    }

private:
    // The normals and primitive of the point (u, v) of a triangle (no point).
    SurfaceHit normalsAt(uint32_t prim, float u, float v) const;

    struct Impl;
    std::unique_ptr<Impl> impl_;
    TriangleMesh mesh_;
    std::vector<Vec3f> faceNormals_;  // per triangle, unit (every hit needs one)
    Bounds3f bounds_;
    float rayEpsilon_mm_, surfaceLift_mm_;
};

}  // namespace pl
