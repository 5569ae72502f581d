#include "integrators/photons/bre.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/fresnel.h"
#include "core/sampling.h"
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
// Bytes a photon takes while its iteration's map is built (the photon in
// its part and in the map, its grid entry and its place in the grid).
constexpr uint64_t kPhotonBytes = 2 * sizeof(PhotonMap::Photon) + 16 + 4;

Point3f lowestCorner(const std::vector<PhotonMap::Photon>& photons) {
    Point3f lo{1e30f, 1e30f, 1e30f};
    for (const PhotonMap::Photon& ph : photons)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], ph.p[a]);
    return photons.empty() ? Point3f{0, 0, 0} : lo;
}
}  // namespace

PhotonMap::PhotonMap(std::vector<Photon> photons, float radius_mm)
    : radius_mm_(radius_mm), grid_(radius_mm, lowestCorner(photons)) {
    std::vector<std::pair<uint64_t, uint32_t>> entries(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) entries[i] = {grid_.keyOf(grid_.cellOf(photons[i].p)), uint32_t(i)};
    grid_.fill(std::move(entries));
    // Stored in the grid's order: a cell's photons lie together.
    photons_.resize(grid_.entries());
    for (size_t i = 0; i < photons_.size(); ++i) photons_[i] = photons[grid_.itemAt(i)];
}

Bre::Bre(const Scene& scene, const Sensor& sensor, BreOptions options, Majorants majorants, uint64_t seed)
    : scene_(scene),
      photons_(scene, majorants, options.photonsPerPixel, sensor.pixelCount(), seed, 0x62726550ULL, kPhotonBytes,
               "bre", "photons", "lower bre_photons_per_pixel"),
      radius_(options.radius_voxels, scene.medium->frame().voxelSize_mm, options.alpha, 2) {}

IntegratorCapabilities Bre::capabilities(const RenderSettings&) {
    IntegratorCapabilities c;
    c.needs = {false, true};  // volpath's walk looks for the clearance first
    c.lightPathsServeEveryPixel = true;
    return c;
}

std::unique_ptr<Integrator> Bre::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Bre>(scene, sensor, readOptions(breParameters(), s.parameters), s.majorants, s.seed);
}

float Bre::radiusAt_mm(uint32_t iteration) const { return radius_.at_mm(iteration); }

PhotonMap Bre::tracePhotons(int channel, uint32_t sample, PathStats& stats) const {
    const double power = photons_.powerEach(channel);
    // Stored at every real collision with the power after the albedo.
    std::vector<PhotonMap::Photon> photons = photons_.trace<PhotonMap::Photon>(
        channel, sample, stats, [](std::vector<PhotonMap::Photon>&, const Ray&, float, const SingleChannelPath&) {},
        [&](std::vector<PhotonMap::Photon>& stored, const Point3f& y, const Vec3f& dIn, Label label,
            const SingleChannelPath& p) { stored.push_back({y, dIn, float(power * double(p.beta)), label}); });
    return PhotonMap(std::move(photons), radiusAt_mm(sample + 1));
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

ChannelSample Bre::gather(const PhotonMap& map, const Ray& cameraRay, int channel,
                          LabelMedium::Tracker& medium) const {
    const Geometry& geometry = *scene_.geometry;
    const float Le = scene_.environment[channel];
    const std::optional<SurfaceHit> entry = geometry.intersect(cameraRay);
    if (!entry) return ChannelSample{Le};
    const Vec3f n = dot(cameraRay.d, entry->ng) < 0 ? entry->ns : -entry->ns;
    const float F = fresnelDielectric(-dot(cameraRay.d, n), scene_.ior);
    double L = double(F) * Le;  // what comes without the kernel
    TwoRadii gathered;
    // The radiance inside, in the path tracers' unit: over n^2.
    const double insideToOutside = 1.0 / (double(scene_.ior) * scene_.ior);
    double beta = 1.0 - F;
    Ray ray = enteringRay(scene_, cameraRay, *entry);
    for (int segment = 0; segment < kMostSegments && beta > 1e-6; ++segment) {
        const std::optional<SurfaceHit> exit = geometry.intersectFromInside(ray);
        if (!exit) break;  // a numerical leak
        const SegmentGather g = gatherSegment(map, ray, exit->t, channel, medium);
        gathered += g.radiance * (beta * insideToOutside);
        if (!(g.transmittance > 0.0f)) break;
        // The environment straight through the far side, and the rest
        // reflected back inside.
        const float Ffar = fresnelDielectric(std::abs(dot(ray.d, exit->ns)), 1.0f / scene_.ior);
        L += beta * g.transmittance * (1.0f - Ffar) * Le;
        beta *= double(g.transmittance) * Ffar;
        ray = reflectedInside(geometry, ray.d, *exit);
    }
    ChannelSample sample = kernelSample(L, gathered);
    poolByEntry(sample, scene_, cameraRay, entry, channel, medium);
    return sample;
}

void Bre::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    if (pass.channel < 0) throw std::logic_error("bre renders one channel per pass");
    const PixelShare& share = pass.share;
    for (uint32_t s = pass.firstSample; s < pass.firstSample + pass.count; ++s) {
        const PhotonMap map = tracePhotons(pass.channel, s, stats);
        renderPixelTiles(pass, stats, progress, 1, [&](size_t i, LabelMedium::Tracker& medium, PathStats& tileStats) {
            const size_t p = share.pixel(i);
            Rng rng = Rng::forPath(pass.seed, p, s, uint64_t(pass.channel));
            const float u0 = rng.uniform(), u1 = rng.uniform();
            const ChannelSample sample = gather(map, pass.sensor.generateRay(p, u0, u1), pass.channel, medium);
            film.add(share.filmPixel(i), pass.channel, sample);
            ++tileStats.paths;
        });
    }
}

}  // namespace pl
