#include "core/prism_index.h"

#include <stdexcept>
#include <vector>

#include "core/embree_scene.h"

namespace pl {

struct PrismIndex::Impl : EmbreeScene {
    struct Prism {
        Point3f a, b, c;
        Vec3f normal;
    };
    std::vector<Prism> prisms;
    float depth_mm = 0;
};

namespace {

struct QueryState {
    const PrismIndex::Impl* impl;
    Point3f y;
    void (*call)(void*, const PrismIndex::Line&);
    void* visit;
};

// The line of prism `prim` through the query point, if it has one.
bool prismCallback(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<QueryState*>(args->userPtr);
    const auto& p = state->impl->prisms[args->primID];
    const float s = dot(p.a - state->y, p.normal);
    if (!(s > 0.0f && s <= state->impl->depth_mm)) return false;
    const Point3f x = state->y + p.normal * s;
    // Inside the triangle: x is on the inner side of each edge.
    const Vec3f ab = p.b - p.a, bc = p.c - p.b, ca = p.a - p.c;
    if (dot(cross(ab, x - p.a), p.normal) < 0.0f || dot(cross(bc, x - p.b), p.normal) < 0.0f ||
        dot(cross(ca, x - p.c), p.normal) < 0.0f)
        return false;
    state->call(state->visit, PrismIndex::Line{args->primID, s, x, p.normal});
    return false;  // the query radius does not change
}

void prismBounds(const RTCBoundsFunctionArguments* args) {
    const auto* impl = static_cast<const PrismIndex::Impl*>(args->geometryUserPtr);
    const auto& p = impl->prisms[args->primID];
    Bounds3f b;
    for (const Point3f& v : {p.a, p.b, p.c}) {
        b.expand(v);
        b.expand(v - p.normal * impl->depth_mm);
    }
    args->bounds_o->lower_x = b.lo.x;
    args->bounds_o->lower_y = b.lo.y;
    args->bounds_o->lower_z = b.lo.z;
    args->bounds_o->upper_x = b.hi.x;
    args->bounds_o->upper_y = b.hi.y;
    args->bounds_o->upper_z = b.hi.z;
}

}  // namespace

PrismIndex::PrismIndex(const TriangleMesh& mesh, float depth_mm) : impl_(std::make_unique<Impl>()) {
    impl_->depth_mm = depth_mm;
    impl_->prisms.reserve(mesh.triangleCount());
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* i = &mesh.indices[3 * t];
        const Point3f &a = mesh.positions_mm[i[0]], &b = mesh.positions_mm[i[1]], &c = mesh.positions_mm[i[2]];
        const Vec3f e = cross(b - a, c - a);
        // A degenerate triangle has no line: an empty prism.
        impl_->prisms.push_back({a, b, c, length(e) > 0.0f ? normalize(e) : Vec3f(0, 0, 0)});
    }
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(impl_->prisms.size()));
    rtcSetGeometryUserData(geom, impl_.get());
    rtcSetGeometryBoundsFunction(geom, prismBounds, impl_.get());
    rtcSetGeometryPointQueryFunction(geom, prismCallback);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);
}

PrismIndex::~PrismIndex() = default;

float PrismIndex::depth_mm() const { return impl_->depth_mm; }

void PrismIndex::linesThrough(const Point3f& y, void (*call)(void*, const Line&), void* visit) const {
    RTCPointQuery query;
    query.x = y.x;
    query.y = y.y;
    query.z = y.z;
    query.radius = 0.0f;  // the boxes that hold y
    query.time = 0.0f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    QueryState state{impl_.get(), y, call, visit};
    rtcPointQuery(impl_->scene, &query, &context, nullptr, &state);
}

}  // namespace pl
