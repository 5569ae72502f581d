#include "integrators/photons/bre.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/fresnel.h"
#include "core/sampling.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/photon_iterations.h"
#include "integrators/photons/photon_parts.h"
#include "integrators/photons/progressive_radius.h"
#include "integrators/render_settings.h"
#include "media/dda.h"

namespace pl {

const std::vector<OptionParameter<BreOptions>>& breParameters() {
    using O = BreOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"bre_photons_per_pixel", &O::photonsPerPixel, 0, 1e6, true, "must be in (0, 1e6]",
         "bre: photons traced per iteration (sample) for each sensor pixel"},
        {"bre_radius_voxels", &O::radius_voxels, 0, 100, true, "must be in (0, 100] (voxel sides)",
         "bre: the first iteration's kernel radius, in the smallest voxel side"},
        {"bre_alpha", &O::alpha, 0, 1, true, "must be in (0, 1]",
         "bre: r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1); 1 keeps the radius"},
    };
    return parameters;
}

namespace {
// Where the light left along a query has fallen below 1 %, the photons
// beyond are left out (Brecka 2021, 3.7.2).
constexpr float kCutOffOpticalDepth = 4.6051702f;  // ln 100
// Straight segments a query follows inside (each internal reflection
// starts one) before it stops; the weight left by then is F^16 at most.
constexpr int kMostSegments = 16;
}  // namespace

Bre::Bre(const Scene& scene, const Sensor& sensor, BreOptions options, Majorants majorants, uint64_t seed)
    : scene_(scene),
      photons_(scene, majorants, options.photonsPerPixel, sensor.pixelCount(), seed, 0x62726550ULL, kPhotonBytes,
               "bre", "photons", "lower bre_photons_per_pixel"),
      radius_(options.radius_voxels, scene.medium->frame().voxelSize_mm, options.alpha, 2) {}

IntegratorCapabilities Bre::capabilities(const RenderSettings&) { return photonCapabilities(); }

std::unique_ptr<Integrator> Bre::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Bre>(scene, sensor, readOptions(breParameters(), s.parameters), s.majorants, s.seed);
}

float Bre::radiusAt_mm(uint32_t iteration) const { return radius_.at_mm(iteration); }

PhotonMap Bre::tracePhotons(int channel, uint32_t sample, PathStats& stats) const {
    return tracePhotonPoints(photons_, channel, sample, radiusAt_mm(sample + 1), stats);
}

Bre::SegmentGather Bre::gatherSegment(const PhotonMap& map, const Ray& ray, float tEnd_mm, int channel,
                                      LabelMedium::Tracker& medium) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    // The optical depth along the segment: constant over each voxel it
    // crosses (regular tracking), cut where the light left falls below 1 %.
    struct Piece {
        float t0, t1;
        double tau0;  // optical depth at t0
        float sigmaT;
    };
    thread_local std::vector<Piece> pieces;
    pieces.clear();
    const GridFrame& frame = scene_.medium->frame();
    const CellRay cells = scene_.medium->toCellRay(ray);
    GridDda dda(cells.o, cells.d, 0.0f, tEnd_mm, frame.indexMin, frame.indexMax());
    DdaSegment segment;
    double tau = 0;
    float tCut = tEnd_mm;
    bool cut = false;
    while (dda.next(segment)) {
        const float sigmaT = lut.sigmaT_perMm[medium.labelAt(segment.cell)];
        pieces.push_back({segment.t0, segment.t1, tau, sigmaT});
        const double after = tau + double(sigmaT) * (segment.t1 - segment.t0);
        if (after > kCutOffOpticalDepth) {
            tCut = segment.t0 + float((kCutOffOpticalDepth - tau) / double(sigmaT));
            cut = true;
            break;
        }
        tau = after;
    }
    auto transmittanceTo = [&](float t) {
        auto after = std::upper_bound(pieces.begin(), pieces.end(), t, [](float x, const Piece& p) { return x < p.t0; });
        if (after == pieces.begin()) return 1.0;
        const Piece& p = *(after - 1);
        return std::exp(-(p.tau0 + double(p.sigmaT) * (std::min(t, p.t1) - p.t0)));
    };
    const float r2 = map.radius_mm() * map.radius_mm();
    TwoRadii sum;
    map.forEachNear(ray, tCut, [&](const PhotonMap::Photon& ph) {
        const Vec3f v = ph.p - ray.o;
        const float t = dot(v, ray.d);
        if (t < 0.0f || t > tCut) return;
        const float d2 = dot(v, v) - t * t;
        if (!(d2 < r2)) return;
        sum += discBiweight(d2, r2) *
               (transmittanceTo(t) * hgPhase(dot(ph.dIn, -ray.d), lut.g[ph.label]) * double(ph.power));
    });
    return {sum, cut ? 0.0f : float(std::exp(-tau))};
}

ChannelSample Bre::gather(const PhotonMap& map, const Ray& cameraRay, const std::optional<SurfaceHit>& entry,
                          int channel, LabelMedium::Tracker& medium) const {
    const Geometry& geometry = *scene_.geometry;
    const float Le = scene_.environment[channel];
    if (!entry) return ChannelSample{Le};
    const Vec3f n = dot(cameraRay.d, entry->ng) < 0 ? entry->ns : -entry->ns;
    const float F = fresnelDielectric(-dot(cameraRay.d, n), scene_.ior);
    double L = double(F) * Le;  // what comes without the kernel
    TwoRadii gathered;
    double beta = 1.0 - F;
    Ray ray = enteringRay(scene_, cameraRay, *entry);
    for (int segment = 0; segment < kMostSegments && beta > 1e-6; ++segment) {
        std::optional<SurfaceHit> exit = geometry.intersectFromInside(ray);
        if (!exit) exit = geometry.exitBeforeTMin(ray);  // spawned at an edge
        if (!exit) break;                                // a numerical leak
        const SegmentGather g = gatherSegment(map, ray, exit->t, channel, medium);
        gathered += g.radiance * (beta * insideToOutside(scene_));
        if (!(g.transmittance > 0.0f)) break;
        // The environment straight through the far side, and the rest
        // reflected back inside.
        const float Ffar = fresnelDielectric(std::abs(dot(ray.d, exit->ns)), 1.0f / scene_.ior);
        L += beta * g.transmittance * (1.0f - Ffar) * Le;
        beta *= double(g.transmittance) * Ffar;
        ray = reflectedInside(geometry, ray.d, *exit);
    }
    return kernelSample(L, gathered);
}

void Bre::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    renderPhotonIterations(
        pass, film, stats, progress, "bre", [&](uint32_t s) { return tracePhotons(pass.channel, s, stats); },
        [&](const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
            LabelMedium::Tracker& medium, Rng&, PathStats& tileStats) {
            ++tileStats.paths;
            return gather(map, ray, entry, pass.channel, medium);
        });
}

}  // namespace pl
