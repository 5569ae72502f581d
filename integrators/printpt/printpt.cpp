#include "integrators/printpt/printpt.h"

#include <type_traits>

#include "core/fresnel.h"
#include "core/sampling.h"
#include "integrators/printpt/controlled_path.h"
#include "integrators/render_settings.h"
#include "media/ball_walk.h"

namespace pl {

IntegratorCapabilities PrintPt::capabilities(const RenderSettings& settings) {
    IntegratorCapabilities c;
    const PrintPtOptions options = readOptions(printPtParameters(), settings.parameters);
    c.needs = {options.nee, options.clearance || options.ballWalks};
    c.threeChannelsInOnePath = !options.nee;
    return c;
}

std::unique_ptr<Integrator> PrintPt::create(const Scene& scene, const Sensor&, const RenderSettings& settings) {
    return std::make_unique<PrintPt>(scene, readOptions(printPtParameters(), settings.parameters), settings.seed);
}

ChannelSample PrintPt::Li(Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                          PathStats& stats) const {
    return traceOneChannel(scene_, channel, [&](const auto& path) {
        Traced<float> t = trace(ray, path, medium, rng, stats);
        return ChannelSample{t.L, t.sharedError, t.poolKey, t.residual, t.poolWhereFlat};
    });
}

RGB PrintPt::LiRGB(Ray ray, ChannelSampling sampling, int hero, LabelMedium::Tracker& medium, Rng& rng,
                   PathStats& stats) const {
    return traceThreeChannels(scene_, sampling, hero,
                              [&](const auto& path) { return trace(ray, path, medium, rng, stats).L; });
}

template <class Path>
PrintPt::Traced<typename Path::Value> PrintPt::trace(Ray ray, const Path& path, LabelMedium::Tracker& medium,
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
    const Ray inside = enteringRay(scene_, ray, *entry);

    // Branching: k walks share the camera ray and the entry.
    const int k = std::max(1, options_.branches);
    const float branchWeight = transmitted / float(k);
    WalkFunction<Path> walkPath;
    if constexpr (std::is_same_v<Path, SingleChannelPath>) walkPath = walkSingle_;
    else if constexpr (std::is_same_v<Path, HeroPath>) walkPath = walkHero_;
    else walkPath = walkSpectral_;
    std::optional<ControlVariate::EntryControl> control;
    if constexpr (std::is_same_v<Path, SingleChannelPath>)
        if (options_.controlVariate) control = control_.forEntry(inside, path, medium);
    if (control) {
        // Every branch adds the same mean: its error is shared, not averaged.
        result.sharedError = transmitted * control->meanError;
        result.poolKey = control->key;
        stats.controlledWalks[int(control->kind)] += uint64_t(k);
    } else if constexpr (std::is_same_v<Path, SingleChannelPath>) {
        result.poolKey = entryPoolKey(path.channel, medium.labelAt(scene_.medium->voxelAt(inside.o)));
        result.poolWhereFlat = true;
    }
    for (int b = 0; b < k; ++b) {
        // Each walk starts at throughput 1 (Russian roulette is relative to it).
        typename Path::Value Lb{};
        if constexpr (std::is_same_v<Path, SingleChannelPath>) {
            if (control) {
                // forScene runs controls only medium first, Fresnel-weighted, without NEE.
                ControlledPath controlled(path, control->region, inside.d, options_);
                const float difference = walk<ControlledPath, false, true, true>(inside, controlled, medium, rng, stats);
                result.residual += branchWeight * difference;
                Lb = difference + control->mean;
            } else {
                Lb = (this->*walkPath)(inside, path, medium, rng, stats);
            }
        } else {
            Lb = (this->*walkPath)(inside, path, medium, rng, stats);
        }
        if constexpr (std::is_same_v<typename Path::Value, float>) {
            L += branchWeight * Lb;
            if (!control) result.residual += branchWeight * Lb;
        } else
            for (int c = 0; c < 3; ++c) L[c] += branchWeight * Lb[c];
    }
    return result;
}

namespace {

// The switches that run with this scene, decided once: NEE needs the
// surface fields of a prepared .vdb. The control variate is for walks
// without NEE, and its coupled walk (ControlledPath) samples the medium
// first and weights by Fresnel: with either switch off the control does
// not run, so that those switches mean what they say.
PrintPtOptions forScene(PrintPtOptions options, const Scene& scene) {
    options.nee = options.nee && scene.medium->hasSurfaceFields();
    options.controlVariate =
        options.controlVariate && !options.nee && options.mediumFirst && options.fresnelWeighting;
    return options;
}

}  // namespace

PrintPt::PrintPt(const Scene& scene, PrintPtOptions options, uint64_t seed)
    : scene_(scene), options_(forScene(options, scene)), control_(scene, options_, seed) {
    // The walk is compiled once per combination of the switches it tests
    // in its loop; the scene picks one here and the loop pays for no branch.
    walkSingle_ = selectWalk<SingleChannelPath>();
    walkHero_ = selectWalk<HeroPath>();
    walkSpectral_ = selectWalk<SpectralPath>();
}

void PrintPt::preprocess(const Sensor& sensor, const std::vector<int>& channels) { control_.survey(sensor, channels); }

bool PrintPt::controlsEntry(const Ray& cameraRay, int channel, LabelMedium::Tracker& medium) const {
    if (!options_.controlVariate) return false;
    auto entry = scene_.geometry->intersect(cameraRay);
    if (!entry) return false;
    const SingleChannelPath path{&scene_.medium->lut(channel), channel, scene_.environment[channel]};
    return control_.forEntry(enteringRay(scene_, cameraRay, *entry), path, medium).has_value();
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
typename Path::Value PrintPt::walk(Ray ray, Path path, LabelMedium::Tracker& medium, Rng& rng,
                                   PathStats& stats) const {
    constexpr bool kControlled = std::is_same_v<Path, ControlledPath>;
    const Geometry& geometry = *scene_.geometry;
    const float etaOut = 1.0f / scene_.ior;
    typename Path::Value L{};
    // The walk's value where it ends: L, or with a control f - g;
    // absorbed: by Russian roulette.
    auto end = [&](bool absorbed) {
        if constexpr (kControlled) return path.value(L, absorbed, rng);
        else return L;
    };
    int64_t bounces = 0;
    stats.paths += 1;
    const SurfaceClearance* clearance = options_.clearance ? scene_.clearance.get() : nullptr;
    const bool balls = options_.ballWalks && scene_.clearance && !kNee;
    // MIS weight of the next boundary hit's transmitted light: below 1 only
    // for the first hit after a collision where next-event estimation ran.
    float hitWeight = 1.0f;

    bool deep = false;  // the last collision needed no boundary query: worth looking for a ball
    for (;;) {
        if constexpr (kControlled) {
            if (!path.coupled) {
                // The control parted in the last step: the plain walk goes on.
                stats.paths -= 1;  // which counts the path again
                return path.value(L, false, rng) + (this->*walkSingle_)(ray, path.plain(), medium, rng, stats);
            }
        }
        if (balls && deep) {
            // Deep in one material: walk to the edge of a ball that holds
            // nothing else, without grid lookups or boundary queries.
            Ball ball = homogeneousBall(ray.o);
            if constexpr (kControlled) ball.radius_mm = std::min(ball.radius_mm, path.ballLimit_mm(ray.d));
            if (ball.radius_mm > 0.0f && path.canWalkBall(ball.label) &&
                ball.radius_mm * path.ballSigmaT(ball.label) >= options_.ballMinMfp) {
                if (!walkInBall(ray, ball.radius_mm, ball.label, path, rng, stats)) return end(true);
                bounces = 0;
                hitWeight = 1.0f;
                continue;
            }
        }
        // Distance to the next real collision, then the boundary up to it.
        auto track = [&](const Ray& r, float tMax) { return path.track(medium, r, tMax, rng); };
        FreeFlight ff;
        std::optional<SurfaceHit> hit;
        if constexpr (kMediumFirst) {
            ff = flightFromSurface(ray, 1e30f, track);
            // A collision nearer than the boundary can be needs no query.
            deep = ff.scattered && clearance && ff.t_mm < clearance->at(ray.o);
            if (!deep) hit = geometry.intersectFromInside(ray, ff.scattered ? ff.t_mm : 1e30f);
        } else {
            hit = geometry.intersectFromInside(ray);
            if (hit) ff = flightFromSurface(ray, hit->t, track);
        }
        if (!hit && !(kMediumFirst && ff.scattered)) {
            stats.leaks += 1;  // left an open mesh: count it, treat as leaving
            path.addLight(L, 1.0f);
            return end(false);
        }
        // Medium first: the boundary query only reached the collision, so a
        // hit means the boundary comes first. Geometry first: the tracking
        // only reached the boundary, so a collision means it comes first.
        bool boundaryFirst = kMediumFirst ? hit.has_value() : !ff.scattered;
        if (boundaryFirst && dot(ray.d, hit->ng) < 0) {
            // Round-off put the ray outside, facing the surface: it leaves.
            stats.leaks += 1;
            path.addLight(L, 1.0f);
            return end(false);
        }
        if constexpr (kControlled) path.partsAfterFlight(!boundaryFirst, ff.label, L, rng);

        if (!boundaryFirst) {
            // Scattering: weight by the albedo, Russian roulette, phase sampling.
            stats.scatterEvents += 1;
            bounces = 0;
            path.collide(ff.label);
            if (!survivesRoulette(path, ff.label, rng)) return end(true);
            Point3f x = ray.at(ff.t_mm);
            NextEvent nee;
            if constexpr (kNee) {
                nee = nextEvent(x, ray.d, ff.label, path.channel, medium, rng);
                path.addLight(L, nee.light);
            }
            const Lobe& lobe = nee.lobe;
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
            return end(false);
        }
        Vec3f n = -hit->ns;  // facing against the ray
        float F = fresnelDielectric(-dot(ray.d, n), etaOut);
        if constexpr (kFresnelWeighting) {
            path.addLight(L, hitWeight * (1.0f - F));  // the transmitted part leaves for good
            path.scale(F);
            if (!path.alive()) return end(false);
            // The throughput roulette plays after every inner reflection
            // too: where no collision comes between reflections (clear
            // resin) nothing else would end the path before its weight
            // underflows. Not in a controlled walk, whose control walker
            // does not reflect here: scaling both would part them.
            if constexpr (!kControlled)
                if (!survivesRouletteAbove(path, options_.rrThreshold, rng)) return end(true);
        } else if (!(rng.uniform() < F)) {
            path.addLight(L, hitWeight);
            return end(false);
        }
        hitWeight = 1.0f;  // light after an inner reflection has no NEE counterpart
        ray = reflectedInside(geometry, ray.d, *hit);
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
    return survivesRouletteAbove(path, rouletteThreshold(path, label), rng);
}

template <class Path>
bool PrintPt::survivesRouletteAbove(Path& path, float threshold, Rng& rng) const {
    const float q = std::min(options_.rrCap, path.rouletteValue() / threshold);
    return playRoulette(q, rng, [&](float survival) {
        if constexpr (std::is_same_v<Path, ControlledPath>) path.survive(survival);  // the control's weight too
        else path.scale(1.0f / survival);
    });
}

PrintPt::Ball PrintPt::homogeneousBall(const Point3f& p) const {
    const LabelMedium& medium = *scene_.medium;
    const UniformRegions::Cell cell = medium.uniformRegions().at(medium.voxelAt(p));
    if (cell.radius_mm <= 0.0f) return {};
    return Ball{std::min(cell.radius_mm, scene_.clearance->at(p)), Label(cell.label)};
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
    if constexpr (std::is_same_v<Path, ControlledPath>) path.followBall(ray.d, b.exit, b.direction);
    stats.scatterEvents += uint64_t(b.collisions);
    stats.ballEvents += uint64_t(b.collisions);
    ray = {ray.o + b.exit, b.direction};
    return b.alive;
}

PrintPt::NextEvent PrintPt::nextEvent(const Point3f& x, const Vec3f& dIn, Label label, int channel,
                                      LabelMedium::Tracker& medium, Rng& rng) const {
    NextEvent result;
    Lobe& lobe = result.lobe;
    float uPrune = rng.uniform(), u0 = rng.uniform(), u1 = rng.uniform();  // drawn always: streams stay aligned
    auto surface = medium.nearestSurface(x);
    if (!surface) return result;
    const ChannelLut& lut = scene_.medium->lut(channel);
    // Deep below the surface in dense resin, light comes out close to the normal.
    float depth = lut.sigmaT_perMm[label] * std::max(0.0f, -surface->sdf_mm);
    lobe.axis = surface->normal;
    lobe.kappa = std::clamp(depth, 1.0f, options_.neeMaxKappa);
    lobe.probability = std::clamp(options_.neePruneScale * std::exp(-depth), options_.neeMinProbability, 1.0f);
    if (!(uPrune < lobe.probability)) return result;  // pruned; the phase path's weight knows
    DirectionSample ds = sampleVMF(lobe.axis, lobe.kappa, u0, u1);
    // The boundary straight along the sampled direction, and what gets there.
    auto hit = scene_.geometry->intersectFromInside({x, ds.d});
    if (!hit || dot(ds.d, hit->ng) <= 0) return result;
    float T = medium.transmittance({x, ds.d}, hit->t, channel, {options_.neeRouletteDepth, &rng});
    if (T <= 0.0f) return result;
    float F = fresnelDielectric(dot(ds.d, hit->ns), 1.0f / scene_.ior);
    float phase = hgPhase(dot(dIn, ds.d), lut.g[label]);
    // Balance heuristic over the two techniques; NEE's density includes the
    // probability that it ran at all.
    float pNee = lobe.probability * ds.pdf;
    float misWeight = pNee / (pNee + phase);
    result.light = misWeight * phase * T * (1.0f - F) / pNee;
    return result;
}

}  // namespace pl
