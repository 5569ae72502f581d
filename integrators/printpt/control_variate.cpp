#include "integrators/printpt/control_variate.h"

#include <cstring>

#include <Eigen/Dense>
#include <tbb/task_arena.h>

#include "runtime/scheduler.h"
#include "core/sensors.h"
#include "media/slab_transport.h"

namespace pl {

ControlVariate::ControlVariate(const Scene& scene, const PrintPtOptions& options, uint64_t seed)
    : scene_(scene),
      options_(options),
      seed_(seed) {
    const size_t controls = key(3, 0, 0);
    means_.reset(new std::atomic<float>[controls]);
    meanErrors_.reset(new std::atomic<float>[controls]);
    entries_.reset(new std::atomic<uint32_t>[controls]);
    for (size_t i = 0; i < controls; ++i) {
        means_[i].store(kUnknown, std::memory_order_relaxed);
        meanErrors_[i].store(0.0f, std::memory_order_relaxed);
        entries_[i].store(0, std::memory_order_relaxed);
    }
}

int64_t ControlVariate::meanWalks(const Shape& shape) const {
    // The wedges and curved regions are many: a quarter (wedges) or a
    // 32nd (curved: a hundred or more pairs per channel on curved objects)
    // of the walks each; their shared error is still far below a pixel's.
    // (The half-space's mean is exact: no walks.)
    if (shape.kind() == ControlKind::HalfSpace) return 0;
    return std::max<int64_t>(1024, options_.controlWalks / (shape.kind() == ControlKind::Curved ? 32 : 4));
}

ControlVariate::ControlMean ControlVariate::meanOf(int channel, Label label, const Shape& shape) const {
    const size_t index = key(channel, label, shape.index());
    float mean = means_[index].load(std::memory_order_acquire);
    if (mean != kUnknown) return {mean, meanErrors_[index].load(std::memory_order_relaxed)};
    // First use: compute it (the same bits whichever thread gets here
    // first). The mean does not depend on sigma_t (it only scales the
    // walk's lengths, the edge's distance and the curvatures included,
    // which are in mean free paths): computed at sigma_t = 1.
    const ChannelLut& lut = scene_.medium->lut(channel);
    HalfSpace hs{{0, 0, 0}, {0, 0, 1}, 1.0f, lut.albedo[label], lut.g[label], 1.0f / scene_.ior};
    ControlMean m;
    if (shape.kind() == ControlKind::HalfSpace) {
        // The half-space: exact, but for the solver's error and the float
        // round-off of a sample's sum (a few ulps: 2^-21 of the value).
        SlabEscape exact = slabEscape({hs.albedo, hs.g, scene_.ior});
        m = {float(exact.top), float(std::max(exact.error, std::ldexp(exact.top, -21)))};
    } else {
        // Wedges and curved regions: Monte Carlo walks seeded by the
        // render's seed and by what the mean depends on (materials and
        // channels of equal albedo and g, white resin's three channels,
        // share one estimate).
        uint64_t seed = mix64(seed_ ^ 0x636f6e74726f6cULL);
        for (float v : {hs.albedo, hs.g, hs.etaOut}) {
            uint32_t bits;
            std::memcpy(&bits, &v, sizeof bits);
            seed = mix64(seed ^ bits);
        }
        seed = mix64(seed ^ uint64_t(shape.index()));
        if (shape.edgeStep >= 0) {
            hs.hasSide = true;
            hs.sideNormal = {1, 0, 0};
            hs.sideOrigin = {edgeDistance_mfp(shape.edgeStep), 0, 0};
        } else {
            // The pair in one order, whichever order the surface had.
            hs.curved = true;
            hs.axisS = {1, 0, 0};
            hs.axisT = {0, 1, 0};
            hs.kappaS_perMm = curvature_perMfp(std::max(shape.curveS, shape.curveT));
            hs.kappaT_perMm = curvature_perMfp(std::min(shape.curveS, shape.curveT));
        }
        HalfSpaceMean estimate;
        tbb::this_task_arena::isolate([&] {
            estimate = HalfSpaceMeans::ofProcess().get(hs, {options_.rrThreshold, options_.rrCap},
                                             std::max(1.0f, options_.ballMinMfp), meanWalks(shape), seed);
        });
        m = {float(estimate.mean), float(estimate.standardError)};
    }
    meanErrors_[index].store(m.standardError, std::memory_order_relaxed);
    means_[index].store(m.mean, std::memory_order_release);
    return m;
}

std::optional<ControlVariate::Edge> ControlVariate::findEdge(HalfSpace& control, float reach_mm, float ignore_mm) const {
    // Rays along the plane, half a mean free path down, in eight directions.
    // The nearest face they leave through is the side face if it is at right
    // angles to the plane and no other lies within ignore_mm (as far as the
    // half-space's probes look); otherwise the half-space's probes decide.
    if (reach_mm <= 0.0f) return std::nullopt;
    const float mfp_mm = 1.0f / control.sigmaT_perMm;
    const Frame plane(control.normal);
    const Point3f from = control.origin - control.normal * (0.5f * mfp_mm);
    SurfaceHit hits[8];
    int count = 0, nearest = -1;
    auto distance = [&](const SurfaceHit& h) { return dot(h.p - control.origin, h.ng); };
    for (int i = 0; i < 8; ++i) {
        const float angle = float(i) * (kPi / 4.0f);
        const Vec3f along = plane.s * std::cos(angle) + plane.t * std::sin(angle);
        auto hit = scene_.geometry->intersect({from, along}, 1.5f * reach_mm);
        if (!hit) continue;
        if (dot(along, hit->ng) <= 0.0f) return std::nullopt;  // an inner face: not convex here
        hits[count] = *hit;
        if (nearest < 0 || distance(*hit) < distance(hits[nearest])) nearest = count;
        ++count;
    }
    if (nearest < 0) return std::nullopt;
    const SurfaceHit& side = hits[nearest];
    for (int i = 0; i < count; ++i) {
        const bool sameFace = std::abs(dot(hits[i].p - side.p, side.ng)) <= 0.25f * mfp_mm &&
                              dot(hits[i].ng, side.ng) >= 0.999f;
        if (!sameFace && distance(hits[i]) <= ignore_mm) return std::nullopt;  // a corner
    }
    // Right angles only: the table is over the edge's distance alone.
    if (std::abs(dot(side.ng, control.normal)) > 0.02f) return std::nullopt;
    const Vec3f toEdge = normalize(side.ng - control.normal * dot(side.ng, control.normal));
    const float edge_mm = distance(side) / dot(toEdge, side.ng);
    if (edge_mm > reach_mm) return std::nullopt;
    const int step = nearestEdgeStep(edge_mm / mfp_mm);
    if (step < 0) return std::nullopt;
    control.hasSide = true;
    control.sideNormal = toEdge;
    control.sideOrigin = control.origin + toEdge * (edgeDistance_mfp(step) * mfp_mm);
    return Edge{step, edge_mm};
}

int ControlVariate::solidLabelAt(const Point3f& p) const {
    return scene_.medium->majorants().solidLabelAt(scene_.medium->voxelAt(p));
}

std::optional<ControlVariate::EntryControl> ControlVariate::forEntry(const Ray& inside,
                                                                    const SingleChannelPath& path,
                                                                    LabelMedium::Tracker& medium) const {
    // The surface-voxel sensor sends the same ray for every sample of a
    // pixel, and a thread renders a pixel's samples one after another: the
    // decision (probes, fit, mean), a function of the entry and the channel
    // alone, is kept for the last entry each thread saw.
    LastEntry& last = lastEntry_.local();
    auto equal = [](const Vec3f& a, const Vec3f& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    const bool same =
        last.channel == path.channel && equal(last.inside.o, inside.o) && equal(last.inside.d, inside.d);
    if (!same) {
        last.control.reset();
        std::optional<Fit> f = fit(inside, path, medium);
        // Half-space means are exact and free; the others cost walks.
        const size_t index = f ? key(path.channel, f->label, f->shape.index()) : 0;
        if (f && surveyed_ && f->shape.kind() != ControlKind::HalfSpace &&
            int64_t(entries_[index]) * options_.controlMeanWalksPerEntry < meanWalks(f->shape))
            f.reset();
        if (f) {
            const ControlMean m = meanOf(path.channel, f->label, f->shape);
            last.control = EntryControl{f->region, m.mean * path.Le, m.standardError * path.Le, f->shape.kind(),
                                        int32_t(index)};
        }
        last.channel = path.channel;
        last.inside = inside;
    }
    return last.control;
}

void ControlVariate::survey(const Sensor& sensor, const std::vector<int>& channels) {
    if (!options_.controlVariate || options_.controlMeanWalksPerEntry <= 0) return;
    // The sensor's survey rays once per channel (Sensor::surveyRay: a fixed
    // set whatever the image size, so that the decisions do not depend on
    // it). The counts, and so the decisions, do not depend on the thread
    // order.
    const size_t surveyed = sensor.surveyRayCount();
    const uint32_t weight = sensor.surveyRayWeight();
    parallelForTiles(surveyed, 64, [&](size_t begin, size_t end) {
        LabelMedium::Tracker medium(*scene_.medium);
        for (size_t i = begin; i < end; ++i) {
            const Ray camera = sensor.surveyRay(i);
            auto entry = scene_.geometry->intersect(camera);
            if (!entry) continue;
            const Ray inside = enteringRay(scene_, camera, *entry);
            for (int c : channels) {
                SingleChannelPath path{&scene_.medium->lut(c), c, scene_.environment[c]};
                if (std::optional<Fit> f = fit(inside, path, medium))
                    entries_[key(c, f->label, f->shape.index())].fetch_add(weight, std::memory_order_relaxed);
            }
        }
    });
    surveyed_ = true;
}

std::optional<ControlVariate::Fit> ControlVariate::fit(const Ray& inside, const SingleChannelPath& path,
                                                       LabelMedium::Tracker& medium) const {
    // Cheapest first: under a halftone the entry's brick holds several resins.
    if (solidLabelAt(inside.o) == MajorantGrid::kSeveralLabels) return std::nullopt;
    // The plane goes through the first point along the ray where the
    // medium can scatter: the mesh and the voxels' edges do not line up, and
    // a skin of void voxels inside the mesh would otherwise shift the two
    // walks' collisions apart by its thickness.
    FreeFlight first = flightFromSurface(inside, 1e30f, [&](const Ray& r, float tMax) {
        return medium.freeFlightAtDepth(r, tMax, path.channel, 0.0f);
    });
    if (!first.scattered) return std::nullopt;
    const Label l = first.label;
    const ChannelLut& lut = *path.lut;
    // Absorbing resin ends walks by itself; a walk in albedo near 1 would
    // make the control's mean slow to estimate.
    if (lut.albedo[l] < PrintPtOptions::kAbsorbingAlbedo || lut.albedo[l] > 0.999f) return std::nullopt;
    Fit result;
    HalfSpace& control = result.region;
    Shape& shape = result.shape;
    // (At the surface itself where the medium starts there: the walk's first
    // flight starts there too, flightFromSurface.)
    const float start_mm = first.t_mm > 0.0f ? first.t_mm : -inside.mediumBefore_mm;
    control = {inside.at(start_mm), -inside.d, lut.sigmaT_perMm[l], lut.albedo[l], lut.g[l], 1.0f / scene_.ior};

    // Where another material, a corner, a thin part or a curved surface lies
    // within the walk's reach, the walks part early and each goes on alone,
    // which adds variance instead of taking it away. The control only runs
    // where, over the probe's reach (diffusion lengths of the material), the
    // bricks sampled below the entry hold only its material, the surface stays
    // within a quarter of a mean free path of the plane (and of the side
    // face, near a right-angled edge: the control is then the wedge; or of
    // a tabulated convex paraboloid: the curved control), and the object
    // holds a ball that deep below the entry. Cheapest first.
    const float mfp_mm = 1.0f / control.sigmaT_perMm;
    const float diffusion_mm = mfp_mm / std::sqrt(3.0f * (1.0f - control.albedo) * (1.0f - control.g));
    const float reach_mm = options_.controlProbe * diffusion_mm;
    result.label = l;
    const bool onlyMaterial = materialBelow(inside, l, reach_mm, control);
    bool fits = onlyMaterial && flatFits(inside, reach_mm, diffusion_mm, control, shape);
    // Curved surfaces fail the flat probes: the region under a paraboloid
    // that follows the surface, or a plane over a shorter reach, if the
    // body is thick enough below the entry that the walks do not part at once.
    if (!fits && onlyMaterial && options_.controlCurved)
        fits = curvedFits(inside, reach_mm, diffusion_mm, control, shape);
    if (!fits && options_.controlProbeShort > 0.0f) {
        const float shortReach_mm = options_.controlProbeShort * diffusion_mm;
        if (holdsBall(control.origin + inside.d * diffusion_mm, diffusion_mm) &&
            materialBelow(inside, l, shortReach_mm, control)) {
            control.hasSide = false;
            shape = {};
            fits = flatFits(inside, shortReach_mm, diffusion_mm, control, shape);
        }
    }
    if (!fits) return std::nullopt;
    return result;
}

bool ControlVariate::materialBelow(const Ray& inside, Label l, float reach_mm, const HalfSpace& control) const {
    const float mfp_mm = 1.0f / control.sigmaT_perMm;
    const Frame plane(control.normal);
    const Vec3f alongPlane[4] = {plane.s, -plane.s, plane.t, -plane.t};
    // Whole bricks, not single voxels: a halftone's sparse dots are seen.
    // (Beyond an edge they hold only void.)
    auto holdsMaterial = [&](const Point3f& p) {
        int solid = solidLabelAt(p);
        return solid == int(l) || solid == MajorantGrid::kOnlyVoid;  // void: the skin above the first voxels
    };
    const Point3f below = control.origin + inside.d * (0.5f * mfp_mm);
    for (float f : {0.25f, 0.5f, 1.0f}) {
        if (!holdsMaterial(control.origin + inside.d * (f * reach_mm))) return false;
        for (const Vec3f& along : alongPlane)
            if (!holdsMaterial(below + along * (f * reach_mm))) return false;
    }
    return true;
}

bool ControlVariate::curvedFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control,
                                Shape& shape) const {
    // Only on thick bodies below the entry: on thinner parts the walks
    // soon reach surface the fit did not see, part, and the probes and
    // continuations cost more than they save (docs/performance.md).
    const float thickness_mm = options_.controlCurvedThickness * diffusion_mm;
    if (!holdsBall(control.origin + inside.d * thickness_mm, thickness_mm)) return false;
    // The surface's drop below the entry plane at the closest points to 8
    // points around the entry, at half and full reach, fitted by least
    // squares with drop = (k11 x^2 + 2 k12 x y + k22 y^2) / 2.
    const float mfp_mm = 1.0f / control.sigmaT_perMm;
    const Frame plane(control.normal);
    constexpr int kProbes = 16;
    float xs[kProbes], ys[kProbes], drops[kProbes];
    Eigen::Matrix<double, kProbes, 3> basis;
    Eigen::Matrix<double, kProbes, 1> drop;
    for (int i = 0; i < kProbes; ++i) {
        const float angle = float(i / 2) * (kPi / 4.0f), f = i % 2 ? 1.0f : 0.5f;
        const Vec3f along = plane.s * std::cos(angle) + plane.t * std::sin(angle);
        auto nearest = scene_.geometry->closestPoint(inside.o + along * (f * reach_mm), 2.0f * reach_mm);
        if (!nearest) return false;
        const Vec3f off = nearest->p - inside.o;
        xs[i] = dot(off, plane.s);
        ys[i] = dot(off, plane.t);
        drops[i] = -dot(off, control.normal);
        basis.row(i) << 0.5 * xs[i] * xs[i], double(xs[i]) * ys[i], 0.5 * ys[i] * ys[i];
        drop(i) = drops[i];
    }
    const Eigen::ColPivHouseholderQR<decltype(basis)> qr(basis);
    if (qr.rank() < 3) return false;
    const Eigen::Vector3d k = qr.solve(drop);
    // Principal curvatures and the direction of the larger (Euler).
    const double mean = 0.5 * (k[0] + k[2]), half = std::sqrt(0.25 * (k[0] - k[2]) * (k[0] - k[2]) + k[1] * k[1]);
    const float angle = 0.5f * float(std::atan2(2.0 * k[1], k[0] - k[2]));
    const int stepS = nearestCurvatureStep(float(mean + half) * mfp_mm);
    const int stepT = nearestCurvatureStep(float(mean - half) * mfp_mm);  // 0 for saddles: the check below decides
    if (stepS <= 0 || stepT < 0) return false;
    const float kappaS = curvature_perMfp(stepS) / mfp_mm, kappaT = curvature_perMfp(stepT) / mfp_mm;
    const float c = std::cos(angle), sn = std::sin(angle);
    // The tabulated paraboloid must follow every probe within the
    // tolerance (looser than the plane's quarter mean free path: measured
    // in docs/performance.md).
    const float tolerance_mm = options_.controlCurvedTolerance * mfp_mm;
    for (int i = 0; i < kProbes; ++i) {
        const float u = c * xs[i] + sn * ys[i], v = -sn * xs[i] + c * ys[i];
        if (std::abs(0.5f * (kappaS * u * u + kappaT * v * v) - drops[i]) > tolerance_mm) return false;
    }
    control.hasSide = false;
    control.curved = true;
    control.axisS = plane.s * c + plane.t * sn;
    control.axisT = plane.t * c - plane.s * sn;
    control.kappaS_perMm = kappaS;
    control.kappaT_perMm = kappaT;
    shape = {};
    shape.curveS = stepS;
    shape.curveT = stepT;
    return true;
}

bool ControlVariate::flatFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control,
                              Shape& shape) const {
    const float mfp_mm = 1.0f / control.sigmaT_perMm;
    const Frame plane(control.normal);
    const Vec3f alongPlane[4] = {plane.s, -plane.s, plane.t, -plane.t};
    // The surface along the plane, four ways: where it leaves the plane both
    // ways along a line the surface is curved or the part thin, and no edge
    // explains that (this also spares curved objects the edge search's rays).
    const Geometry& geometry = *scene_.geometry;
    const float flat_mm = 0.25f * mfp_mm;
    bool leaves[4];
    for (int i = 0; i < 4; ++i) leaves[i] = !geometry.closestPoint(inside.o + alongPlane[i] * reach_mm, flat_mm);
    if ((leaves[0] && leaves[1]) || (leaves[2] && leaves[3])) return false;
    std::optional<Edge> edge = findEdge(control, options_.controlEdgeReach * diffusion_mm, reach_mm);
    if (edge) shape.edgeStep = edge->step;
    // Distance from p to the real side face (mm; huge without one).
    auto insideSide = [&](const Point3f& p) {
        return edge ? edge->distance_mm - dot(p - control.origin, control.sideNormal) : 1e30f;
    };
    // Only past the edge may the surface leave the plane (the side face is
    // checked below).
    for (int i = 0; i < 4; ++i)
        if (leaves[i] && insideSide(inside.o + alongPlane[i] * reach_mm) >= flat_mm) return false;
    if (edge) {
        // The side face is flat too: on it, down from the edge and along it.
        const Point3f onEdge = control.origin + control.sideNormal * edge->distance_mm;
        const Vec3f alongEdge = cross(control.normal, control.sideNormal);
        const Point3f halfDown = onEdge - control.normal * (0.5f * reach_mm);
        for (const Point3f& p :
             {onEdge - control.normal * reach_mm, halfDown + alongEdge * reach_mm, halfDown - alongEdge * reach_mm})
            if (!geometry.closestPoint(p, flat_mm)) return false;
    }
    // The object holds a ball that deep below the entry (or as deep as the
    // side face allows).
    const Point3f deep = control.origin + inside.d * reach_mm;
    return holdsBall(deep, std::min(reach_mm, insideSide(deep)));
}

bool ControlVariate::holdsBall(const Point3f& centre, float radius_mm) const {
    if (radius_mm <= 0.0f) return true;
    // The clearance grid's bounds settle most cases without a query.
    if (const SurfaceClearance* clearance = scene_.clearance.get()) {
        if (clearance->at(centre) >= 0.9f * radius_mm) return true;
        if (clearance->upperBoundAt(centre) < 0.9f * radius_mm) return false;
    }
    auto nearest = scene_.geometry->closestPoint(centre, radius_mm);
    return !nearest || nearest->distance_mm >= 0.9f * radius_mm;
}

}  // namespace pl
