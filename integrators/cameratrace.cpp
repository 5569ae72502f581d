#include "integrators/cameratrace.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/fresnel.h"
#include "core/sampling.h"
#include "integrators/lighttrace.h"
#include "integrators/render_settings.h"
#include "integrators/volume_walk.h"
#include "runtime/interrupt.h"
#include "runtime/memory_budget.h"
#include "runtime/scheduler.h"

namespace pl {

const std::vector<OptionParameter<CameraTraceOptions>>& cameraTraceParameters() {
    using O = CameraTraceOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"cameratrace_particles_per_pixel", &O::particlesPerPixel, 0, 1e6, true, "must be in (0, 1e6]",
         "cameratrace: particles per sample (one block) for each camera pixel"},
    };
    return parameters;
}

namespace {
// Below this optical depth a connection's transmittance is exact; beyond
// it Russian roulette ends most connections early (as lighttrace's).
constexpr float kConnectionRouletteDepth = 2.0f;

const PerspectiveSensor& perspectiveOf(const Sensor& sensor) {
    const auto* camera = dynamic_cast<const PerspectiveSensor*>(&sensor);
    if (!camera) throw std::invalid_argument("cameratrace renders into a \"perspective\" sensor only");
    return *camera;
}

// The horizontal distance r from y's foot on the plane to the point where
// the ray from y (depth h1 below) refracts towards the pinhole (height h2
// above, horizontal distance D from y's foot): Snell's law,
// n r / sqrt(r^2 + h1^2) = (D - r) / sqrt((D - r)^2 + h2^2), whose left
// side less the right rises from r = 0 to r = D. Bisection to float
// precision, Newton's steps where they stay inside the bracket.
float refractionDistance(float D, float h1, float h2, float n) {
    auto f = [&](double r) {
        return n * r / std::sqrt(r * r + double(h1) * h1) - (D - r) / std::sqrt((D - r) * (D - r) + double(h2) * h2);
    };
    auto df = [&](double r) {
        const double a = r * r + double(h1) * h1, b = (D - r) * (D - r) + double(h2) * h2;
        return n * double(h1) * h1 / (a * std::sqrt(a)) + double(h2) * h2 / (b * std::sqrt(b));
    };
    double lo = 0, hi = D, r = D / (1.0 + n * double(h2) / std::max(double(h1), 1e-30));
    for (int i = 0; i < 60 && hi - lo > 1e-7 * D; ++i) {
        const double v = f(r);
        (v < 0 ? lo : hi) = r;
        const double newton = r - v / df(r);
        r = newton > lo && newton < hi ? newton : 0.5 * (lo + hi);
    }
    return float(r);
}
}  // namespace

std::vector<CameraTrace::Plane> CameraTrace::planesOf(const TriangleMesh& mesh) {
    Bounds3f b;
    for (const Point3f& p : mesh.positions_mm) b.expand(p);
    const float tolerance_mm = 1e-5f * length(b.hi - b.lo);
    std::vector<Plane> planes;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Point3f& a = mesh.positions_mm[mesh.indices[3 * t]];
        const Vec3f c = cross(mesh.positions_mm[mesh.indices[3 * t + 1]] - a, mesh.positions_mm[mesh.indices[3 * t + 2]] - a);
        if (!(length(c) > 0.0f)) continue;
        const Plane plane{normalize(c), dot(normalize(c), Vec3f(a.x, a.y, a.z))};
        const bool known = std::any_of(planes.begin(), planes.end(), [&](const Plane& q) {
            return dot(q.n, plane.n) > 1.0f - 1e-5f && std::abs(q.offset - plane.offset) < tolerance_mm;
        });
        if (!known) planes.push_back(plane);
    }
    return planes;
}

CameraTrace::CameraTrace(const Scene& scene, const Sensor& sensor, CameraTraceOptions options, Majorants majorants,
                         uint64_t seed)
    : scene_(scene),
      camera_(perspectiveOf(sensor)),
      options_(options),
      majorants_(majorants),
      volpath_(scene, VolPathOptions{}, /*reentry=*/false),
      lightSeed_(mix64(seed ^ 0x63616d657261ULL)),
      entries_(*scene.geometry) {
    leastSigmaT_ = gridCoefficientsOf(*scene.medium).leastSigmaT;
    const std::vector<Plane> planes = planesOf(scene.geometry->mesh());
    if (planes.size() > kMostPlanes)
        throw std::invalid_argument("cameratrace connects through flat faces: the mesh has " +
                                    std::to_string(planes.size()) + " planes, more than " +
                                    std::to_string(kMostPlanes) + " (render it with printpt or volpath)");
    const Point3f& c = camera_.position_mm();
    for (const Plane& p : planes)
        if (dot(p.n, Vec3f(c.x, c.y, c.z)) > p.offset) planes_.push_back(p);
    const uint64_t tallyBytes = uint64_t(kParts + 1) * sensor.pixelCount() * sizeof(double) * 2;
    if (auto why = memoryShortfall(tallyBytes, "cameratrace's per-part tallies", memoryInUseBytes()))
        throw std::runtime_error("cameratrace: " + *why);
}

IntegratorCapabilities CameraTrace::capabilities(const RenderSettings&) {
    IntegratorCapabilities c;
    c.needs = {false, true};  // volpath's walk looks for the clearance first
    c.lightPathsServeEveryPixel = true;
    c.sensors = kCameraSensor;
    return c;
}

std::unique_ptr<Integrator> CameraTrace::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s,
                                                std::shared_ptr<HalfSpaceMeans>) {
    return std::make_unique<CameraTrace>(scene, sensor, s.cameratrace, s.majorants, s.seed);
}

template <class Score>
void CameraTrace::connect(const Point3f& y, const Vec3f& dIn, Label label, double power, int channel,
                          LabelMedium::Tracker& medium, Rng& rng, Score&& score) const {
    const Geometry& geometry = *scene_.geometry;
    const ChannelLut& lut = scene_.medium->lut(channel);
    const Point3f& c = camera_.position_mm();
    const float n = scene_.ior;
    // The transmittance to a plane h1 below is at most exp(-sigma_min h1):
    // one uniform number plays every plane's roulette on that bound before
    // any work, survival exp(-(bound's depth - kConnectionRouletteDepth)),
    // and the survivors' estimates carry the log of the scale.
    const float sigmaMin = leastSigmaT_[channel];
    const float u = rng.uniform();
    for (const Plane& plane : planes_) {
        const float h1 = plane.offset - dot(plane.n, Vec3f(y.x, y.y, y.z));  // y's depth below the plane
        const float h2 = dot(plane.n, Vec3f(c.x, c.y, c.z)) - plane.offset;  // the pinhole's height above
        if (!(h1 > 0.0f)) continue;
        const float logScale = std::max(0.0f, sigmaMin * h1 - kConnectionRouletteDepth);
        if (!(u < std::exp(-logScale))) continue;
        const Point3f yFoot = y + plane.n * h1, cFoot = c - plane.n * h2;
        const Vec3f across = cFoot - yFoot;
        const float D = length(across);
        const Point3f x = D > 0.0f ? yFoot + across * (refractionDistance(D, h1, h2, n) / D) : yFoot;
        const Vec3f toX = x - y, toCamera = c - x;
        const float d1 = length(toX), d2 = length(toCamera);
        const Vec3f wIn = toX * (1.0f / d1), wOut = toCamera * (1.0f / d2);
        const float cos1 = dot(wIn, plane.n), cos2 = dot(wOut, plane.n);
        if (!(cos1 > 0.0f && cos2 > 0.0f)) continue;
        auto pixel = camera_.importanceOf(-wOut);
        if (!pixel) continue;
        // The pinhole sees x first, and x sees y.
        const float tolerance_mm = geometry.rayEpsilon_mm() * 4.0f;
        auto seen = geometry.intersect(Ray{c, -wOut}, d2 + tolerance_mm);
        if (!seen || seen->t < d2 - tolerance_mm) continue;
        auto inside = geometry.intersectFromInside(Ray{y, wIn}, d1 + tolerance_mm);
        if (!inside || inside->t < d1 - tolerance_mm) continue;
        const float T = medium.transmittance(Ray{y, wIn}, d1, channel,
                                             TransmittanceRoulette{kConnectionRouletteDepth, &rng, logScale});
        if (!(T > 0.0f)) continue;
        const float out = 1.0f - fresnelDielectric(cos1, 1.0f / n);
        const double bundle = 1.0 / ((double(d1) + n * d2) * (double(d1) * cos2 / cos1 + n * double(d2) * cos1 / cos2));
        score(pixel->pixel, power * hgPhase(dot(dIn, wIn), lut.g[label]) * T * out * bundle * pixel->importance);
    }
}

std::vector<double> CameraTrace::scoreBlock(int channel, uint32_t sample, PathStats& stats) const {
    const size_t pixels = camera_.pixelCount();
    std::vector<double> block(pixels, 0.0);
    const double Le = scene_.environment[channel];
    if (!(Le > 0.0) || planes_.empty()) return block;
    const ChannelLut& lut = scene_.medium->lut(channel);
    const uint64_t count = std::max<uint64_t>(1, uint64_t(std::llround(options_.particlesPerPixel * double(pixels))));
    const double power = Le * kPi * entries_.area_mm2() / double(count);
    // Parts in groups of as many as run at once, each into a tally of its
    // own, added in part order.
    const size_t group = std::max<size_t>(1, std::min(kParts, size_t(tbb::this_task_arena::max_concurrency())));
    std::vector<std::vector<double>> tallies(group);
    std::vector<PathStats> partStats(group);
    for (size_t first = 0; first < kParts; first += group) {
        const size_t parts = std::min(group, kParts - first);
        parallelForTiles(parts, 1, [&](size_t begin, size_t end) {
            LabelMedium::Tracker medium(*scene_.medium, majorants_);
            for (size_t k = begin; k < end; ++k) {
                const size_t part = first + k;
                std::vector<double>& tally = tallies[k];
                tally.assign(pixels, 0.0);
                partStats[k] = PathStats{};
                for (uint64_t i = count * part / kParts; i < count * (part + 1) / kParts; ++i) {
                    if (interruptRequested()) return;
                    Rng rng = Rng::forPath(lightSeed_, i, sample, uint64_t(channel));
                    const SurfaceHit entry = entries_.sample(rng);
                    SingleChannelPath path{&lut, channel, scene_.environment[channel]};
                    auto onCollision = [&](const Point3f& y, const Vec3f& dIn, Label label, const SingleChannelPath& p) {
                        connect(y, dIn, label, power * double(p.beta), channel, medium, rng,
                                [&](size_t pixel, double value) { tally[pixel] += value; });
                    };
                    walkParticleIn(scene_, VolPathOptions{}, entry, path, medium, rng, partStats[k],
                                   [](const Ray&, float, const SingleChannelPath&) {}, onCollision);
                }
            }
        });
        for (size_t k = 0; k < parts; ++k) {
            for (size_t p = 0; p < pixels; ++p) block[p] += tallies[k][p];
            stats += partStats[k];
        }
    }
    return block;
}

void CameraTrace::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    if (pass.channel < 0) throw std::logic_error("cameratrace renders one channel per pass");
    const PixelShare& share = pass.share;
    for (uint32_t s = pass.firstSample; s < pass.firstSample + pass.count; ++s) {
        const std::vector<double> block = scoreBlock(pass.channel, s, stats);
        renderPixelTiles(pass, stats, progress, 1, [&](size_t i, LabelMedium::Tracker& medium, PathStats& tileStats) {
            const size_t p = share.pixel(i);
            Rng rng = Rng::forPath(pass.seed, p, s, uint64_t(pass.channel));
            const float u0 = rng.uniform(), u1 = rng.uniform();
            ChannelSample sample = unscatteredCameraSide(scene_, volpath_, pass.sensor.generateRay(p, u0, u1),
                                                         pass.channel, medium, rng, tileStats);
            // The block's score is part of each sample's random value: the
            // pixel's error is its samples' spread, not pooled residuals.
            sample.value += float(block[p]);
            sample.poolKey = -1;
            sample.residual = 0.0f;
            sample.poolWhereFlat = false;
            film.add(share.filmPixel(i), pass.channel, sample);
        });
    }
}

}  // namespace pl
