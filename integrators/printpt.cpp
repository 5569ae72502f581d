#include "integrators/printpt.h"

#include <cstring>
#include <type_traits>

#include <tbb/task_arena.h>

#include "core/fresnel.h"
#include "core/sampling.h"
#include "core/scheduler.h"
#include "core/sensors.h"
#include "integrators/half_space_walk.h"
#include "media/ball_walk.h"
#include "media/slab_transport.h"

namespace pl {

namespace {

// The solution of the 3x3 system a x = b by Cramer's rule; false if singular.
bool solve3x3(const double a[3][3], const double b[3], double x[3]) {
    auto det = [](const double m[3][3]) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double d = det(a);
    if (!(std::abs(d) > 1e-300)) return false;
    for (int col = 0; col < 3; ++col) {
        double m[3][3];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = c == col ? b[r] : a[r][c];
        x[col] = det(m) / d;
    }
    return true;
}

}  // namespace

ChannelSample PrintPt::Li(Ray ray, int channel, LabelMedium::Sampler& medium, Rng& rng,
                          PathStats& stats) const {
    return traceOneChannel(scene_, channel, [&](const auto& path) {
        Traced<float> t = trace(ray, path, medium, rng, stats);
        return ChannelSample{t.L, t.sharedError, t.controlKey, t.residual};
    });
}

RGB PrintPt::LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Sampler& medium, Rng& rng,
                   PathStats& stats) const {
    return traceThreeChannels(scene_, sampling, hero,
                              [&](const auto& path) { return trace(ray, path, medium, rng, stats).L; });
}

template <class Path>
PrintPt::Traced<typename Path::Value> PrintPt::trace(Ray ray, const Path& path, LabelMedium::Sampler& medium,
                                                     Rng& rng, PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    Traced<typename Path::Value> result;
    typename Path::Value& L = result.L;
    auto entry = geometry.intersect(ray);
    if (!entry) {
        stats.paths += 1;
        path.addLight(L, 1.0f);
        return result;
    }
    // The camera ray arrives from outside: Fresnel at the entry.
    Vec3f n = dot(ray.d, entry->ng) < 0 ? entry->ns : -entry->ns;
    float F = fresnelDielectric(-dot(ray.d, n), scene_.ior);
    float transmitted = 1.0f;
    if (options_.fresnelWeighting) {
        // Reflected light leaves at once (no re-entry): it is Le exactly.
        path.addLight(L, F);
        transmitted = 1.0f - F;
    } else if (rng.uniform() < F) {
        stats.paths += 1;
        path.addLight(L, 1.0f);
        return result;
    }
    const Ray inside = enteringRay(ray, *entry);

    // Branching: k walks share the camera ray and the entry.
    const int k = std::max(1, options_.branches);
    const float branchWeight = transmitted / float(k);
    WalkFunction<Path> walk;
    if constexpr (std::is_same_v<Path, SingleChannelPath>) walk = walkSingle_;
    else if constexpr (std::is_same_v<Path, HeroPath>) walk = walkHero_;
    else walk = walkSpectral_;
    std::optional<EntryControl> control;
    if constexpr (std::is_same_v<Path, SingleChannelPath>)
        if (options_.controlVariate && !options_.nee) control = controlForEntry(inside, path, medium);
    if (control) {
        // Every branch adds the same mean: its error is shared, not averaged.
        result.sharedError = transmitted * control->meanError;
        result.controlKey = control->key;
        stats.controlledWalks[int(control->kind)] += uint64_t(k);
    }
    for (int b = 0; b < k; ++b) {
        // Each walk starts at throughput 1 (Russian roulette is relative to it).
        typename Path::Value Lb{};
        if constexpr (std::is_same_v<Path, SingleChannelPath>) {
            if (control) {
                const float difference = walkWithControl(inside, path, control->region, medium, rng, stats);
                result.residual += branchWeight * difference;
                Lb = difference + control->mean;
            } else {
                Lb = (this->*walk)(inside, path, medium, rng, stats);
            }
        } else {
            Lb = (this->*walk)(inside, path, medium, rng, stats);
        }
        if constexpr (std::is_same_v<typename Path::Value, float>) L += branchWeight * Lb;
        else
            for (int c = 0; c < 3; ++c) L[c] += branchWeight * Lb[c];
    }
    return result;
}

Ray PrintPt::enteringRay(const Ray& camera, const SurfaceHit& entry) const {
    Vec3f n = dot(camera.d, entry.ng) < 0 ? entry.ns : -entry.ns;
    auto t = refract(camera.d, n, scene_.ior);
    Vec3f d = t ? *t : camera.d;
    if (dot(d, entry.ng) >= 0) d = -entry.ng;
    return scene_.geometry->spawnRay(entry.p, entry.ng, d);
}

PrintPt::PrintPt(const Scene& scene, PrintPtOptions options, uint64_t seed)
    : scene_(scene), options_(options), seed_(seed) {
    static std::atomic<uint64_t> instances{0};
    id_ = ++instances;
    // The walk is compiled once per combination of the switches it tests
    // in its loop; the scene picks one here and the loop pays for no branch.
    options_.nee = options_.nee && scene_.medium->hasSurfaceFields();
    walkSingle_ = selectWalk<SingleChannelPath>();
    const size_t controls = controlIndex(3, 0, 0);
    controlMean_.reset(new std::atomic<float>[controls]);
    controlStdErr_.reset(new std::atomic<float>[controls]);
    controlEntries_.reset(new std::atomic<uint32_t>[controls]);
    for (size_t i = 0; i < controls; ++i) {
        controlMean_[i].store(kControlUnknown, std::memory_order_relaxed);
        controlStdErr_[i].store(0.0f, std::memory_order_relaxed);
        controlEntries_[i].store(0, std::memory_order_relaxed);
    }
    walkHero_ = selectWalk<HeroPath>();
    walkSpectral_ = selectWalk<SpectralPath>();
}

template <class Path>
PrintPt::WalkFunction<Path> PrintPt::selectWalk() const {
    const bool m = options_.mediumFirst, f = options_.fresnelWeighting;
    if constexpr (Path::kSupportsNee) {
        if (options_.nee)
            return m ? (f ? &PrintPt::walk<Path, true, true, true> : &PrintPt::walk<Path, true, true, false>)
                     : (f ? &PrintPt::walk<Path, true, false, true> : &PrintPt::walk<Path, true, false, false>);
    }
    return m ? (f ? &PrintPt::walk<Path, false, true, true> : &PrintPt::walk<Path, false, true, false>)
             : (f ? &PrintPt::walk<Path, false, false, true> : &PrintPt::walk<Path, false, false, false>);
}

template <class Path, bool kNee, bool kMediumFirst, bool kFresnelWeighting>
typename Path::Value PrintPt::walk(Ray ray, Path path, LabelMedium::Sampler& medium, Rng& rng,
                                   PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const float etaOut = 1.0f / scene_.ior;
    typename Path::Value L{};
    int64_t bounces = 0;
    stats.paths += 1;
    const SurfaceClearance* clearance = options_.clearance ? scene_.clearance.get() : nullptr;
    const bool balls = options_.ballWalks && scene_.clearance && !kNee;
    // MIS weight of the next boundary hit's transmitted light: below 1 only
    // for the first hit after a collision where next-event estimation ran.
    float hitWeight = 1.0f;

    bool deep = false;  // the last collision needed no boundary query: worth looking for a ball
    for (;;) {
        if (balls && deep) {
            // Deep in one material: walk to the edge of a ball that holds
            // nothing else, without grid lookups or boundary queries.
            Label label;
            float radius_mm = homogeneousBall(ray.o, label);
            if (radius_mm > 0.0f && path.canWalkBall(label) &&
                radius_mm * path.ballSigmaT(label) >= options_.ballMinMfp) {
                if (!walkInBall(ray, radius_mm, label, path, rng, stats)) return L;
                bounces = 0;
                hitWeight = 1.0f;
                continue;
            }
        }
        // Distance to the next real collision, then the boundary up to it.
        FreeFlight ff;
        std::optional<SurfaceHit> hit;
        if constexpr (kMediumFirst) {
            ff = path.track(medium, ray, 1e30f, rng);
            // A collision nearer than the boundary can be needs no query.
            deep = ff.scattered && clearance && ff.t_mm < clearance->at(ray.o);
            if (!deep) hit = geometry.intersectFromInside(ray, ff.scattered ? ff.t_mm : 1e30f);
        } else {
            hit = geometry.intersectFromInside(ray);
            if (hit) ff = path.track(medium, ray, hit->t, rng);
        }
        if (!hit && !(kMediumFirst && ff.scattered)) {
            stats.leaks += 1;  // left an open mesh: count it, treat as leaving
            path.addLight(L, 1.0f);
            return L;
        }
        // Medium first: the boundary query only reached the collision, so a
        // hit means the boundary comes first. Geometry first: the tracking
        // only reached the boundary, so a collision means it comes first.
        bool boundaryFirst = kMediumFirst ? hit.has_value() : !ff.scattered;
        if (boundaryFirst && dot(ray.d, hit->ng) < 0) {
            // Round-off put the ray outside, facing the surface: it leaves.
            stats.leaks += 1;
            path.addLight(L, 1.0f);
            return L;
        }

        if (!boundaryFirst) {
            // Scattering: weight by the albedo, Russian roulette, phase sampling.
            stats.scatterEvents += 1;
            bounces = 0;
            path.collide(ff.label);
            if (!survivesRoulette(path, ff.label, rng)) return L;
            Point3f x = ray.at(ff.t_mm);
            Lobe lobe;
            if constexpr (kNee) path.addLight(L, nextEvent(x, ray.d, ff.label, path.channel, medium, rng, lobe));
            Vec3f dOut = path.samplePhase(ff.label, ray.d, rng);
            hitWeight = 1.0f;
            if (lobe.kappa > 0) {
                float pPhase = hgPhase(dot(ray.d, dOut), path.g(ff.label));
                float pv = lobe.probability * vmfPdf(lobe.axis, lobe.kappa, dOut);
                hitWeight = pPhase / (pPhase + pv);
            }
            ray = {x, dOut};
            continue;
        }

        // Boundary from inside.
        if (++bounces > kMaxBoundaryBounces) {
            stats.trapped += 1;
            return L;
        }
        Vec3f n = -hit->ns;  // facing against the ray
        float F = fresnelDielectric(-dot(ray.d, n), etaOut);
        if constexpr (kFresnelWeighting) {
            path.addLight(L, hitWeight * (1.0f - F));  // the transmitted part leaves for good
            path.scale(F);
            if (!path.alive()) return L;
        } else if (!(rng.uniform() < F)) {
            path.addLight(L, hitWeight);
            return L;
        }
        hitWeight = 1.0f;  // light after an inner reflection has no NEE counterpart
        Vec3f r = reflectOnSide(ray.d, *hit);
        if (dot(r, hit->ng) >= 0) r = -hit->ng;
        ray = geometry.spawnRay(hit->p, hit->ng, r);
    }
}

template <class Path>
float PrintPt::rouletteThreshold(const Path& path, Label label) const {
    // Absorbing ink ends walks soon anyway: an earlier roulette there saves
    // their tails at little variance; white keeps long weighted walks.
    return path.rouletteAlbedo(label) < PrintPtOptions::kAbsorbingAlbedo ? options_.rrThresholdAbsorbing
                                                                          : options_.rrThreshold;
}

template <class Path>
bool PrintPt::survivesRoulette(Path& path, Label label, Rng& rng) const {
    float q = std::min(options_.rrCap, path.rouletteValue() / rouletteThreshold(path, label));
    if (q >= 1.0f) return true;
    if (!(rng.uniform() < q)) return false;
    path.scale(1.0f / q);
    return true;
}

float PrintPt::homogeneousBall(const Point3f& p, Label& label) const {
    const LabelMedium& medium = *scene_.medium;
    const UniformRegions::Cell cell = medium.uniformRegions().at(medium.voxelAt(p));
    if (cell.radius_mm <= 0.0f) return 0.0f;
    label = Label(cell.label);
    return std::min(cell.radius_mm, scene_.clearance->at(p));
}

template <class Path>
bool PrintPt::walkInBall(Ray& ray, float radius_mm, Label label, Path& path, Rng& rng, PathStats& stats) const {
    BallWalk b = pl::walkInBall(ray.d, radius_mm, path.ballSigmaT(label), path.g(label),
                                [&](float flight_mm) {
                                    path.ballFlight(label, flight_mm);
                                    path.ballCollision(label);
                                    path.collide(label);
                                    return survivesRoulette(path, label, rng);
                                },
                                rng);
    path.ballFlight(label, b.lastFlight_mm);
    stats.scatterEvents += uint64_t(b.collisions);
    stats.ballEvents += uint64_t(b.collisions);
    ray = {ray.o + b.exit, b.direction};
    return b.alive;
}

int64_t PrintPt::controlMeanWalks(const ControlShape& shape) const {
    // The wedges and curved regions are many: a quarter (wedges) or a
    // 32nd (curved: a hundred or more pairs per channel on curved objects)
    // of the walks each; their shared error is still far below a pixel's.
    // (The half-space's mean is exact: no walks.)
    if (shape.kind() == ControlKind::HalfSpace) return 0;
    return std::max<int64_t>(1024, options_.controlWalks / (shape.kind() == ControlKind::Curved ? 32 : 4));
}

PrintPt::ControlMean PrintPt::controlMean(int channel, Label label, const ControlShape& shape) const {
    const size_t index = controlIndex(channel, label, shape.index());
    float mean = controlMean_[index].load(std::memory_order_acquire);
    if (mean != kControlUnknown) return {mean, controlStdErr_[index].load(std::memory_order_relaxed)};
    // First use: compute it (the same bits whichever thread gets here
    // first). The mean does not depend on sigma_t (it only scales the
    // walk's lengths, the edge's distance and the curvatures included,
    // which are in mean free paths): computed at sigma_t = 1.
    const ChannelLut& lut = scene_.medium->lut(channel);
    HalfSpace hs{{0, 0, 0}, {0, 0, 1}, 1.0f, lut.albedo[label], lut.g[label], 1.0f / scene_.ior};
    ControlMean m;
    if (shape.index() == 0) {
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
            estimate = halfSpaceMean(hs, {options_.rrThreshold, options_.rrCap}, std::max(1.0f, options_.ballMinMfp),
                                     controlMeanWalks(shape), seed);
        });
        m = {float(estimate.mean), float(estimate.standardError)};
    }
    controlStdErr_[index].store(m.standardError, std::memory_order_relaxed);
    controlMean_[index].store(m.mean, std::memory_order_release);
    return m;
}

std::optional<PrintPt::Edge> PrintPt::findEdge(HalfSpace& control, float reach_mm, float ignore_mm) const {
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

int PrintPt::solidLabelAt(const Point3f& p) const {
    return scene_.medium->majorants().solidLabelAt(scene_.medium->voxelAt(p));
}

std::optional<PrintPt::EntryControl> PrintPt::controlForEntry(const Ray& inside, const SingleChannelPath& path,
                                                              LabelMedium::Sampler& medium) const {
    // The surface-voxel sensor sends the same ray for every sample of a
    // pixel, and a thread renders a pixel's samples one after another: the
    // decision (probes, fit, mean), a function of the entry and the channel
    // alone, is kept for the last entry each thread saw.
    struct Last {
        uint64_t integrator = 0;  // id_ of the integrator that made it; 0: none
        int channel = -1;
        Ray inside;
        std::optional<EntryControl> control;
    };
    thread_local Last last;
    auto equal = [](const Vec3f& a, const Vec3f& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    const bool same = last.integrator == id_ && last.channel == path.channel && equal(last.inside.o, inside.o) &&
                      equal(last.inside.d, inside.d);
    if (!same) {
        last.control.reset();
        HalfSpace region;
        Label label;
        ControlShape shape;
        bool controlled = controlFor(inside, path, medium, region, label, shape);
        // Half-space means are exact and free; the others cost walks.
        if (controlled && entriesCounted_ && shape.kind() != ControlKind::HalfSpace) {
            const uint32_t entries = controlEntries_[controlIndex(path.channel, label, shape.index())];
            controlled = int64_t(entries) * options_.controlMeanWalksPerEntry >= controlMeanWalks(shape);
        }
        if (controlled) {
            const ControlMean m = controlMean(path.channel, label, shape);
            last.control = EntryControl{region, m.mean * path.Le, m.standardError * path.Le, shape.kind(),
                                        int32_t(controlIndex(path.channel, label, shape.index()))};
        }
        last.integrator = id_;
        last.channel = path.channel;
        last.inside = inside;
    }
    return last.control;
}

void PrintPt::prepare(const Sensor& sensor, const std::vector<int>& channels) {
    if (!options_.controlVariate || options_.nee || options_.controlMeanWalksPerEntry <= 0) return;
    // The sensor's survey rays once per channel (Sensor::surveyRay: a fixed
    // set whatever the image size, so that the decisions do not depend on
    // it). The counts, and so the decisions, do not depend on the thread
    // order.
    const size_t surveyed = sensor.surveyRayCount();
    const uint32_t weight = sensor.surveyRayWeight();
    parallelForTiles(surveyed, 64, [&](size_t begin, size_t end) {
        LabelMedium::Sampler medium(*scene_.medium);
        for (size_t i = begin; i < end; ++i) {
            const Ray camera = sensor.surveyRay(i);
            auto entry = scene_.geometry->intersect(camera);
            if (!entry) continue;
            const Ray inside = enteringRay(camera, *entry);
            for (int c : channels) {
                SingleChannelPath path{&scene_.medium->lut(c), c, scene_.environment[c]};
                HalfSpace control;
                Label label;
                ControlShape shape;
                if (!controlFor(inside, path, medium, control, label, shape)) continue;
                controlEntries_[controlIndex(c, label, shape.index())].fetch_add(weight, std::memory_order_relaxed);
            }
        }
    });
    entriesCounted_ = true;
}

bool PrintPt::controlFor(const Ray& inside, const SingleChannelPath& path, LabelMedium::Sampler& medium,
                         HalfSpace& control, Label& label, ControlShape& shape) const {
    // Cheapest first: under a halftone the entry's brick holds several resins.
    if (solidLabelAt(inside.o) == MajorantGrid::kSeveralLabels) return false;
    // The plane goes through the first point along the ray where the
    // medium can scatter: the mesh and the voxels' edges do not line up, and
    // a skin of void voxels inside the mesh would otherwise shift the two
    // walks' collisions apart by its thickness.
    FreeFlight first = medium.freeFlightAtDepth(inside, 1e30f, path.channel, 0.0f);
    if (!first.scattered) return false;
    const Label l = first.label;
    const ChannelLut& lut = *path.lut;
    // Absorbing resin ends walks by itself; a walk in albedo near 1 would
    // make the control's mean slow to estimate.
    if (lut.albedo[l] < PrintPtOptions::kAbsorbingAlbedo || lut.albedo[l] > 0.999f) return false;
    control = {inside.at(first.t_mm), -inside.d, lut.sigmaT_perMm[l], lut.albedo[l], lut.g[l], 1.0f / scene_.ior};

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
    label = l;
    shape = {};
    const bool onlyMaterial = materialBelow(inside, l, reach_mm, control);
    bool fits = onlyMaterial && controlFits(inside, reach_mm, diffusion_mm, control, shape);
    // Curved surfaces fail the flat probes: the region under a paraboloid
    // that follows the surface, or a plane over a shorter reach, if the
    // body is thick enough below the entry that the walks do not part at once.
    if (!fits && onlyMaterial && options_.controlCurved)
        fits = curvedControlFits(inside, reach_mm, diffusion_mm, control, shape);
    if (!fits && options_.controlProbeShort > 0.0f) {
        const float shortReach_mm = options_.controlProbeShort * diffusion_mm;
        if (holdsBall(control.origin + inside.d * diffusion_mm, diffusion_mm) &&
            materialBelow(inside, l, shortReach_mm, control)) {
            control.hasSide = false;
            shape = {};
            fits = controlFits(inside, shortReach_mm, diffusion_mm, control, shape);
        }
    }
    return fits;
}

bool PrintPt::materialBelow(const Ray& inside, Label l, float reach_mm, const HalfSpace& control) const {
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

bool PrintPt::curvedControlFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control,
                                ControlShape& shape) const {
    // Only on thick bodies below the entry: on thinner parts the walks
    // soon reach surface the fit did not see, part, and the probes and
    // continuations cost more than they save (the white animal: 0.85x at
    // one diffusion length, 0.98x at two; docs/performance.md).
    const float thickness_mm = options_.controlCurvedThickness * diffusion_mm;
    if (!holdsBall(control.origin + inside.d * thickness_mm, thickness_mm)) return false;
    // The surface's drop below the entry plane at the closest points to 8
    // points around the entry, at half and full reach, fitted by least
    // squares with drop = (k11 x^2 + 2 k12 x y + k22 y^2) / 2.
    const float mfp_mm = 1.0f / control.sigmaT_perMm;
    const Frame plane(control.normal);
    constexpr int kProbes = 16;
    float xs[kProbes], ys[kProbes], drops[kProbes];
    double normal[3][3] = {}, rhs[3] = {};
    for (int i = 0; i < kProbes; ++i) {
        const float angle = float(i / 2) * (kPi / 4.0f), f = i % 2 ? 1.0f : 0.5f;
        const Vec3f along = plane.s * std::cos(angle) + plane.t * std::sin(angle);
        auto nearest = scene_.geometry->closestPoint(inside.o + along * (f * reach_mm), 2.0f * reach_mm);
        if (!nearest) return false;
        const Vec3f off = nearest->p - inside.o;
        xs[i] = dot(off, plane.s);
        ys[i] = dot(off, plane.t);
        drops[i] = -dot(off, control.normal);
        const double basis[3] = {0.5 * xs[i] * xs[i], double(xs[i]) * ys[i], 0.5 * ys[i] * ys[i]};
        for (int a = 0; a < 3; ++a) {
            rhs[a] += basis[a] * drops[i];
            for (int b = 0; b < 3; ++b) normal[a][b] += basis[a] * basis[b];
        }
    }
    double k[3];
    if (!solve3x3(normal, rhs, k)) return false;
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

bool PrintPt::controlFits(const Ray& inside, float reach_mm, float diffusion_mm, HalfSpace& control,
                          ControlShape& shape) const {
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

bool PrintPt::holdsBall(const Point3f& centre, float radius_mm) const {
    if (radius_mm <= 0.0f) return true;
    // The clearance grid's bounds settle most cases without a query.
    if (const SurfaceClearance* clearance = scene_.clearance.get()) {
        if (clearance->at(centre) >= 0.9f * radius_mm) return true;
        if (clearance->upperBoundAt(centre) < 0.9f * radius_mm) return false;
    }
    auto nearest = scene_.geometry->closestPoint(centre, radius_mm);
    return !nearest || nearest->distance_mm >= 0.9f * radius_mm;
}

float PrintPt::walkWithControl(Ray ray, SingleChannelPath path, const HalfSpace& control,
                               LabelMedium::Sampler& medium, Rng& rng, PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const float etaOut = 1.0f / scene_.ior;
    const SurfaceClearance* clearance = options_.clearance ? scene_.clearance.get() : nullptr;
    const bool balls = options_.ballWalks && scene_.clearance;
    const RouletteRule controlRoulette{options_.rrThreshold, options_.rrCap};
    const float controlBallMfp = std::max(1.0f, options_.ballMinMfp);
    HalfSpaceWalker c{control.origin, ray.d, 1.0f};
    float L = 0.0f, Lc = 0.0f;  // Lc per unit environment radiance
    int64_t bounces = 0, controlEvents = 0;
    bool deep = false;
    // The control walks on alone from its state (after its pending event).
    auto sameMaterial = [&](Label label) {
        return path.lut->sigmaT_perMm[label] == control.sigmaT_perMm && path.lut->albedo[label] == control.albedo &&
               path.lut->g[label] == control.g;
    };
    // One roulette for both, on the larger weight: neither weight can grow
    // past the threshold (in ink the surface walk's weight drops fast while
    // the control's may not).
    auto sharedSurvival = [&](Label label) {
        return std::min(options_.rrCap, std::max(path.beta, c.weight) / rouletteThreshold(path, label));
    };
    auto finishControl = [&](bool atCollision) {
        const int n = options_.controlContinuations;
        float remainder = 0.0f;
        for (int i = 0; i < n; ++i)
            remainder += finishHalfSpaceWalk(control, c, atCollision, controlRoulette, controlBallMfp, rng, controlEvents);
        Lc += remainder / float(n);
        return L - Lc * path.Le;
    };
    stats.paths += 1;
    for (;;) {
        if (balls && deep) {
            // A ball that holds only the control's material and lies below
            // its plane: one ball walk for both (rotated onto the control).
            Label label;
            float radius_mm = std::min(homogeneousBall(ray.o, label), control.depth(c.x));
            if (radius_mm > 0.0f && sameMaterial(label) && radius_mm * control.sigmaT_perMm >= options_.ballMinMfp &&
                dot(ray.d, c.d) > -0.99f) {
                const Vec3f d0 = ray.d;
                BallWalk b = pl::walkInBall(d0, radius_mm, control.sigmaT_perMm, control.g,
                                            [&](float) {
                                                path.collide(label);
                                                c.weight *= control.albedo;
                                                float q = sharedSurvival(label);
                                                if (q >= 1.0f) return true;
                                                if (!(rng.uniform() < q)) return false;
                                                path.scale(1.0f / q);
                                                c.weight /= q;
                                                return true;
                                            },
                                            rng);
                stats.scatterEvents += uint64_t(b.collisions);
                stats.ballEvents += uint64_t(b.collisions);
                if (!b.alive) return L - Lc * path.Le;  // both ended by the same roulette
                ray = {ray.o + b.exit, b.direction};
                c.x = c.x + rotateAtoB(d0, c.d, b.exit);
                c.d = normalize(rotateAtoB(d0, c.d, b.direction));
                bounces = 0;
                continue;
            }
        }
        // One optical depth for both flights.
        float opticalDepth = -std::log(1.0f - rng.uniform());
        FreeFlight ff = medium.freeFlightAtDepth(ray, 1e30f, path.channel, opticalDepth);
        deep = ff.scattered && clearance && ff.t_mm < clearance->at(ray.o);
        std::optional<SurfaceHit> hit;
        if (!deep) hit = geometry.intersectFromInside(ray, ff.scattered ? ff.t_mm : 1e30f);
        const bool controlCollides = halfSpaceFlight(control, c, opticalDepth, Lc);
        if ((!hit && !ff.scattered) || (hit && dot(ray.d, hit->ng) < 0)) {
            stats.leaks += 1;  // as walk(): treated as leaving
            path.addLight(L, 1.0f);
            return finishControl(controlCollides);
        }
        const bool collides = !hit;
        // The events part (one collides where the other leaves, or the
        // surface walk collides in another material, whose roulette the
        // control should not share): each walk goes on alone.
        if (collides != controlCollides || (collides && !sameMaterial(ff.label))) {
            float f = finishControl(controlCollides);
            if (collides) {
                stats.scatterEvents += 1;
                path.collide(ff.label);
                if (!survivesRoulette(path, ff.label, rng)) return f;
                Point3f x = ray.at(ff.t_mm);
                ray = {x, path.samplePhase(ff.label, ray.d, rng)};
            } else {
                Vec3f n = -hit->ns;
                float F = fresnelDielectric(-dot(ray.d, n), etaOut);
                f += (1.0f - F) * path.beta * path.Le;
                path.scale(F);
                if (!path.alive()) return f;
                Vec3f r = reflectOnSide(ray.d, *hit);
                if (dot(r, hit->ng) >= 0) r = -hit->ng;
                ray = geometry.spawnRay(hit->p, hit->ng, r);
            }
            stats.paths -= 1;  // walk() counts it again
            return f + (this->*walkSingle_)(ray, path, medium, rng, stats);
        }
        if (collides) {
            // Both collide: shared roulette and phase numbers.
            stats.scatterEvents += 1;
            bounces = 0;
            path.collide(ff.label);
            float q = sharedSurvival(ff.label);
            if (q < 1.0f) {
                if (!(rng.uniform() < q)) return L - Lc * path.Le;
                path.scale(1.0f / q);
                c.weight /= q;
            }
            float u0 = rng.uniform(), u1 = rng.uniform();
            Point3f x = ray.at(ff.t_mm);
            ray = {x, sampleHG(ray.d, path.g(ff.label), u0, u1).dOut};
            c.d = sampleHG(c.d, control.g, u0, u1).dOut;
            continue;
        }
        // Both reach their boundary: Fresnel weighting on each.
        if (++bounces > kMaxBoundaryBounces) {
            stats.trapped += 1;
            return finishControl(false);
        }
        Vec3f n = -hit->ns;
        float F = fresnelDielectric(-dot(ray.d, n), etaOut);
        path.addLight(L, 1.0f - F);
        path.scale(F);
        if (!path.alive()) return finishControl(false);
        Vec3f r = reflectOnSide(ray.d, *hit);
        if (dot(r, hit->ng) >= 0) r = -hit->ng;
        ray = geometry.spawnRay(hit->p, hit->ng, r);
    }
}

float PrintPt::nextEvent(const Point3f& x, const Vec3f& dIn, Label label, int channel,
                         LabelMedium::Sampler& medium, Rng& rng, Lobe& lobe) const {
    Vec3f normal;
    float sdf_mm;
    float uPrune = rng.uniform(), u0 = rng.uniform(), u1 = rng.uniform();  // drawn always: streams stay aligned
    if (!medium.nearestSurface(x, normal, sdf_mm)) return 0.0f;
    const ChannelLut& lut = scene_.medium->lut(channel);
    // Deep below the surface in dense resin, light comes out close to the normal.
    float depth = lut.sigmaT_perMm[label] * std::max(0.0f, -sdf_mm);
    lobe.axis = normal;
    lobe.kappa = std::clamp(depth, 1.0f, options_.neeMaxKappa);
    lobe.probability = std::clamp(options_.neePruneScale * std::exp(-depth), options_.neeMinProbability, 1.0f);
    if (!(uPrune < lobe.probability)) return 0.0f;  // pruned; the phase path's weight knows
    DirectionSample ds = sampleVMF(lobe.axis, lobe.kappa, u0, u1);
    // The boundary straight along the sampled direction, and what gets there.
    auto hit = scene_.geometry->intersectFromInside({x, ds.d});
    if (!hit || dot(ds.d, hit->ng) <= 0) return 0.0f;
    float T = medium.transmittance({x, ds.d}, hit->t, channel, {options_.neeRouletteDepth, &rng});
    if (T <= 0.0f) return 0.0f;
    float F = fresnelDielectric(dot(ds.d, hit->ns), 1.0f / scene_.ior);
    float phase = hgPhase(dot(dIn, ds.d), lut.g[label]);
    // Balance heuristic over the two techniques; NEE's density includes the
    // probability that it ran at all.
    float pNee = lobe.probability * ds.pdf;
    float misWeight = pNee / (pNee + phase);
    return misWeight * phase * T * (1.0f - F) / pNee;
}

}  // namespace pl
