#include "integrators/photons/combined.h"

#include <cmath>
#include <vector>

#include "core/sampling.h"
#include "integrators/photons/photon_estimator.h"
#include "integrators/photons/photon_iterations.h"
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

namespace {
// isClear at points of one flight, mostly from a few distances to the
// boundary along it: a point within step / 2 of a sampled point p is clear
// where p's distance is at least reach + step / 2, and not where it is
// below reach - step / 2 (distances change no faster than the position);
// otherwise it is asked. The same answers as isClear, fewer queries.
class ClearAlong {
public:
    ClearAlong(const Scene& scene, const Ray& flight, float reach_mm, float step_mm)
        : scene_(scene), flight_(flight), reach_mm_(reach_mm), step_mm_(step_mm) {}

    bool at(float t_mm) {
        const Point3f x = flight_.at(t_mm);
        if (scene_.clearance && scene_.clearance->at(x) >= reach_mm_) return true;
        const size_t j = size_t(std::lround(t_mm / step_mm_));
        if (j >= distances_mm_.size()) distances_mm_.resize(j + 1, -1.0f);
        if (distances_mm_[j] < 0.0f) {
            // Looked for up to reach + step: beyond, all that matters is that it is far.
            const float far_mm = reach_mm_ + step_mm_;
            const auto nearest = scene_.geometry->closestPoint(flight_.at(float(j) * step_mm_), far_mm);
            distances_mm_[j] = nearest ? nearest->distance_mm : far_mm;
        }
        const float d = distances_mm_[j], half = 0.5f * step_mm_;
        if (d >= reach_mm_ + half) return true;
        if (d < reach_mm_ - half) return false;
        return isClear(scene_, x, reach_mm_);
    }

private:
    const Scene& scene_;
    const Ray& flight_;
    float reach_mm_, step_mm_;
    std::vector<float> distances_mm_;  // at j x step along the flight; < 0: not yet asked
};
}  // namespace

ChannelSample Combined::Li(const PhotonMap& map, const Ray& ray, const std::optional<SurfaceHit>& entry,
                           int channel, LabelMedium::Tracker& medium, Rng& rng, PathStats& stats) const {
    const ChannelLut& lut = scene_.medium->lut(channel);
    const float r2 = map.radius_mm() * map.radius_mm();
    const float reach_mm = clearReach_mm(map.radius_mm());
    const MergeRatios ratios = mergeRatios(map.radius_mm());
    // (q_point + q_beam) x f at a merging vertex of extinction sigmaT.
    auto mergesTimesPhase = [&](float sigmaT_perMm) { return ratios.point_mm * sigmaT_perMm + ratios.beam; };
    // Before the first clear collision; there (the next flight's phase not
    // yet known); the walk's light weighted; the roulette drawn.
    enum class Stage { Walking, Merged, Weighted, Rouletted } stage = Stage::Walking;
    Vec3f mergeDIn;
    float mergeG = 0.0f;
    double mergeQTimesPhase = 0.0;
    double walkWeight = 1.0;  // of the light the walk brings out
    TwoRadii gathered;

    // The photons within r of a flight before the first clear collision,
    // up to where the flight ends (a short beam), where the flight's point
    // nearest them is clear (the camera's point decides, as the walk's
    // collision does: a photon's own would count light twice where a
    // flight passes outside the clear region within r of it).
    auto gatherAlong = [&](const Ray& flight, float tEnd_mm) {
        TwoRadii sum;
        ClearAlong clearAlong(scene_, flight, reach_mm, map.radius_mm());
        map.forEachNear(flight, tEnd_mm, [&](const PhotonMap::Photon& ph) {
            const Vec3f v = ph.p - flight.o;
            const float t = dot(v, flight.d);
            if (t < 0.0f || t > tEnd_mm) return;
            const float d2 = dot(v, v) - t * t;
            if (!(d2 < r2) || !clearAlong.at(t)) return;
            const double f = hgPhase(dot(ph.dIn, -flight.d), lut.g[ph.label]);
            const double weightedPhase = f * ratios.beam / (f + mergesTimesPhase(lut.sigmaT_perMm[ph.label]));
            sum += discBiweight(d2, r2) * (weightedPhase * double(ph.power));
        });
        return sum;
    };
    // The photons within r of x, the first clear collision.
    auto gatherAround = [&](const Point3f& x, const Vec3f& dIn, Label label) {
        TwoRadii sum;
        const double pointTimesPhase = ratios.point_mm * lut.sigmaT_perMm[label];
        map.forEachNearPoint(x, [&](const PhotonMap::Photon& ph) {
            const Vec3f v = ph.p - x;
            const float d2 = dot(v, v);
            const double sigmaS_perMm = double(lut.sigmaT_perMm[ph.label]) * lut.albedo[ph.label];
            if (!(d2 < r2) || !(sigmaS_perMm > 0.0)) return;
            const double f = hgPhase(dot(ph.dIn, -dIn), mergeG);
            const double weightedPhase = f * pointTimesPhase / (f + mergeQTimesPhase);
            sum += ballBiweight(d2, r2) * (weightedPhase * double(ph.power) / sigmaS_perMm);
        });
        return sum;
    };

    auto onFlight = [&](const Ray& flight, float tEnd_mm, const SingleChannelPath& path) {
        if (stage == Stage::Walking) {
            if (beams_) gathered += gatherAlong(flight, tEnd_mm) * double(path.beta);
        } else if (stage == Stage::Merged) {
            const double f = hgPhase(dot(mergeDIn, flight.d), mergeG);
            walkWeight = f / (f + mergeQTimesPhase);
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
        mergeG = lut.g[label];
        mergeQTimesPhase = mergesTimesPhase(lut.sigmaT_perMm[label]);
        gathered += gatherAround(x, dIn, label) * double(path.beta);
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
