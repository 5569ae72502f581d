#include "integrators/photons/combined.h"

#include "core/sampling.h"
#include "integrators/photons/clear_region.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/photon_iterations.h"
#include "integrators/photons/pp3d.h"
#include "integrators/photons/two_radii.h"
#include "integrators/render_settings.h"
#include "integrators/volume_walk.h"

namespace pl {

const std::vector<OptionParameter<CombinedOptions>>& combinedParameters() {
    using O = CombinedOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"combined_photons_per_pixel", &O::photonsPerPixel, 0, 1e6, true, "must be in (0, 1e6]",
         "combined: photons traced per iteration (sample) for each sensor pixel"},
        {"combined_radius_voxels", &O::radius_voxels, 0, 100, true, "must be in (0, 100] (voxel sides)",
         "combined: the first iteration's kernel radius (ball and disc), in the smallest voxel side"},
        {"combined_alpha", &O::alpha, 0, 1, true, "must be in (0, 1]",
         "combined: r_{i+1}^3 = r_i^3 (i + alpha) / (i + 1); 1 keeps the radius"},
        {"combined_beams", &O::beams, 0, 0, false, "",
         "combined: also bre's queries along the camera's flights (short beams) as a third technique"},
    };
    return parameters;
}

Combined::Combined(const Scene& scene, const Sensor& sensor, CombinedOptions options, Majorants majorants,
                   uint64_t seed)
    : scene_(scene),
      photons_(scene, majorants, options.photonsPerPixel, sensor.pixelCount(), seed, 0x636f6d62ULL, kPhotonBytes,
               "combined", "photons", "lower combined_photons_per_pixel"),
      radius_(options.radius_voxels, scene.medium->frame().voxelSize_mm, options.alpha, 3),
      beams_(options.beams) {}

IntegratorCapabilities Combined::capabilities(const RenderSettings&) { return photonCapabilities(); }

std::unique_ptr<Integrator> Combined::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    return std::make_unique<Combined>(scene, sensor, readOptions(combinedParameters(), s.parameters), s.majorants,
                                      s.seed);
}

Combined::MergeRatios Combined::mergeRatios(float radius_mm) const {
    const double r_mm = radius_mm;
    const double densityTimesN2 = double(scene_.ior) * scene_.ior * double(photons_.count()) / photons_.area_mm2();
    // n^2 N / (pi A) times the ball's volume, and times the disc's area
    // (no beams: none).
    return {densityTimesN2 * 4.0 / 3.0 * r_mm * r_mm * r_mm, beams_ ? densityTimesN2 * r_mm * r_mm : 0.0};
}

ChannelSample Combined::Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                           int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float r2 = map.radius_mm() * map.radius_mm();
    const float reach_mm = clearReach_mm(scene_, map.radius_mm());
    const MergeRatios ratios = mergeRatios(map.radius_mm());
    // (q_point + q_beam) x f at a merging vertex in resin `label`.
    auto qSumTimesPhase = [&](Label label) {
        return ratios.ballPerExtinction_mm * lut.sigmaT_perMm[label] + ratios.discTimesPhase;
    };
    // Before the first clear collision; there (the next flight's phase not
    // yet known); the walk's light weighted; the roulette drawn.
    enum class Stage { Walking, Merged, Weighted, Rouletted } stage = Stage::Walking;
    Vec3f mergeDIn;
    Label mergeLabel = 0;
    double walkWeight = 1.0;  // of the light the walk brings out
    TwoRadii gathered;

    // The photons within r of a flight before the first clear collision, up
    // to where the flight ends (a short beam), where the flight's point c
    // nearest them is clear. As in the ball, a photon brings its share of
    // the fluence (power / sigma_s where it was stored) and c's resin
    // scatters it: everything but the fluence, weights included, is the
    // camera's point's, as in every technique.
    auto gatherAlong = [&](const Ray& flight, float tEnd_mm) {
        TwoRadii sum;
        ClearAlong clear(scene_, flight, reach_mm, map.radius_mm());
        map.forEachNear(flight, tEnd_mm, [&](const PhotonMap::Photon& ph) {
            const Vec3f v = ph.p - flight.o;
            const float t = dot(v, flight.d);
            if (t < 0.0f || t > tEnd_mm) return;
            const float d2 = dot(v, v) - t * t;
            if (!(d2 < r2) || !clear.at(t)) return;
            const double sigmaS_perMm = double(lut.sigmaT_perMm[ph.label]) * lut.albedo[ph.label];
            if (!(sigmaS_perMm > 0.0)) return;
            const Label c = medium.labelAt(scene_.medium->voxelAt(flight.at(t)));
            const double f = hgPhase(dot(ph.dIn, -flight.d), lut.g[c]);
            const double weight = ratios.discTimesPhase / (f + qSumTimesPhase(c));
            const double scattered = double(lut.sigmaT_perMm[c]) * lut.albedo[c] * f;
            sum += discBiweight(d2, r2) * (weight * scattered * double(ph.power) / sigmaS_perMm);
        });
        return sum;
    };
    // The photons within r of x, the first clear collision.
    auto gatherAround = [&](const Point3f& x, const Vec3f& dIn) {
        const double pointTimesPhase = ratios.ballPerExtinction_mm * lut.sigmaT_perMm[mergeLabel];
        const double qSum = qSumTimesPhase(mergeLabel);
        return gatherBall(map, lut, x, dIn, lut.g[mergeLabel],
                          [&](double f) { return pointTimesPhase / (f + qSum) * f; });
    };

    auto onFlight = [&](const Ray& flight, float tEnd_mm, const SingleChannelPath& path) {
        if (stage == Stage::Walking) {
            if (beams_) gathered += gatherAlong(flight, tEnd_mm) * double(path.beta);
        } else if (stage == Stage::Merged) {
            const double f = hgPhase(dot(mergeDIn, flight.d), lut.g[mergeLabel]);
            walkWeight = f / (f + qSumTimesPhase(mergeLabel));
            stage = Stage::Weighted;
        }
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
        mergeLabel = label;
        gathered += gatherAround(x, dIn) * double(path.beta);
        return false;
    };
    SingleChannelPath path{&lut, channel, scene_.environment[channel]};
    const float escaped = walkVolume(scene_, VolPathOptions{}, /*reentry=*/false, ray, path, medium, rng, stats,
                                     onFlight, onCollision, &entry);
    // A walk that left after the merge without a flight (a numerical leak)
    // leaves its light to the merge.
    if (stage == Stage::Merged) walkWeight = 0.0;
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
