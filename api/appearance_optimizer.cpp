#include "api/appearance_optimizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include "compare/color_difference.h"
#include "compare/surface_colour_error.h"
#include "prepare/halftone.h"

namespace pl {

namespace {

// Dense index of the frame's voxels, x fastest.
struct DenseIndex {
    Vec3i res;
    size_t operator()(const Vec3i& v) const { return (size_t(v.z) * res.y + v.y) * res.x + v.x; }
    bool contains(const Vec3i& v) const {
        return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < res.x && v.y < res.y && v.z < res.z;
    }
};

// Each object voxel within depth_mm of a surface voxel gets the index of
// its nearest surface voxel (multi-source breadth-first search over face
// neighbours through the object), -1 elsewhere.
std::vector<int32_t> shellOwners(const std::vector<Label>& labels, Label voidLabel, const GridFrame& frame,
                                 const std::vector<Vec3i>& surface, float depth_mm) {
    DenseIndex at{frame.resolution};
    std::vector<int32_t> owner(labels.size(), -1);
    std::deque<Vec3i> queue;
    for (size_t s = 0; s < surface.size(); ++s) {
        Vec3i v = surface[s] - frame.indexMin;
        owner[at(v)] = int32_t(s);
        queue.push_back(v);
    }
    const Vec3f& h = frame.voxelSize_mm;
    while (!queue.empty()) {
        Vec3i v = queue.front();
        queue.pop_front();
        const int32_t o = owner[at(v)];
        const Vec3i src = surface[size_t(o)] - frame.indexMin;
        for (const Vec3i& d : kFaceDirections) {
            Vec3i n = v + d;
            if (!at.contains(n) || owner[at(n)] >= 0 || labels[at(n)] == voidLabel) continue;
            Vec3f off{(n.x - src.x) * h.x, (n.y - src.y) * h.y, (n.z - src.z) * h.z};
            if (length(off) > depth_mm) continue;
            owner[at(n)] = o;
            queue.push_back(n);
        }
    }
    return owner;
}

// Halftones the shell: the mixture each voxel's owner asks for, vector
// error diffusion slice by slice; returns the changes against `labels`.
std::vector<LabelGrid::Change> halftoneShell(const std::vector<Label>& labels, const GridFrame& frame,
                                             const std::vector<int32_t>& owner,
                                             const std::vector<MaterialFractions>& mixtures) {
    const Vec3i& r = frame.resolution;
    std::vector<LabelGrid::Change> changes;
    halftoneFrame(
        r,
        [&](size_t i, MaterialFractions& f) {
            if (owner[i] < 0) return false;
            f = mixtures[size_t(owner[i])];
            return true;
        },
        [&](size_t i, int material) {
            const Label l = kPrintMaterialLabel[material];
            if (l != labels[i])
                changes.push_back({{frame.indexMin.x + int(i % r.x), frame.indexMin.y + int((i / r.x) % r.y),
                                    frame.indexMin.z + int(i / (size_t(r.x) * r.y))},
                                   l});
        });
    return changes;
}

// Every shell voxel set to one label (calibration of the gamut).
std::vector<LabelGrid::Change> fillShell(const std::vector<Label>& labels, const GridFrame& frame,
                                         const std::vector<int32_t>& owner, Label label) {
    const Vec3i& r = frame.resolution;
    std::vector<LabelGrid::Change> changes;
    for (size_t i = 0; i < owner.size(); ++i)
        if (owner[i] >= 0 && labels[i] != label)
            changes.push_back({{frame.indexMin.x + int(i % r.x), frame.indexMin.y + int((i / r.x) % r.y),
                                frame.indexMin.z + int(i / (size_t(r.x) * r.y))}, label});
    return changes;
}

// Radiance (or its standard error) as reflectance: over the surroundings' radiance.
std::vector<RGB> reflectance(const std::vector<RGB>& radiance, const RGB& environment) {
    std::vector<RGB> out(radiance.size());
    for (size_t i = 0; i < out.size(); ++i)
        for (int c = 0; c < 3; ++c) out[i][c] = environment[c] > 0 ? radiance[i][c] / environment[c] : 0.0f;
    return out;
}

RGB meanOf(const std::vector<RGB>& v) {
    double s[3] = {0, 0, 0};
    for (const RGB& x : v)
        for (int c = 0; c < 3; ++c) s[c] += x[c];
    RGB m;
    for (int c = 0; c < 3; ++c) m[c] = float(s[c] / double(std::max<size_t>(v.size(), 1)));
    return m;
}

// Mean of `values` over the surface voxels within radius voxels of each
// (Chebyshev), i.e. the colour seen at the scale of a few voxels.
std::vector<RGB> smoothOverSurface(const std::vector<RGB>& values, const std::vector<Vec3i>& voxels,
                                   const std::vector<int32_t>& surfaceAt, const DenseIndex& at,
                                   const Vec3i& indexMin, int radius) {
    if (radius <= 0) return values;
    std::vector<RGB> out(values.size());
    for (size_t s = 0; s < values.size(); ++s) {
        double sum[3] = {0, 0, 0};
        int n = 0;
        Vec3i v = voxels[s] - indexMin;
        for (int dz = -radius; dz <= radius; ++dz)
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx) {
                    Vec3i q{v.x + dx, v.y + dy, v.z + dz};
                    if (!at.contains(q) || surfaceAt[at(q)] < 0) continue;
                    const RGB& x = values[size_t(surfaceAt[at(q)])];
                    for (int c = 0; c < 3; ++c) sum[c] += x[c];
                    ++n;
                }
        for (int c = 0; c < 3; ++c) out[s][c] = float(sum[c] / n);
    }
    return out;
}

// Mean and 95th percentile of CIEDE2000 between two colour lists.
void scoreInto(const std::vector<RGB>& predicted, const std::vector<RGB>& target, double& mean, double& p95) {
    const DeltaEStats stats = deltaEStats(predicted, target);
    mean = stats.mean;
    p95 = stats.p95;
}

}  // namespace

OptimizeResult optimizeAppearance(Predictor& predictor, const std::vector<RGB>& targets,
                                  const OptimizeSettings& settings,
                                  const std::function<void(const OptimizeIteration&)>& onIteration) {
    using Clock = std::chrono::steady_clock;
    const GridFrame frame = predictor.labels().frame();
    const Label voidLabel = predictor.labels().voidLabel();
    const RGB environment = predictor.environment();
    std::vector<Label> labels = predictor.labels().toDense();
    const uint64_t baseSeed = predictor.settings().seed;
    OptimizeResult result;

    // The predictor's settings come back as they were, whatever happens.
    struct RestoreSettings {
        Predictor& predictor;
        RenderSettings saved;
        ~RestoreSettings() { predictor.settings() = saved; }
    } restore{predictor, predictor.settings()};
    // The Monte Carlo integrator of the settings, and the fast one if any
    // (with iterations to use it on).
    const std::string monteCarlo = predictor.settings().integrator;
    const bool fastFirst =
        !settings.fastPredictor.empty() && settings.fastPredictor != monteCarlo && settings.iterations > 0;
    if (fastFirst) predictor.settings().integrator = settings.fastPredictor;
    auto t0 = Clock::now();
    SurfacePrediction p = predictor.predict();
    if (targets.size() != p.voxels.size())
        throw std::invalid_argument("optimizeAppearance: one target per surface voxel is needed");
    std::vector<int32_t> owner = shellOwners(labels, voidLabel, frame, p.voxels, settings.shellDepth_mm);
    // The targets mapped into the gamut that integrator predicts.
    auto mapIntoGamut = [&](const std::string& integrator, RGB& black, RGB& white) {
        std::vector<RGB> mapped = targets;
        if (!settings.gamutMap) return mapped;
        const std::string current = predictor.settings().integrator;
        predictor.settings().integrator = integrator;
        // Calibration: the shell all black, then all white; then the labels as given again.
        // One sample per voxel: the mean over all surface voxels is precise.
        auto meanWith = [&](Label l) {
            auto changes = fillShell(labels, frame, owner, l);
            predictor.changeLabels(changes);
            const uint32_t spp = predictor.settings().spp;
            predictor.settings().spp = 1;
            RGB m = meanOf(reflectance(predictor.predict().radiance, environment));
            predictor.settings().spp = spp;
            for (auto& c : changes) c.label = labels[DenseIndex{frame.resolution}(c.voxel - frame.indexMin)];
            predictor.changeLabels(changes);
            return m;
        };
        black = meanWith(kBlackLabel);
        white = meanWith(kWhiteLabel);
        predictor.settings().integrator = current;
        for (RGB& t : mapped)
            for (int c = 0; c < 3; ++c) t[c] = black[c] + std::clamp(t[c], 0.0f, 1.0f) * (white[c] - black[c]);
        return mapped;
    };
    const std::vector<RGB> mapped = mapIntoGamut(monteCarlo, result.gamutBlack, result.gamutWhite);
    const std::vector<Point3f> points_mm = predictor.surfacePoints_mm();
    std::optional<SurfaceGaussian> updateFilter;
    if (settings.updateFootprint_mm > 0) updateFilter.emplace(points_mm, settings.updateFootprint_mm);
    // Surface voxels by position, for smoothing.
    DenseIndex at{frame.resolution};
    std::vector<int32_t> surfaceAt(labels.size(), -1);
    for (size_t s = 0; s < p.voxels.size(); ++s) surfaceAt[at(p.voxels[s] - frame.indexMin)] = int32_t(s);
    auto smooth = [&](const std::vector<RGB>& v, int radius) {
        return smoothOverSurface(v, p.voxels, surfaceAt, at, frame.indexMin, radius);
    };
    const std::vector<RGB> scoredTarget = smooth(mapped, settings.scoreRadius);

    std::vector<RGB> requested = targets;
    double previousScore = 0;
    for (int iteration = 0;; ++iteration) {
        std::vector<RGB> predicted = reflectance(p.radiance, environment);
        OptimizeIteration it;
        it.iteration = iteration;
        it.predictor = predictor.settings().integrator;
        scoreInto(smooth(predicted, settings.scoreRadius), scoredTarget, it.meanDeltaE, it.p95DeltaE);
        scoreInto(predicted, mapped, it.meanDeltaEPerVoxel, it.p95DeltaEPerVoxel);
        // Past the fast predictor's use: its score has stopped falling (or
        // the last prediction is next: it is Monte Carlo's).
        const bool switchNow = fastFirst && predictor.settings().integrator == settings.fastPredictor &&
                               ((iteration > 0 && previousScore - it.meanDeltaE < settings.switchBelowDeltaE) ||
                                iteration + 1 == settings.iterations);
        previousScore = it.meanDeltaE;
        if (iteration == settings.iterations) {
            result.finalPredicted = smooth(predicted, settings.scoreRadius);
            result.finalTarget = scoredTarget;
            result.finalDeltaE.resize(predicted.size());
            for (size_t i = 0; i < predicted.size(); ++i)
                result.finalDeltaE[i] = float(ciede2000(labFromLinearSrgb(result.finalPredicted[i]),
                                                        labFromLinearSrgb(result.finalTarget[i])));
            it.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
            result.iterations.push_back(it);
            if (onIteration) onIteration(it);
            break;
        }
        // Error, averaged over the surface neighbourhood; move the requests.
        std::vector<RGB> error(predicted.size());
        for (size_t i = 0; i < error.size(); ++i)
            for (int c = 0; c < 3; ++c) error[i][c] = mapped[i][c] - predicted[i][c];
        error = updateFilter ? updateFilter->apply(error) : smooth(error, settings.smoothRadius);
        for (size_t s = 0; s < requested.size(); ++s)
            for (int c = 0; c < 3; ++c)
                requested[s][c] = std::clamp(requested[s][c] + settings.step * error[s][c], 0.0f, 1.0f);
        std::vector<MaterialFractions> mixtures(requested.size());
        for (size_t s = 0; s < requested.size(); ++s) mixtures[s] = fractionsForColor(requested[s]);
        std::vector<LabelGrid::Change> changes = halftoneShell(labels, frame, owner, mixtures);
        for (const auto& c : changes) labels[at(c.voxel - frame.indexMin)] = c.label;
        predictor.changeLabels(changes);
        it.changedVoxels = changes.size();
        it.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        result.iterations.push_back(it);
        if (onIteration) onIteration(it);
        t0 = Clock::now();
        // A new seed each iteration: the loop must not fit one noise realisation.
        predictor.settings().seed = baseSeed + uint64_t(iteration) + 1;
        if (switchNow) predictor.settings().integrator = monteCarlo;
        p = predictor.predict();
    }
    if (settings.judgeSpp > 0) {
        // The judge: what gets printed, rendered apart from the loop.
        const std::string judge = settings.judgeIntegrator.empty() ? monteCarlo : settings.judgeIntegrator;
        predictor.settings().integrator = judge;
        predictor.settings().spp = settings.judgeSpp;
        predictor.settings().seed = settings.judgeSeed;
        const auto j0 = Clock::now();
        const SurfacePrediction judged = predictor.predict();
        // Against the targets mapped by the judge's own calibration: the
        // same whatever predicted.
        RGB black, white;
        const std::vector<RGB> judgeTargets = mapIntoGamut(judge, black, white);
        const std::vector<RGB> judgedColours = reflectance(judged.radiance, environment);
        const SurfaceColourError e = surfaceColourError(points_mm, judgedColours, judgeTargets);
        // What the judge's own noise adds to its score.
        const SurfaceColourError noise =
            noiseColourError(points_mm, judgedColours, reflectance(judged.standardError, environment));
        result.judgement = OptimizeJudgement{judge, settings.judgeSpp, settings.judgeSeed, e.mean,
                                             e.p95, e.meanFiltered, e.p95Filtered, noise.mean, noise.meanFiltered,
                                             judged.voxelsShareSamples,
                                             std::chrono::duration<double>(Clock::now() - j0).count()};
    }
    return result;
}

}  // namespace pl
