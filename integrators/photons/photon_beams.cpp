#include "integrators/photons/photon_beams.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/photon_iterations.h"
#include "runtime/memory_budget.h"

namespace pl {

const std::vector<OptionParameter<BeamOptions>>& beamParameters() {
    using O = BeamOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"beams_photons_per_pixel", &O::photonsPerPixel, 0, 1e6, true, "must be in (0, 1e6]",
         "pb2d, bb1d: photons traced per iteration (sample) for each sensor pixel"},
        {"beams_radius_voxels", &O::radius_voxels, 0, 100, true, "must be in (0, 100] (voxel sides)",
         "pb2d, bb1d: the first iteration's kernel radius, in the smallest voxel side"},
        {"beams_alpha", &O::alpha, 0, 1, true, "must be in (0, 1]",
         "pb2d, bb1d: the kernel's measure (r^2, r) shrinks by (i + alpha) / (i + 1); 1 keeps the radius"},
    };
    return parameters;
}

namespace {
// Bytes a beam takes while its iteration's map is built: the beam in its
// part and in the map, its first entry's index, and its cells' entries
// (a beam crosses 2 to 7 cells of a voxel's side in the resins; the map
// checks the entries it makes against the memory once it has counted them).
constexpr uint64_t kEntryBytes = 16 + 4;  // sorted (cell, beam) pair, and the beam's place in its cell
constexpr uint64_t kBeamBytes = 2 * sizeof(PhotonBeam) + 8 + 3 * kEntryBytes;
}  // namespace

PhotonBeamMap::PhotonBeamMap(std::vector<PhotonBeam> beams, float radius_mm, const Point3f& origin_mm)
    : beams_(std::move(beams)), radius_mm_(radius_mm), grid_(radius_mm, origin_mm) {
    // In parallel and in two passes (how many cells each beam crosses, then
    // the entries where the counts put them): the same entries whatever the threads.
    std::vector<uint64_t> firstEntry(beams_.size() + 1, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, beams_.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            const PhotonBeam& b = beams_[i];
            uint64_t cells = 0;
            grid_.forEachCellCrossed(Ray{b.o, b.d}, b.length_mm, [&](uint64_t) { ++cells; });
            firstEntry[i + 1] = cells;
        }
    });
    for (size_t i = 0; i < beams_.size(); ++i) firstEntry[i + 1] += firstEntry[i];
    // A beam crosses length / r cells: more as the radius shrinks, many in
    // clear resin; refused before the entries are made if they do not fit.
    if (auto why = memoryShortfall(firstEntry.back() * kEntryBytes,
                                   std::to_string(firstEntry.back()) + " cells crossed by one iteration's beams",
                                   memoryInUseBytes(), "lower beams_photons_per_pixel or raise beams_radius_voxels"))
        throw std::runtime_error("photon beams: " + *why);
    std::vector<std::pair<uint64_t, uint32_t>> entries(firstEntry.back());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, beams_.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
            const PhotonBeam& b = beams_[i];
            uint64_t at = firstEntry[i];
            grid_.forEachCellCrossed(Ray{b.o, b.d}, b.length_mm,
                                     [&](uint64_t key) { entries[at++] = {key, uint32_t(i)}; });
        }
    });
    grid_.fill(std::move(entries));
}

TwoRadii BeamSum::total() {
    // A beam's repeats are equal: the order among them does not matter.
    std::sort(terms_.begin(), terms_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    TwoRadii sum;
    for (size_t i = 0; i < terms_.size(); ++i)
        if (i == 0 || terms_[i].first != terms_[i - 1].first) sum += terms_[i].second;
    return sum;
}

PhotonBeamEstimator::PhotonBeamEstimator(const Scene& scene, const Sensor& sensor, BeamOptions options,
                                         int kernelDimensions, Majorants majorants, uint64_t seed)
    : scene_(scene),
      photons_(scene, majorants, options.photonsPerPixel, sensor.pixelCount(), seed, 0x6265616dULL, kBeamBytes,
               "photon beams", "photon beams", "lower beams_photons_per_pixel"),
      radius_(options.radius_voxels, scene.medium->frame().voxelSize_mm, options.alpha, kernelDimensions) {}

IntegratorCapabilities PhotonBeamEstimator::capabilities(const RenderSettings&) { return photonCapabilities(); }

float PhotonBeamEstimator::radiusAt_mm(uint32_t iteration) const { return radius_.at_mm(iteration); }

PhotonBeamMap PhotonBeamEstimator::traceBeams(int channel, uint32_t sample, PathStats& stats) const {
    const double power = photons_.powerEach(channel);
    // A beam for every flight, with the power the photon carries along it.
    std::vector<PhotonBeam> beams = photons_.trace<PhotonBeam>(
        channel, sample, stats,
        [&](std::vector<PhotonBeam>& stored, const Ray& flight, float tEnd_mm, const SingleChannelPath& p) {
            if (tEnd_mm > 0.0f) stored.push_back({flight.o, flight.d, tEnd_mm, float(power * p.beta)});
        },
        [](std::vector<PhotonBeam>&, const Point3f&, const Vec3f&, Label, const SingleChannelPath&) {});
    // Cells from a radius below the object's lowest corner (no beam lies below it).
    const float radius_mm = radiusAt_mm(sample + 1);
    const Point3f origin = scene_.geometry->bounds().lo - Vec3f{1, 1, 1} * radius_mm;
    return PhotonBeamMap(std::move(beams), radius_mm, origin);
}

void PhotonBeamEstimator::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    renderPhotonIterations(
        pass, film, stats, progress, "photon beams",
        [&](uint32_t s) { return traceBeams(pass.channel, s, stats); },
        [&](const PhotonBeamMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
            LabelMedium::Tracker& medium, Rng& rng, PathStats& tileStats) {
            return Li(map, ray, entry, pass.channel, medium, rng, tileStats);
        });
}

}  // namespace pl
