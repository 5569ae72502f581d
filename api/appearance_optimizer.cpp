#include "api/appearance_optimizer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <numeric>
#include <optional>
#include <tuple>

#include <tbb/parallel_for.h>

#include "api/printers_reach.h"
#include "compare/colour_difference.h"
#include "compare/footprint_sample.h"
#include "compare/surface_colour_error.h"
#include "media/label_grid.h"
#include "media/voxel_int_grid.h"
#include "prepare/halftone.h"
#include "prepare/rendering_intent.h"
#include "prepare/threshold_matrix.h"
#include "render/registry.h"

namespace pl {

namespace {

// Dense index of the frame's voxels, x fastest.
struct DenseIndex {
    Vec3i res;
    size_t operator()(const Vec3i& v) const { return (size_t(v.z) * res.y + v.y) * res.x + v.x; }
    Vec3i voxel(size_t i) const { return {int(i % res.x), int((i / res.x) % res.y), int(i / (size_t(res.x) * res.y))}; }
    bool contains(const Vec3i& v) const {
        return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < res.x && v.y < res.y && v.z < res.z;
    }
};

// Each object voxel within depth_mm of a surface voxel gets the index of
// its nearest surface voxel (multi-source breadth-first search over face
// neighbours through the object); the rest are not set (-1). Sparse: the
// shell, not the grid.
VoxelIntGrid shellOwners(const LabelGrid& labels, const std::vector<Vec3i>& surface, float depth_mm) {
    const GridFrame& frame = labels.frame();
    const LabelReader label(labels);
    VoxelIntGrid owner(-1);
    std::deque<Vec3i> queue;
    for (size_t s = 0; s < surface.size(); ++s) {
        owner.set(surface[s], int32_t(s));
        queue.push_back(surface[s]);
    }
    const Vec3f& h = frame.voxelSize_mm;
    while (!queue.empty()) {
        const Vec3i v = queue.front();
        queue.pop_front();
        const int32_t o = owner.get(v);
        const Vec3i& src = surface[size_t(o)];
        for (const Vec3i& d : kFaceDirections) {
            const Vec3i n = v + d;
            if (!frame.contains(n) || owner.get(n) >= 0 || label.at(n) == labels.voidLabel()) continue;
            Vec3f off{(n.x - src.x) * h.x, (n.y - src.y) * h.y, (n.z - src.z) * h.z};
            if (length(off) > depth_mm) continue;
            owner.set(n, o);
            queue.push_back(n);
        }
    }
    return owner;
}

// Halftones the shell: the mixture each voxel's owner asks for; returns
// the changes against `labels`. Error diffusion walks the frame slice by
// slice; by thresholds each shell voxel is decided alone.
std::vector<LabelGrid::Change> halftoneShell(const LabelGrid& labels, const VoxelIntGrid& owner,
                                             const std::vector<MaterialFractions>& mixtures, HalftoneMethod method,
                                             float hysteresis) {
    const GridFrame& frame = labels.frame();
    const DenseIndex at{frame.resolution};
    const LabelReader label(labels);
    std::vector<LabelGrid::Change> changes;
    if (method != HalftoneMethod::ErrorDiffusion) {
        const ThresholdMatrix* thresholds =
            method == HalftoneMethod::Thresholds ? &ThresholdMatrix::forVoxel(frame.voxelSize_mm) : nullptr;
        owner.forEachSet([&](const Vec3i& v, int32_t o) {
            const MaterialFractions& f = mixtures[size_t(o)];
            const Label now = label.at(v);
            const int m = materialOfVoxel(f, thresholds, v, printMaterialOf(now), hysteresis);
            if (kPrintMaterialLabel[m] != now) changes.push_back({v, kPrintMaterialLabel[m]});
        });
        return changes;
    }
    halftoneFrame(
        frame.resolution,
        [&](size_t i, MaterialFractions& f) {
            const int32_t o = owner.get(frame.indexMin + at.voxel(i));
            if (o < 0) return false;
            f = mixtures[size_t(o)];
            return true;
        },
        [&](size_t i, int material) {
            const Label l = kPrintMaterialLabel[material];
            const Vec3i v = frame.indexMin + at.voxel(i);
            if (l != label.at(v)) changes.push_back({v, l});
        });
    return changes;
}

std::vector<Lab> labsOf(const std::vector<RGB>& colours) {
    std::vector<Lab> out(colours.size());
    tbb::parallel_for(size_t(0), colours.size(), [&](size_t i) { out[i] = labFromLinearSrgb(colours[i]); });
    return out;
}

using LabVector = std::array<double, 3>;
LabVector difference(const Lab& x, const Lab& y) { return {x.L - y.L, x.a - y.a, x.b - y.b}; }
double dot(const LabVector& x, const LabVector& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

// The gamut's match for every colour (first compressed by the perceptual
// intent, if given), each distinct colour searched once (a uniform target
// is one search).
std::vector<PrinterGamut::Match> matchesOf(const PrinterGamut& gamut, const std::vector<RGB>& colours,
                                           const PerceptualIntent* perceptual) {
    std::vector<uint32_t> order(colours.size());
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](uint32_t i) { return std::make_tuple(colours[i][0], colours[i][1], colours[i][2]); };
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    std::vector<uint32_t> distinct;
    for (size_t k = 0; k < order.size(); ++k)
        if (k == 0 || key(order[k]) != key(order[k - 1])) distinct.push_back(order[k]);
    std::vector<PrinterGamut::Match> found(distinct.size());
    tbb::parallel_for(size_t(0), distinct.size(), [&](size_t d) {
        const Lab colour = labFromLinearSrgb(colours[distinct[d]]);
        found[d] = gamut.closest(perceptual ? (*perceptual)(colour) : colour);
    });
    std::vector<PrinterGamut::Match> out(colours.size());
    for (size_t k = 0, d = 0; k < order.size(); ++k) {
        if (k > 0 && key(order[k]) != key(order[k - 1])) ++d;
        out[order[k]] = found[d];
    }
    return out;
}

// The sampled footprints' scores into j: per footprint the halves' mean
// against the mapped target (and its centre voxel's own), its noise and
// the squared error without it; their means over the footprints estimate
// the whole surface's, with 95 % intervals.
void judgeSampledFootprints(const FootprintSample& sample, const std::array<std::vector<RGB>, 2>& halves,
                            const std::vector<RGB>& mapped, const std::vector<RGB>& mappedSampled,
                            const std::vector<RGB>& flatSampled, OptimizeJudgement& j) {
    const std::vector<RGB> a = sample.apply(halves[0]), b = sample.apply(halves[1]);
    const size_t m = sample.size();
    std::vector<double> error(m), noise(m), square(m), flatError(m);
    std::vector<float> centreError(m), centreNoise(m);
    for (size_t k = 0; k < m; ++k) {
        const FootprintError e = footprintError(a[k], b[k], mappedSampled[k]);
        error[k] = e.deltaE;
        noise[k] = e.noiseDeltaE;
        square[k] = e.squareNoiseRemoved;
        flatError[k] = footprintError(a[k], b[k], flatSampled[k]).deltaE;
        const uint32_t c = sample.centres()[k];
        const FootprintError own = footprintError(halves[0][c], halves[1][c], mapped[c]);
        centreError[k] = float(own.deltaE);
        centreNoise[k] = float(own.noiseDeltaE);
    }
    const SampledMean filtered = stratifiedMean(error), squares = stratifiedMean(square);
    const DeltaEStats perVoxel = meanAndP95(centreError);
    j.meanDeltaEFiltered = filtered.mean;
    j.meanDeltaEFilteredHalfWidth95 = filtered.halfWidth95;
    j.meanDeltaEFilteredFlatFace = stratifiedMean(flatError).mean;
    j.p95DeltaEFiltered = meanAndP95(std::vector<float>(error.begin(), error.end())).p95;
    j.meanDeltaE = perVoxel.mean;
    j.p95DeltaE = perVoxel.p95;
    j.noiseDeltaE = meanAndP95(centreNoise).mean;
    j.noiseDeltaEFiltered = stratifiedMean(noise).mean;
    j.rmsDeltaEFilteredNoiseRemoved = std::sqrt(std::max(0.0, squares.mean));
    j.rmsLow95 = std::sqrt(std::max(0.0, squares.mean - squares.halfWidth95));
    j.rmsHigh95 = std::sqrt(std::max(0.0, squares.mean + squares.halfWidth95));
}

// The judge: the printed labels rendered apart from the loop in two
// independent halves, in rounds (seeds judgeSeed + 0, 1, 2, ...) until the
// noise over the footprint is under the wanted level; each round asks for
// the samples that the noise's fall as the root of the samples says are
// missing, a fifth more. Every surface voxel, or (judgeFootprints) only
// the neighbourhoods of a stratified random sample of footprints, whose
// mean error estimates the whole surface's with a 95 % interval.
OptimizeJudgement judgePrint(Predictor& predictor, const OptimizeSettings& settings, const std::string& integrator,
                             const SurfaceGaussian& eye, const std::vector<RGB>& mapped,
                             const std::vector<RGB>& flatMapped, const RGB& environment) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool fixed = settings.judgeSpp > 0;
    const uint32_t mostPerHalf = std::max(1u, (fixed ? settings.judgeSpp : settings.judgeMostSpp) / 2);
    setIntegrator(predictor.settings(), integrator);
    predictor.carryOver().enabled = false;  // independent renders
    std::optional<FootprintSample> sample;
    std::vector<RGB> mappedSampled, flatSampled;
    if (settings.judgeFootprints > 0) {
        sample.emplace(predictor.surfacePoints_mm(), eye, kEyeFootprint_mm, settings.judgeFootprints,
                       settings.judgeSeed);
        mappedSampled = sample->apply(mapped);
        flatSampled = sample->apply(flatMapped);
    }
    std::array<std::vector<RGB>, 2> sum;  // radiance times samples, per half
    uint32_t perHalf = 0, next = fixed ? mostPerHalf : std::min(4u, mostPerHalf);
    OptimizeJudgement j;
    j.integrator = integrator;
    j.seed = settings.judgeSeed;
    j.footprints = sample ? sample->size() : 0;
    j.renderedVoxels = sample ? sample->points().size() : predictor.surfaceVoxelCount();
    for (;;) {
        for (int half = 0; half < 2; ++half) {
            predictor.settings().spp = next;
            predictor.settings().seed = settings.judgeSeed + uint64_t(2 * j.rounds + half);
            const SurfacePrediction p = sample ? predictor.predictVoxels(sample->points()) : predictor.predict();
            sum[half].resize(p.radiance.size(), RGB{0, 0, 0});
            for (size_t i = 0; i < p.radiance.size(); ++i)
                for (int c = 0; c < 3; ++c) sum[half][i][c] += float(next) * p.radiance[i][c];
        }
        perHalf += next;
        ++j.rounds;
        std::array<std::vector<RGB>, 2> halves;
        for (int half = 0; half < 2; ++half) {
            halves[half] = reflectance(sum[half], environment);
            for (RGB& x : halves[half])
                for (float& v : x) v /= float(perHalf);
        }
        const bool last = [&] {
            if (sample) {
                judgeSampledFootprints(*sample, halves, mapped, mappedSampled, flatSampled, j);
            } else {
                const SplitRenderError e = splitRenderError(eye, halves[0], halves[1], mapped);
                j.meanDeltaE = e.error.mean;
                j.p95DeltaE = e.error.p95;
                j.meanDeltaEFiltered = e.error.meanFiltered;
                j.p95DeltaEFiltered = e.error.p95Filtered;
                j.noiseDeltaE = e.noise.mean;
                j.noiseDeltaEFiltered = e.noise.meanFiltered;
                j.rmsDeltaEFilteredNoiseRemoved = e.rmsFilteredNoiseRemoved;
                j.judgedSeen = e.meanSeen;
                j.deltaESeen = e.deltaESeen;
                // A second whole-surface score only where the targets differ.
                j.meanDeltaEFilteredFlatFace =
                    flatMapped == mapped ? e.error.meanFiltered
                                         : splitRenderError(eye, halves[0], halves[1], flatMapped).error.meanFiltered;
            }
            return fixed || j.noiseDeltaEFiltered <= settings.judgeNoiseDeltaE || perHalf >= mostPerHalf;
        }();
        if (last) {
            j.spp = 2 * perHalf;
            j.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            return j;
        }
        const double wanted = std::ceil(1.2 * perHalf * std::pow(j.noiseDeltaEFiltered / settings.judgeNoiseDeltaE, 2));
        next = uint32_t(std::min<double>(wanted, mostPerHalf)) - perHalf;
        next = std::max(next, 1u);
    }
}

// The targets as the printer can show them: clamped to [0, 1], the
// nearest printable colour of each (mapped, unless the gamut map is off)
// and the mixture that shows it, which the loop prints first.
struct MappedTargets {
    std::vector<RGB> given, mapped;
    std::vector<MaterialFractions> mixture;
    std::vector<Lab> request;  // the colour each voxel's mixture is asked to show
};

MappedTargets mapTargets(const PrinterGamut& gamut, const std::vector<RGB>& targets, bool gamutMap,
                         RenderingIntent intent) {
    const size_t n = targets.size();
    MappedTargets t;
    t.given = targets;
    for (RGB& x : t.given)
        for (float& v : x) v = std::clamp(v, 0.0f, 1.0f);
    std::optional<PerceptualIntent> perceptual;
    if (gamutMap && intent == RenderingIntent::Perceptual) perceptual.emplace(gamut);
    const std::vector<PrinterGamut::Match> mapping = matchesOf(gamut, t.given, perceptual ? &*perceptual : nullptr);
    t.mapped.resize(n);
    t.mixture.resize(n);
    t.request.resize(n);
    for (size_t i = 0; i < n; ++i) {
        t.mapped[i] = gamutMap ? mapping[i].reflectance : t.given[i];
        t.mixture[i] = mapping[i].mixture;
        t.request[i] = mapping[i].colour;
    }
    return t;
}

// What the loop aims at, at the scales it looks at: over the eye's
// footprint (or the update's own), and over three footprints (the error's
// wide part, a tenth of the noise of the footprint's: what a whole face or
// region lacks).
struct LoopGoal {
    LoopGoal(const std::vector<Point3f>& points_mm, const OptimizeSettings& settings)
        : settings(settings), eye(points_mm, kEyeFootprint_mm), wide(points_mm, 3 * kEyeFootprint_mm, 0.25f) {
        if (settings.updateFootprint_mm > 0 && settings.updateFootprint_mm != kEyeFootprint_mm)
            ownUpdateFilter.emplace(points_mm, settings.updateFootprint_mm);
    }
    // Over the footprint the requests move by.
    std::vector<RGB> updateFiltered(const std::vector<RGB>& v) const {
        if (settings.updateFootprint_mm <= 0) return v;
        return ownUpdateFilter ? ownUpdateFilter->apply(v) : eye.apply(v);
    }
    void aimAt(const std::vector<RGB>& mapped) {
        mappedSeen = eye.apply(mapped);
        // The update's footprint is the eye's unless set otherwise: filtered once.
        const bool ownFootprint = settings.updateFootprint_mm <= 0 || ownUpdateFilter;
        goal = labsOf(ownFootprint ? updateFiltered(mapped) : mappedSeen);
        goalWide = labsOf(wide.apply(mapped));
    }
    const OptimizeSettings& settings;
    const SurfaceGaussian eye;
    std::optional<SurfaceGaussian> ownUpdateFilter;
    const CellSurfaceGaussian wide;
    std::vector<RGB> mappedSeen;
    std::vector<Lab> goal, goalWide;
};

// One prediction as the loop sees it: as reflectance, over the footprint
// and over three, and the variance per CIELAB component of its noise at
// both scales, over the object (one draw of it per voxel).
struct SeenPrediction {
    std::vector<RGB> predicted, overFootprint, overFootprintMoved;  // the last: moved by one draw of the noise
    std::vector<Lab> overFootprintLab, wideLab;
    double noiseVariance = 0, noiseVarianceWide = 0;
};

SeenPrediction seePrediction(const SurfacePrediction& p, const RGB& environment, bool noisy, const LoopGoal& goal) {
    SeenPrediction s;
    const size_t n = p.radiance.size();
    s.predicted = reflectance(p.radiance, environment);
    const std::vector<RGB> moved =
        noisy ? movedByNoise(s.predicted, reflectance(p.standardError, environment), 1) : s.predicted;
    std::vector<std::vector<RGB>> filtered = goal.eye.apply(std::vector<const std::vector<RGB>*>{&s.predicted, &moved});
    s.overFootprint = std::move(filtered[0]);
    s.overFootprintMoved = std::move(filtered[1]);
    s.overFootprintLab = labsOf(s.overFootprint);
    s.wideLab = labsOf(goal.wide.apply(s.predicted));
    if (noisy) {
        const std::vector<Lab> drawn = labsOf(s.overFootprintMoved), drawnWide = labsOf(goal.wide.apply(moved));
        for (size_t i = 0; i < n; ++i) {
            const LabVector d = difference(drawn[i], s.overFootprintLab[i]), w = difference(drawnWide[i], s.wideLab[i]);
            s.noiseVariance += dot(d, d);
            s.noiseVarianceWide += dot(w, w);
        }
        s.noiseVariance /= 3.0 * double(n);
        s.noiseVarianceWide /= 3.0 * double(n);
    }
    return s;
}

// Mean CIEDE2000 between two lists of colours.
double meanDeltaE(const std::vector<Lab>& x, const std::vector<Lab>& y) {
    double sum = 0;
    for (size_t i = 0; i < x.size(); ++i) sum += ciede2000(x[i], y[i]);
    return x.empty() ? 0.0 : sum / double(x.size());
}

// The iteration's scores: over the footprint, per voxel, the noise's share
// and the wide score the best is chosen by.
void scoreIteration(const SeenPrediction& s, const LoopGoal& goal, const std::vector<RGB>& mapped, bool noisy,
                    OptimizeIteration& it) {
    const DeltaEStats overFootprint = deltaEStats(s.overFootprint, goal.mappedSeen), raw = deltaEStats(s.predicted, mapped);
    it.meanDeltaE = overFootprint.mean;
    it.p95DeltaE = overFootprint.p95;
    it.meanDeltaEPerVoxel = raw.mean;
    it.p95DeltaEPerVoxel = raw.p95;
    if (noisy) it.noiseDeltaE = deltaEStats(s.overFootprintMoved, s.overFootprint).mean;
    it.meanDeltaEWide = meanDeltaE(s.wideLab, goal.goalWide);
}

// Each voxel's request and its mixture, moved by the error the eye sees
// over the voxel's gain, then the nearest printable colour:
//  - the secant per voxel: the request printed now and the one before, and
//    the prediction of the one before, measure the gain;
//  - Kesten's rule per voxel: the step shrinks each time the error turns
//    back (the voxel overshot, or noise dominates its error), so the moves
//    first follow the error and then average the predictions' noise.
class RequestSteps {
public:
    explicit RequestSteps(size_t n)
        : previousRequest_(n), previousSeen_(n), gain_(n, 1.0f), previousError_(n), reversals_(n, 0), outside_(n, 0),
          outward_(n, {0, 0, 0}) {}

    void move(int iteration, const SeenPrediction& s, const std::vector<Lab>& now, const LoopGoal& goal,
              const PrinterGamut& gamut, double step, std::vector<Lab>& request,
              std::vector<MaterialFractions>& mixture) {
        const size_t n = request.size();
        // The requests' wide part, for the secant (a voxel's own request
        // also moves by its share of the noisy detail, which the wide
        // prediction does not follow).
        std::vector<RGB> requestValues(n);
        for (size_t i = 0; i < n; ++i) requestValues[i] = {request[i].L, request[i].a, request[i].b};
        const std::vector<RGB> requestWide = goal.wide.apply(requestValues);
        tbb::parallel_for(size_t(0), n, [&](size_t i) {
            const Lab r{requestWide[i][0], requestWide[i][1], requestWide[i][2]};
            if (iteration >= 2) {
                const LabVector dR = difference(r, previousRequest_[i]), dP = difference(s.wideLab[i], previousSeen_[i]);
                // Only moves well above the prediction's noise measure a
                // gain (the wide prediction's: the request's move is
                // mostly the wide error's).
                if (dot(dR, dR) > 4.0)
                    gain_[i] = float(std::clamp(0.5 * gain_[i] + 0.5 * (dot(dP, dR) / dot(dR, dR)), 0.5, 2.5));
            }
            previousRequest_[i] = r;
            previousSeen_[i] = s.wideLab[i];
            // The error: its wide part, plus the footprint's detail shrunk
            // by James-Stein's positive-part rule against the predictions'
            // noise (detail the size of the noise barely moves).
            const LabVector errWide = difference(goal.goalWide[i], s.wideLab[i]), errEye = difference(goal.goal[i], now[i]);
            const LabVector detail{errEye[0] - errWide[0], errEye[1] - errWide[1], errEye[2] - errWide[2]};
            const double detailSq = dot(detail, detail);
            const double shrink = detailSq > 0 ? std::max(0.0, 1.0 - s.noiseVariance / detailSq) : 0.0;
            // Kesten's rule on the wide part, counting only turns between
            // errors above its noise.
            const LabVector before{previousError_[i][0], previousError_[i][1], previousError_[i][2]};
            if (iteration >= 2 && dot(errWide, errWide) > 3 * s.noiseVarianceWide &&
                dot(before, before) > 3 * s.noiseVarianceWide && dot(errWide, before) < 0)
                ++reversals_[i];
            previousError_[i] = {float(errWide[0]), float(errWide[1]), float(errWide[2])};
            const double a = step / (gain_[i] * (1 + reversals_[i]));
            const Lab wanted{float(request[i].L + a * (errWide[0] + shrink * detail[0])),
                             float(request[i].a + a * (errWide[1] + shrink * detail[1])),
                             float(request[i].b + a * (errWide[2] + shrink * detail[2]))};
            // A few steps from the last mixture: the request moved little,
            // and the next iteration goes on from here (outside the gamut
            // the full descent costs ~100 us a voxel).
            const PrinterGamut::Match m = gamut.closest(wanted, mixture[i], 12);
            mixture[i] = m.mixture;
            request[i] = m.colour;
            outside_[i] = m.deltaEab > 1.0;
            outward_[i] = {wanted.L - m.colour.L, wanted.a - m.colour.a, wanted.b - m.colour.b};
        });
    }
    // Per voxel, whether its request after the last move lay outside the gamut.
    const std::vector<uint8_t>& outside() const { return outside_; }
    // Per voxel, from the printable request to the wanted one (CIELAB).
    const std::vector<std::array<float, 3>>& outward() const { return outward_; }
    // This iteration's requests that lay outside the gamut.
    double outsideShare() const {
        return double(std::count(outside_.begin(), outside_.end(), uint8_t(1))) / double(outside_.size());
    }
    // A new noise level starts a new averaging: Kesten's counts restart.
    void restartAveraging() { std::fill(reversals_.begin(), reversals_.end(), uint16_t(0)); }

private:
    std::vector<Lab> previousRequest_, previousSeen_;  // the wide request before, its wide prediction
    std::vector<float> gain_;
    std::vector<std::array<float, 3>> previousError_;
    std::vector<uint16_t> reversals_;
    std::vector<uint8_t> outside_;
    std::vector<std::array<float, 3>> outward_;
};

// The best iteration's labels back, over the shell (the loop changes
// nothing else).
void restoreBestLabels(Predictor& predictor, const LabelGrid& best, const VoxelIntGrid& owner) {
    std::vector<LabelGrid::Change> changes;
    const LabelReader now(predictor.labels()), then(best);
    owner.forEachSet([&](const Vec3i& v, int32_t) {
        if (now.at(v) != then.at(v)) changes.push_back({v, then.at(v)});
    });
    predictor.changeLabels(changes);
}

// What the loop does after an iteration: stop (and why), or go on, with
// more samples, or switching from the fast predictor to Monte Carlo.
struct NextStep {
    std::string stop;  // "" to go on
    bool switchToMonteCarlo = false;
    uint32_t moreSpp = 0;  // > 0: the samples per pixel to go up to
};

// onFast: the iteration was the fast predictor's; raisedAt: the iteration
// after which the samples last went up; seconds: the loop's time with one
// more iteration like this one.
NextStep nextStep(const OptimizeSettings& settings, const OptimizeResult& result, const OptimizeIteration& it,
                  bool onFast, bool noisy, uint32_t spp, int raisedAt, double seconds) {
    NextStep next;
    const int iteration = it.iteration;
    // Past the fast predictor's use: its score has stopped falling.
    next.switchToMonteCarlo =
        onFast &&
        ((iteration > 0 && result.iterations.back().meanDeltaE - it.meanDeltaE < settings.switchBelowDeltaE) ||
         iteration + 1 == settings.maxIterations);
    if (iteration >= settings.maxIterations) next.stop = "its iterations";
    else if (settings.timeBudget_s > 0 && seconds > settings.timeBudget_s) next.stop = "its time budget";
    if (next.stop.empty() && settings.patience > 0 && !onFast && iteration > 0 &&
        iteration - std::max(result.bestIteration, raisedAt) >= settings.patience) {
        // Stalled on the predictions' noise: first fewer of it, then stop.
        // Up to mostSpp; once there, 4x more where the noise is still above
        // its target.
        const uint32_t most = spp < settings.mostSpp                        ? settings.mostSpp
                              : it.noiseDeltaE > settings.noiseTargetDeltaE ? 4 * settings.mostSpp
                                                                            : settings.mostSpp;
        if (noisy && spp < most) next.moreSpp = std::min(4 * spp, most);
        else next.stop = "its score stopped falling";
    }
    return next;
}

// The predictor's settings come back as they were, whatever happens.
struct RestoreSettings {
    Predictor& predictor;
    RenderSettings saved;
    CarryOver savedCarryOver;
    ~RestoreSettings() {
        predictor.settings() = saved;
        predictor.carryOver() = savedCarryOver;
    }
};

}  // namespace

OptimizeResult optimizeAppearance(Predictor& predictor, const PrinterGamut& gamut, const std::vector<RGB>& targets,
                                  const OptimizeSettings& settings,
                                  const std::function<void(const OptimizeIteration&)>& onIteration) {
    using Clock = std::chrono::steady_clock;
    const auto loopStart = Clock::now();
    const RGB environment = predictor.environment();
    LabelGrid bestLabels = predictor.labels().withChanges({});
    const uint64_t baseSeed = predictor.settings().seed;
    OptimizeResult result;
    RestoreSettings restore{predictor, predictor.settings(), predictor.carryOver()};
    predictor.carryOver().enabled = settings.carryOver.has_value();
    if (settings.carryOver) predictor.carryOver().method = *settings.carryOver;
    // Kept samples need one seed, if they are kept at all.
    const bool oneSeed = settings.carryOver == CarryOver::Method::KeptSamples && predictor.carriesOver();
    // The Monte Carlo integrator of the settings, and the fast one if any.
    const std::string monteCarlo = predictor.settings().integrator;
    // Back to it with its own parameters (the fast one reads none of them).
    auto useMonteCarlo = [&] {
        predictor.settings().integrator = monteCarlo;
        predictor.settings().parameters = restore.saved.parameters;
    };
    const bool fastFirst =
        !settings.fastPredictor.empty() && settings.fastPredictor != monteCarlo && settings.maxIterations > 0;
    if (fastFirst) setIntegrator(predictor.settings(), settings.fastPredictor);
    auto t0 = Clock::now();
    SurfacePrediction p = predictor.predict();
    const size_t n = p.voxels.size();
    if (targets.size() != n) throw std::invalid_argument("optimizeAppearance: one target per surface voxel is needed");
    const VoxelIntGrid owner = shellOwners(predictor.labels(), p.voxels, settings.shellDepth_mm);
    LoopGoal goal(predictor.surfacePoints_mm(), settings);

    MappedTargets aim = mapTargets(gamut, targets, settings.gamutMap, settings.intent);
    result.mappingLossFlatFace = surfaceColourError(goal.eye, aim.mapped, aim.given);
    result.targetSeen = goal.eye.apply(aim.given);
    goal.aimAt(aim.mapped);

    RequestSteps steps(n);
    PrintersReach reach(n);
    const bool mapToReach = settings.gamutMap && settings.spatialGamutMap;
    double bestScore = 0;
    int raisedAt = 0;  // the iteration after which the samples last went up
    for (int iteration = 0;; ++iteration) {
        const bool noisy = !capabilitiesOf(predictor.settings()).deterministic;
        const SeenPrediction now = seePrediction(p, environment, noisy, goal);
        OptimizeIteration it;
        it.iteration = iteration;
        it.predictor = predictor.settings().integrator;
        it.spp = predictor.settings().spp;
        it.retracedVoxels = p.retracedVoxels;
        for (uint32_t s : p.samples) it.meanSamples += double(s) / double(n);
        scoreIteration(now, goal, aim.mapped, noisy, it);
        // A new best only if it beats the last by a margin, on the wide
        // score: at the footprint the predictions' noise dominates the score
        // and hides what the loop still changes.
        if (iteration == 0 || it.meanDeltaEWide < bestScore - std::max(0.02 * bestScore, 0.02)) {
            bestScore = it.meanDeltaEWide;
            result.bestIteration = iteration;
            if (iteration > 0) bestLabels = predictor.labels().withChanges({});
            result.predictedSeen = now.overFootprint;
            if (!mapToReach) result.atPrintersLimit = steps.outside();  // the move that made these labels
        }
        const bool onFast = fastFirst && predictor.settings().integrator == settings.fastPredictor;
        const double elapsed = std::chrono::duration<double>(Clock::now() - loopStart).count();
        const double lastSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
        const NextStep next = nextStep(settings, result, it, onFast, noisy, predictor.settings().spp, raisedAt,
                                       elapsed + lastSeconds);
        const std::string& stop = next.stop;
        if (!stop.empty()) {
            result.stoppedBecause = stop;
            it.seconds = lastSeconds;
            result.iterations.push_back(it);
            if (onIteration) onIteration(it);
            break;
        }
        // Move the requests (the mapped targets' own mixtures are printed first).
        if (iteration > 0) {
            const std::vector<Lab> nowOverUpdate = settings.updateFootprint_mm == kEyeFootprint_mm
                                                       ? now.overFootprintLab
                                                       : labsOf(goal.updateFiltered(now.predicted));
            steps.move(iteration, now, nowOverUpdate, goal, gamut, settings.step, aim.request, aim.mixture);
            it.outsideShare = steps.outsideShare();
            // The evidence of where the print is at the printer's limit
            // (Monte Carlo's only: a deterministic predictor's edges are not
            // the print's).
            if (mapToReach && noisy)
                reach.update({goal.goal, nowOverUpdate, goal.goalWide, now.wideLab, now.noiseVariance,
                              now.noiseVarianceWide, steps.outside(), steps.outward()});
        }
        std::vector<LabelGrid::Change> changes = halftoneShell(predictor.labels(), owner, aim.mixture, settings.halftone,
                                                                   iteration > 0 ? settings.hysteresis : 0.0f);
        predictor.changeLabels(changes);
        it.changedVoxels = changes.size();
        if (settings.recordChanges) result.changes.push_back(std::move(changes));
        it.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        result.iterations.push_back(it);
        if (onIteration) onIteration(it);
        t0 = Clock::now();
        // A new seed each iteration: the loop must not fit one noise
        // realisation. Carrying over, new samples of the same seed.
        if (!oneSeed) predictor.settings().seed = baseSeed + uint64_t(iteration) + 1;
        if (next.switchToMonteCarlo) useMonteCarlo();
        if (next.moreSpp > 0) {
            predictor.settings().spp = next.moreSpp;
            raisedAt = iteration;
            steps.restartAveraging();
        }
        p = predictor.predict();
    }
    // What the print can show at every point, as the loop found it: the
    // judge's and the report's reference.
    if (mapToReach) {
        result.aimedAt = reach.remap(aim.mapped);
        result.mappedSeen = goal.eye.apply(result.aimedAt);
        result.mappingLoss = surfaceColourError(goal.eye, result.aimedAt, aim.given);
        result.atPrintersLimit = reach.atLimit();
    } else {
        result.aimedAt = aim.mapped;
        result.mappedSeen = goal.mappedSeen;
        result.mappingLoss = result.mappingLossFlatFace;
    }
    result.deltaESeen.resize(n);
    for (size_t i = 0; i < n; ++i)
        result.deltaESeen[i] = float(ciede2000(labFromLinearSrgb(result.predictedSeen[i]),
                                               labFromLinearSrgb(result.mappedSeen[i])));
    if (result.bestIteration != result.iterations.back().iteration)
        restoreBestLabels(predictor, bestLabels, owner);
    if (settings.judge) {
        useMonteCarlo();
        const std::string judge = settings.judgeIntegrator.empty() ? monteCarlo : settings.judgeIntegrator;
        result.judgement = judgePrint(predictor, settings, judge, goal.eye, result.aimedAt, aim.mapped, environment);
    }
    return result;
}

OptimizeJudgement judgeLabels(Predictor& predictor, const OptimizeSettings& settings, const std::vector<RGB>& mapped) {
    const std::string integrator =
        settings.judgeIntegrator.empty() ? predictor.settings().integrator : settings.judgeIntegrator;
    const SurfaceGaussian eye(predictor.surfacePoints_mm(), kEyeFootprint_mm);
    return judgePrint(predictor, settings, integrator, eye, mapped, mapped, predictor.environment());
}

}  // namespace pl
