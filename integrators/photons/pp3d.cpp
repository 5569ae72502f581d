#include "integrators/photons/pp3d.h"

#include "core/sampling.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/clear_gather.h"
#include "integrators/photons/photon_iterations.h"
#include "integrators/render_settings.h"

namespace pl {

const std::vector<OptionParameter<Pp3dOptions>>& pp3dParameters() {
    using O = Pp3dOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"pp3d_photons_per_pixel", &O::photonsPerPixel, 0, 1e6, true, "must be in (0, 1e6]",
         "pp3d: photons traced per iteration (sample) for each sensor pixel"},
        {"pp3d_radius_voxels", &O::radius_voxels, 0, 100, true, "must be in (0, 100] (voxel sides)",
         "pp3d: the first iteration's kernel radius, in the smallest voxel side"},
        {"pp3d_alpha", &O::alpha, 0, 1, true, "must be in (0, 1]",
         "pp3d: r_{i+1}^3 = r_i^3 (i + alpha) / (i + 1); 1 keeps the radius"},
    };
    return parameters;
}

Pp3d::Pp3d(const Scene& scene, const Sensor& sensor, Pp3dOptions options, Majorants majorants, uint64_t seed)
    : scene_(scene),
      photons_(scene, majorants, options.photonsPerPixel, sensor.pixelCount(), seed, 0x70703364ULL, kPhotonBytes,
               "pp3d", "photons", "lower pp3d_photons_per_pixel"),
      radius_(options.radius_voxels, scene.medium->frame().voxelSize_mm, options.alpha, 3) {}

IntegratorCapabilities Pp3d::capabilities(const RenderSettings&) { return photonCapabilities(); }

std::unique_ptr<Integrator> Pp3d::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Pp3d>(scene, sensor, readOptions(pp3dParameters(), s.parameters), s.majorants, s.seed);
}

ChannelSample Pp3d::Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry, int channel,
                       LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    auto gatherAt = [&](const Point3f& x, const Vec3f& dIn, Label label) {
        return gatherBall(map, lut, x, dIn, lut.g[label], [](double f) { return f; });
    };
    return gatherWhereClear(scene_, map.radius_mm(), ray, entry, channel, medium, rng, stats, gatherAt);
}

void Pp3d::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    renderPhotonIterations(
        pass, film, stats, progress, "pp3d",
        [&](uint32_t s) { return tracePhotonPoints(photons_, pass.channel, s, radiusAt_mm(s + 1), stats); },
        [&](const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
            LabelMedium::Tracker& medium, Rng& rng, PathStats& tileStats) {
            return Li(map, ray, entry, pass.channel, medium, rng, tileStats);
        });
}

}  // namespace pl
