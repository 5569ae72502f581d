#include "core/geometry.h"

#include "core/embree_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pl {

struct Geometry::Impl : EmbreeScene {};

namespace {

Vec3f triangleNormal(const TriangleMesh& m, uint32_t prim) {
    const Point3f& a = m.positions_mm[m.indices[3 * prim]];
    const Point3f& b = m.positions_mm[m.indices[3 * prim + 1]];
    const Point3f& c = m.positions_mm[m.indices[3 * prim + 2]];
    return normalize(cross(b - a, c - a));
}

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
Point3f closestPointOnTriangle(const Point3f& p, const Point3f& a, const Point3f& b,
                               const Point3f& c) {
    Vec3f ab = b - a, ac = c - a, ap = p - a;
    float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    Vec3f bp = p - b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    Vec3f cp = p - c;
    float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    float denom = 1.0f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Triangle / axis-aligned box overlap by the separating axis theorem
// (Akenine-Moeller 2001): box axes, triangle normal, and the nine edge cross
// products.
bool triangleOverlapsBox(const Point3f& center, const Vec3f& half, Point3f a, Point3f b, Point3f c) {
    a = a - center;
    b = b - center;
    c = c - center;
    auto separated = [&](const Vec3f& axis) {
        float pa = dot(a, axis), pb = dot(b, axis), pc = dot(c, axis);
        float r = half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
        return std::min({pa, pb, pc}) > r || std::max({pa, pb, pc}) < -r;
    };
    const Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3f& e : axes)
        if (separated(e)) return false;
    Vec3f edges[3] = {b - a, c - b, a - c};
    if (separated(cross(edges[0], edges[1]))) return false;
    for (const Vec3f& e : edges)
        for (const Vec3f& u : axes)
            if (separated(cross(e, u))) return false;
    return true;
}

struct BoxQueryState {
    const TriangleMesh* mesh;
    Point3f center;
    Vec3f half;
    bool overlaps = false;
};

bool boxOverlapCallback(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<BoxQueryState*>(args->userPtr);
    const TriangleMesh& m = *state->mesh;
    const uint32_t* i = &m.indices[3 * size_t(args->primID)];
    if (!state->overlaps &&
        triangleOverlapsBox(state->center, state->half, m.positions_mm[i[0]], m.positions_mm[i[1]], m.positions_mm[i[2]])) {
        state->overlaps = true;
        args->query->radius = 0.0f;  // done: stop the search
        return true;
    }
    return false;
}

struct PointQueryState {
    const TriangleMesh* mesh;
    ClosestSurfacePoint best;
    uint32_t bestPrim = 0;
    bool found = false;
};

bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<PointQueryState*>(args->userPtr);
    const TriangleMesh& m = *state->mesh;
    uint32_t prim = args->primID;
    Point3f q(args->query->x, args->query->y, args->query->z);
    const Point3f& a = m.positions_mm[m.indices[3 * prim]];
    const Point3f& b = m.positions_mm[m.indices[3 * prim + 1]];
    const Point3f& v2 = m.positions_mm[m.indices[3 * prim + 2]];
    Point3f c = closestPointOnTriangle(q, a, b, v2);
    float d = length(c - q);
    // Ties (points on shared edges) go to the lowest primitive id, so the
    // answer does not depend on BVH traversal order.
    bool better = state->found ? (d < state->best.distance_mm ||
                                  (d == state->best.distance_mm && prim < state->bestPrim))
                               : d <= args->query->radius;
    if (better) {
        args->query->radius = d;
        state->best = {c, triangleNormal(m, prim), d, prim};
        state->bestPrim = prim;
        state->found = true;
        return true;  // the query radius shrank
    }
    return false;
}

}  // namespace

Geometry::Geometry(TriangleMesh mesh) : impl_(std::make_unique<Impl>()), mesh_(std::move(mesh)) {
    for (const Point3f& p : mesh_.positions_mm) bounds_.expand(p);
    faceNormals_.reserve(mesh_.triangleCount());
    for (size_t t = 0; t < mesh_.triangleCount(); ++t) faceNormals_.push_back(triangleNormal(mesh_, uint32_t(t)));
    float maxAbs = 0;
    for (int a = 0; a < 3; ++a)
        maxAbs = std::max({maxAbs, std::abs(bounds_.lo[a]), std::abs(bounds_.hi[a])});
    // ~64 float ulps at the mesh's largest coordinate, and never below 0.1 um.
    rayEpsilon_mm_ = std::max(1e-4f, maxAbs * 64.0f * 1.2e-7f);
    surfaceLift_mm_ = std::max(1e-7f, maxAbs * 4.0f * 1.2e-7f);

    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads the last vertex with a 16-byte load: a buffer of its own
    // (over-allocated by Embree), not a view of positions_mm, which ends
    // 4 bytes too early (valgrind: invalid read past the vector).
    static_assert(sizeof(Point3f) == 3 * sizeof(float), "FLOAT3 vertices");
    auto* vertices = static_cast<Point3f*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                    sizeof(Point3f), mesh_.positions_mm.size()));
    if (!vertices) throw std::runtime_error("cannot allocate the Embree vertex buffer");
    std::copy(mesh_.positions_mm.begin(), mesh_.positions_mm.end(), vertices);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               mesh_.indices.data(), 0, 3 * sizeof(uint32_t),
                               mesh_.triangleCount());
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);
}

Geometry::~Geometry() = default;

std::optional<SurfaceHit> Geometry::intersect(const Ray& ray, float tMax, float tMin) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x; rh.ray.org_y = ray.o.y; rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x; rh.ray.dir_y = ray.d.y; rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = std::max(tMin, ray.tMin);
    rh.ray.tfar = tMax;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

    SurfaceHit hit = normalsAt(rh.hit.primID, rh.hit.u, rh.hit.v);
    hit.t = rh.ray.tfar;
    hit.p = ray.at(hit.t);
    return hit;
}

SurfaceHit Geometry::pointOn(uint32_t prim, float u, float v) const {
    const uint32_t* idx = &mesh_.indices[3 * size_t(prim)];
    SurfaceHit hit = normalsAt(prim, u, v);
    hit.p = mesh_.positions_mm[idx[0]] * (1 - u - v) + mesh_.positions_mm[idx[1]] * u + mesh_.positions_mm[idx[2]] * v;
    return hit;
}

SurfaceHit Geometry::normalsAt(uint32_t prim, float u, float v) const {
    const uint32_t* idx = &mesh_.indices[3 * size_t(prim)];
    SurfaceHit hit;
    hit.t = 0.0f;
    hit.ng = faceNormals_[prim];
    hit.ns = hit.ng;
    hit.prim = prim;
    if (!mesh_.normals.empty()) {
        // Interpolated file normals.
        Vec3f n = mesh_.normals[idx[0]] * (1 - u - v) + mesh_.normals[idx[1]] * u + mesh_.normals[idx[2]] * v;
        float len = length(n);
        // Keep the shading normal on the geometric normal's side.
        if (len > 0 && dot(n, hit.ng) > 0) hit.ns = n / len;
    }
    return hit;
}

SurfaceHit Geometry::pointAt(uint32_t prim, const Point3f& p) const {
    const uint32_t* idx = &mesh_.indices[3 * size_t(prim)];
    const Point3f& a = mesh_.positions_mm[idx[0]];
    const Vec3f e1 = mesh_.positions_mm[idx[1]] - a, e2 = mesh_.positions_mm[idx[2]] - a, ap = p - a;
    // Barycentrics by least squares in the triangle's plane.
    const float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
    const float dp1 = dot(ap, e1), dp2 = dot(ap, e2), det = d11 * d22 - d12 * d12;
    SurfaceHit hit = det > 0.0f ? pointOn(prim, (d22 * dp1 - d12 * dp2) / det, (d11 * dp2 - d12 * dp1) / det)
                                : pointOn(prim, 0.0f, 0.0f);
    hit.p = p;
    return hit;
}

std::optional<ClosestSurfacePoint> Geometry::closestPoint(const Point3f& p,
                                                          float radius_mm) const {
    RTCPointQuery query;
    query.x = p.x; query.y = p.y; query.z = p.z;
    query.radius = radius_mm;
    query.time = 0.0f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    PointQueryState state{&mesh_, {}, false};
    rtcPointQuery(impl_->scene, &query, &context, closestPointCallback, &state);
    if (!state.found) return std::nullopt;
    return state.best;
}

bool Geometry::surfaceCrossesBox(const Point3f& lo, const Point3f& hi) const {
    BoxQueryState state{&mesh_, (lo + hi) * 0.5f, (hi - lo) * 0.5f, false};
    // Every triangle touching the box is within its half diagonal of the centre.
    RTCPointQuery query;
    query.x = state.center.x; query.y = state.center.y; query.z = state.center.z;
    query.radius = length(state.half) * 1.0001f;
    query.time = 0.0f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(impl_->scene, &query, &context, boxOverlapCallback, &state);
    return state.overlaps;
}

TriangleMesh boxMesh(const Point3f& lo, const Point3f& hi) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions_mm.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Faces as quads (a,b,c,d) counter-clockwise from outside.
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

bool isConvex(const TriangleMesh& mesh) {
    const size_t triangles = mesh.triangleCount(), vertices = mesh.positions_mm.size();
    if (triangles == 0 || double(triangles) * double(vertices) > 2e8) return false;
    Bounds3f b;
    for (const Point3f& p : mesh.positions_mm) b.expand(p);
    const double tolerance_mm = 1e-5 * double(length(b.hi - b.lo));
    for (size_t t = 0; t < triangles; ++t) {
        const Point3f& a = mesh.positions_mm[mesh.indices[3 * t]];
        const Vec3f n = cross(mesh.positions_mm[mesh.indices[3 * t + 1]] - a, mesh.positions_mm[mesh.indices[3 * t + 2]] - a);
        const double area2 = double(length(n));
        if (!(area2 > 0.0)) continue;  // a degenerate triangle has no plane
        const double nx = n.x / area2, ny = n.y / area2, nz = n.z / area2;
        const double offset = nx * a.x + ny * a.y + nz * a.z;
        for (const Point3f& p : mesh.positions_mm)
            if (nx * p.x + ny * p.y + nz * p.z > offset + tolerance_mm) return false;
    }
    return true;
}

}  // namespace pl
