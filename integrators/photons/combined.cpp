#include "integrators/photons/combined.h"

#include "core/sampling.h"
#include "integrators/photons/clear_gather.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/photon_iterations.h"
#include "integrators/render_settings.h"

namespace pl {

Combined::Combined(const Scene& scene, const Sensor& sensor, Pp3dOptions options, Majorants majorants,
                   uint64_t seed)
    : scene_(scene),
      photons_(scene, majorants, options.photonsPerPixel, sensor.pixelCount(), seed, 0x636f6d62ULL, kPhotonBytes,
               "combined", "photons", "lower pp3d_photons_per_pixel"),
      radius_(options.radius_voxels, scene.medium->frame().voxelSize_mm, options.alpha, 3) {}

IntegratorCapabilities Combined::capabilities(const RenderSettings&) { return photonCapabilities(); }

std::unique_ptr<Integrator> Combined::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Combined>(scene, sensor, readOptions(pp3dParameters(), s.parameters), s.majorants,
                                      s.seed);
}

double Combined::mergeRatioFactor(float radius_mm) const {
    const double r_mm = radius_mm;
    const double ballVolume_mm3 = 4.0 / 3.0 * kPi * r_mm * r_mm * r_mm;
    const double n2 = double(scene_.ior) * scene_.ior;
    return n2 * double(photons_.count()) * ballVolume_mm3 / (kPi * photons_.area_mm2());
}

ChannelSample Combined::Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                           int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float r2 = map.radius_mm() * map.radius_mm();
    const float reach_mm = map.radius_mm() + scene_.geometry->surfaceLift_mm();
    const double mergeRatio = mergeRatioFactor(map.radius_mm());
    // Before the merge; merged (the next flight's phase not yet known);
    // the walk's light weighted; the roulette drawn.
    enum class Stage { Walking, Merged, Weighted, Rouletted } stage = Stage::Walking;
    Vec3f mergeDIn;
    float mergeG = 0.0f;
    double qTimesF = 0.0;     // q x f_k: the same for every direction at x_k
    double walkWeight = 1.0;  // of the light the walk brings out
    TwoRadii gathered;

    auto onFlight = [&](const Ray& flight, float, const SingleChannelPath&) {
        if (stage != Stage::Merged) return;
        const double f = hgPhase(dot(mergeDIn, flight.d), mergeG);
        walkWeight = f / (f + qTimesF);
        stage = Stage::Weighted;
    };
    auto onCollision = [&](const Point3f& x, const Vec3f& dIn, Label label, const SingleChannelPath& path) {
        if (stage == Stage::Weighted) {
            // Go on with probability walkWeight, then weighted by its inverse.
            stage = Stage::Rouletted;
            if (!(rng.uniform() < walkWeight)) return true;
            walkWeight = 1.0;
            return false;
        }
        if (stage != Stage::Walking || !isClear(scene_, x, reach_mm)) return false;
        stage = Stage::Merged;
        mergeDIn = dIn;
        mergeG = lut.g[label];
        qTimesF = mergeRatio * lut.sigmaT_perMm[label];
        TwoRadii sum;
        map.forEachNearPoint(x, [&](const PhotonMap::Photon& ph) {
            const Vec3f v = ph.p - x;
            const float d2 = dot(v, v);
            const double sigmaS_perMm = double(lut.sigmaT_perMm[ph.label]) * lut.albedo[ph.label];
            if (!(d2 < r2) || !(sigmaS_perMm > 0.0)) return;
            const double f = hgPhase(dot(ph.dIn, -dIn), mergeG);
            const double weightedPhase = f * qTimesF / (f + qTimesF);  // f x q / (1 + q)
            sum += ballBiweight(d2, r2) * (weightedPhase * double(ph.power) / sigmaS_perMm);
        });
        gathered += sum * double(path.beta);
        return false;
    };
    SingleChannelPath path{&lut, channel, scene_.environment[channel]};
    const float escaped = walkVolume(scene_, VolPathOptions{}, /*reentry=*/false, ray, path, medium, rng, stats,
                                     onFlight, onCollision, &entry);
    return kernelSample(double(escaped) * walkWeight, gathered * insideToOutside(scene_));
}

void Combined::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    renderPhotonIterations(
        pass, film, stats, progress, "combined",
        [&](uint32_t s) { return tracePhotonPoints(photons_, pass.channel, s, radiusAt_mm(s + 1), stats); },
        [&](const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
            LabelMedium::Tracker& medium, Rng& rng, PathStats& tileStats) {
            return Li(map, ray, entry, pass.channel, medium, rng, tileStats);
        });
}

}  // namespace pl
