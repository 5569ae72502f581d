#include "api/predictor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include "runtime/distributed.h"
#include "runtime/progress.h"
#include "render/progressive_render.h"
#include "render/registry.h"
#include "core/input_error.h"
#include "render/scene_io.h"

namespace pl {

struct Predictor::State {
    Scene scene;  // its medium holds the materials and the NEE fields across updates
    std::vector<SurfaceVoxel> surfaceVoxels;
    std::unique_ptr<SurfaceVoxelSensor> sensor;
};

// The samples a prediction leaves for the next (CarryOver).
struct Predictor::CarriedSamples {
    RenderSettings settings;  // they were drawn with (spp aside)
    Film film;
    PathFootprints footprints;
    std::vector<uint32_t> firstSample;  // per voxel: its samples are [firstSample, drawn)
    uint32_t drawn = 0;
    LabelChanges changes;  // since they were drawn
};

// The running estimate a prediction leaves for the next (ControlVariates).
struct Predictor::RunningEstimate {
    RenderSettings settings;              // it was drawn with (seed and spp aside)
    std::vector<RGB> estimate, variance;  // per voxel: X and its variance V
    // The last prediction's standard errors (as the film pooled them) of
    // its samples' mean and of their differences'.
    std::vector<RGB> sampleError, differenceError;
    LabelChanges changes;                     // since the last prediction
    std::unique_ptr<LabelMedium> previous;    // its labels, once any changed
};

Predictor::Predictor(const SceneDescription& desc, const RenderSettings& settings, SceneNeeds alsoNeeds)
    : state_(std::make_unique<State>()), settings_(settings) {
    if (desc.sensor.type != "surface_voxels")
        throw InputError(desc.sceneFile.string(), "the prediction API needs the surface_voxels sensor");
    SceneNeeds needs = sceneNeedsOf(settings);
    needs |= alsoNeeds;
    state_->scene = loadScene(desc, needs);
    // The render command's sensor checks (mesh and grid match, memory).
    state_->surfaceVoxels = labels().surfaceVoxels();
    state_->sensor = makeSurfaceVoxelSensor(desc, state_->scene, state_->surfaceVoxels);
}

std::unique_ptr<Predictor> Predictor::fromSceneFile(const std::filesystem::path& sceneFile) {
    SceneDescription desc = parseScene(sceneFile);
    return std::make_unique<Predictor>(desc, desc.render);
}

Predictor::~Predictor() = default;

const LabelGrid& Predictor::labels() const { return state_->scene.medium->grid(); }
size_t Predictor::surfaceVoxelCount() const { return state_->sensor->pixelCount(); }
std::vector<Vec3i> Predictor::surfaceVoxels() const {
    std::vector<Vec3i> v;
    v.reserve(state_->sensor->pixelCount());
    for (const auto& px : state_->sensor->pixels()) v.push_back(px.voxel);
    return v;
}
std::vector<Point3f> Predictor::surfacePoints_mm() const {
    std::vector<Point3f> points;
    points.reserve(state_->sensor->pixelCount());
    for (const auto& px : state_->sensor->pixels()) points.push_back(px.surfacePoint_mm);
    return points;
}
RGB Predictor::environment() const { return state_->scene.environment; }
GridFrame Predictor::worldFrame() const { return state_->scene.worldFrame(); }

namespace {
// A medium of these labels, built whole, with `like`'s materials and NEE fields.
std::unique_ptr<LabelMedium> mediumLike(LabelGrid grid, const LabelMedium& like) {
    auto medium = std::make_unique<LabelMedium>(std::move(grid), like.materials());
    medium->setSurfaceFields(like.surfaceFields());
    return medium;
}

// Whether a brick's bounds are the same to free flights against per-brick
// majorants (media/collision_events.h), which read its majorant, its sole
// label and whether its labels share one sigma_t per channel.
bool sameBoundsForTrackers(const MajorantGrid::Bounds& a, const MajorantGrid::Bounds& b) {
    for (int c = 0; c < 3; ++c)
        if ((a.maxSigmaT[c] == a.minSigmaT[c]) != (b.maxSigmaT[c] == b.minSigmaT[c])) return false;
    return a.maxSigmaT == b.maxSigmaT && a.soleLabel == b.soleLabel;
}

void requireMaterial(const MaterialTable& materials, Label label, Label voidLabel) {
    if (!materials.covers(label, voidLabel))
        throw std::invalid_argument("label " + std::to_string(label) + " is not in the material table");
}
}  // namespace

void Predictor::install(LabelGrid grid, bool occupancyChanged, const std::vector<Vec3i>* changed) {
    auto t0 = std::chrono::steady_clock::now();
    const GridFrame& local = labels().frame();
    grid.placeCornerAt(local.cornerMin_mm);
    // The sensor only depends on which voxels are void. Built first: labels
    // that the mesh does not cover are refused with the predictor unchanged.
    std::unique_ptr<SurfaceVoxelSensor> sensor;
    std::vector<SurfaceVoxel> surface;
    if (occupancyChanged) {
        surface = grid.surfaceVoxels();
        if (surface != state_->surfaceVoxels) {
            try {
                sensor = std::make_unique<SurfaceVoxelSensor>(*state_->scene.geometry, grid.frame(), surface);
            } catch (const std::runtime_error& e) {
                throw std::invalid_argument(std::string("new labels: ") + e.what());
            }
        }
    }
    // Grid, lookup tables and majorants: everything that depends on labels.
    std::unique_ptr<LabelMedium> previous = std::move(state_->scene.medium);
    try {
        if (changed) {  // majorants of the touched bricks only (that the running estimate lets only rise)
            state_->scene.medium =
                std::make_unique<LabelMedium>(std::move(grid), *previous, *changed, running_ != nullptr);
            majorantsRaised_ = majorantsRaised_ || running_ != nullptr;
        } else {
            state_->scene.medium = mediumLike(std::move(grid), *previous);
        }
    } catch (...) {
        state_->scene.medium = std::move(previous);
        throw;
    }
    const bool shapeChanged = sensor != nullptr;
    if (shapeChanged) {
        state_->surfaceVoxels = std::move(surface);
        state_->sensor = std::move(sensor);
    }
    // What carries over survives a relabelling of voxels alone; the paths
    // are checked against what changed at the next prediction.
    if (shapeChanged || !changed) {
        carried_.reset();
        dropRunningEstimate();
        pendingUpdateSeconds_ += secondsSince(t0);
        return;
    }
    // (At most one of the two is kept: predict() drops the other.)
    LabelChanges* marks = carried_ ? &carried_->changes : running_ ? &running_->changes : nullptr;
    const MajorantGrid &before = previous->majorants(), &after = state_->scene.medium->majorants();
    // Kept samples, drawn before, are compared with the current labels; the
    // running estimate's samples, drawn next, with its last prediction's.
    const LabelGrid& current = labels();
    if (marks)
        for (const Vec3i& v : *changed) {
            const uint64_t key = after.voxelKey(v);
            if (carried_) marks->markRelabelled(key, current.label(v));
            else if (!marks->relabelled(key)) marks->markRelabelled(key, previous->grid().label(v));
            const Vec3i b = MajorantGrid::brickOf(v);
            if (!sameBoundsForTrackers(before.bounds(b), after.bounds(b))) marks->markBoundsChanged(after.brickIndex(b));
        }
    // The running estimate renders the labels of its last prediction too.
    if (running_ && !running_->previous) running_->previous = std::move(previous);
    pendingUpdateSeconds_ += secondsSince(t0);
}

void Predictor::setLabels(LabelGrid grid) {
    auto t0 = std::chrono::steady_clock::now();
    const LabelGrid& old = labels();
    const GridFrame &a = grid.frame(), &b = old.frame();
    bool sameVoxelSize = a.voxelSize_mm.x == b.voxelSize_mm.x && a.voxelSize_mm.y == b.voxelSize_mm.y &&
                         a.voxelSize_mm.z == b.voxelSize_mm.z;
    if (a.indexMin != b.indexMin || a.resolution != b.resolution || !sameVoxelSize || grid.voidLabel() != old.voidLabel())
        throw std::invalid_argument("new labels must lie on the same voxels (frame and void label) as the scene's");
    auto hist = grid.histogram();
    for (int l = 0; l < 256; ++l)
        if (hist[size_t(l)]) requireMaterial(state_->scene.medium->materials(), Label(l), grid.voidLabel());
    bool occupancyChanged = !grid.hasSameOccupancyTree(old);
    pendingUpdateSeconds_ += secondsSince(t0);
    install(std::move(grid), occupancyChanged, nullptr);
}

void Predictor::changeLabels(const std::vector<LabelGrid::Change>& changes) {
    auto t0 = std::chrono::steady_clock::now();
    const LabelGrid& old = labels();
    const Label voidLabel = old.voidLabel();
    bool occupancyChanged = false;
    std::vector<Vec3i> voxels;
    voxels.reserve(changes.size());
    for (const auto& c : changes) {
        requireMaterial(state_->scene.medium->materials(), c.label, voidLabel);
        occupancyChanged = occupancyChanged || ((old.label(c.voxel) == voidLabel) != (c.label == voidLabel));
        voxels.push_back(c.voxel);
    }
    LabelGrid next = old.withChanges(changes);
    pendingUpdateSeconds_ += secondsSince(t0);
    install(std::move(next), occupancyChanged, &voxels);
}

namespace {
// Whether every rendered channel of pixel p meets the adaptive target.
bool converged(const Film& film, size_t p, const std::vector<int>& channels, const AdaptiveSampling& a) {
    for (int c : channels) {
        float target = std::max(a.maxStandardError, a.maxRelativeError * std::abs(film.mean(p, c)));
        if (!(film.standardError(p, c) <= target)) return false;
    }
    return true;
}

// Whether samples drawn with `a` may be pooled with samples drawn with `b`:
// the same paths but for their number (the estimator's parameters
// included).
bool sameButSpp(const RenderSettings& a, const RenderSettings& b) {
    return a.integrator == b.integrator && a.seed == b.seed && a.reentry == b.reentry && a.channels == b.channels &&
           a.channelSampling == b.channelSampling && a.majorants == b.majorants && a.parameters == b.parameters;
}

// The film's estimate of every voxel, into p.
void readFilm(const Film& film, const RenderSettings& rs, SurfacePrediction& p) {
    const size_t n = film.pixelCount();
    p.radiance.resize(n);
    p.standardError.resize(n);
    p.samples.resize(n);
    for (size_t i = 0; i < n; ++i) {
        p.radiance[i] = film.meanRGB(i);
        p.standardError[i] = film.standardErrorRGB(i);
        p.samples[i] = film.samples(i, rs.channels.front());
    }
}

// The weight w of the running estimate X = w X_before + (1 - w) F + w D
// (F the new samples' mean, D the mean of their differences f - h), chosen
// before the samples from the standard errors a, b that F and D are
// expected to have (the last prediction's). With f and h alike in spread
// (labels that change little), Cov(F, D) = b^2 / 2, so the estimate's
// variance is w^2 V + (1 - w)^2 a^2 + w b^2, least at
// w = (a^2 - b^2 / 2) / (V + a^2) in [0, 1]. The weight only has to be
// good: the variance reported is measured on the samples (CoupledSampling).
float controlWeight(double variance, double a, double b) {
    const double denominator = variance + a * a;
    if (!(denominator > 0)) return 0.0f;  // no spread seen at all: the new samples alone
    return float(std::clamp((a * a - 0.5 * b * b) / denominator, 0.0, 1.0));
}
}  // namespace

void Predictor::predictByControlVariates(const RenderSettings& rs, SurfacePrediction& p) {
    const Sensor& sensor = *state_->sensor;
    const size_t n = sensor.pixelCount();
    const auto t0 = std::chrono::steady_clock::now();
    RenderRounds rounds(state_->scene, sensor, rs, false, true);
    // The same seed again would draw the same samples: not new evidence.
    RenderSettings seedAside = rs;
    if (running_) seedAside.seed = running_->settings.seed;
    p.startedAfresh = !running_ || rs.seed == running_->settings.seed || !sameButSpp(running_->settings, seedAside);
    Film& film = rounds.result().film;
    if (p.startedAfresh) {
        rounds.render(nullptr, 0, rs.spp);
        running_ = std::make_unique<RunningEstimate>();
        RunningEstimate& r = *running_;
        r.settings = rs;
        r.changes = LabelChanges(state_->scene.medium->majorants().brickCount(), state_->scene.medium->luts());
        readFilm(film, rs, p);
        r.estimate = p.radiance;
        // Until the first pairs say otherwise, the differences are taken
        // as two independent renders' (w = 0: the next prediction afresh).
        r.sampleError = p.standardError;
        r.variance.resize(n);
        r.differenceError.resize(n);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                r.variance[i][c] = p.standardError[i][c] * p.standardError[i][c];
                r.differenceError[i][c] = std::sqrt(2.0f) * p.standardError[i][c];
            }
        p.renderSeconds = rounds.result().seconds;
        p.stats = rounds.stats();
        return;
    }
    RunningEstimate& r = *running_;
    // The last prediction's errors stand for this one's (per sample: the
    // sample counts may differ).
    const double perSample = std::sqrt(double(r.settings.spp) / double(rs.spp));
    std::vector<RGB> weight(n, RGB{0, 0, 0});
    for (size_t i = 0; i < n; ++i)
        for (int c : rs.channels)
            weight[i][c] = controlWeight(r.variance[i][c], perSample * r.sampleError[i][c],
                                         perSample * r.differenceError[i][c]);
    Film differences(n), combined(n);
    std::vector<uint32_t> tracedTwice(n, 0);
    // No change since: the previous labels are the current ones.
    const CoupledSampling coupled{r.previous ? r.previous.get() : state_->scene.medium.get(), &r.changes,
                                  &differences, &tracedTwice, &weight, &combined};
    rounds.result().seconds += secondsSince(t0);
    rounds.renderPairs(&coupled);
    rounds.render(nullptr, 0, rs.spp);
    const auto t1 = std::chrono::steady_clock::now();
    differences.poolErrors(&sensor);
    combined.poolErrors(&sensor);
    // X = w X_before + (1 - w) F + w D, the last two the combined samples'
    // mean: its variance w^2 V_before + their squared standard error.
    p.radiance.resize(n);
    p.standardError.resize(n);
    p.samples.assign(n, rs.spp);
    for (size_t i = 0; i < n; ++i) {
        p.retracedVoxels += tracedTwice[i] > 0;
        for (int c : rs.channels) {
            const double w = weight[i][c], seF = film.standardError(i, c), seD = differences.standardError(i, c);
            r.estimate[i][c] = float(w * r.estimate[i][c] + combined.mean(i, c));
            const double seY = combined.standardError(i, c);
            r.variance[i][c] = float(w * w * r.variance[i][c] + seY * seY);
            r.sampleError[i][c] = float(seF);
            r.differenceError[i][c] = float(seD);
        }
        p.radiance[i] = r.estimate[i];
        for (int c = 0; c < 3; ++c) p.standardError[i][c] = std::sqrt(r.variance[i][c]);
    }
    r.changes.clear();
    r.previous.reset();
    r.settings = rs;
    p.renderSeconds = rounds.result().seconds + secondsSince(t1);
    p.stats = rounds.stats();
}

void Predictor::predictCarryingOver(const RenderSettings& rs, SurfacePrediction& p) {
    const Sensor& sensor = *state_->sensor;
    const size_t n = sensor.pixelCount();
    const auto t0 = std::chrono::steady_clock::now();
    RenderRounds rounds(state_->scene, sensor, rs, false, true);
    p.startedAfresh = !carried_ || !sameButSpp(carried_->settings, rs);
    if (p.startedAfresh) {
        carried_ = std::make_unique<CarriedSamples>();
        carried_->settings = rs;
        carried_->film = Film(n);
        carried_->footprints = PathFootprints(n);
        carried_->firstSample.assign(n, 0);
        carried_->changes = LabelChanges(state_->scene.medium->majorants().brickCount(), state_->scene.medium->luts());
    }
    CarriedSamples& c = *carried_;
    Film& film = rounds.result().film;
    film = std::move(c.film);
    rounds.recordFootprints(&c.footprints);
    // The voxels whose paths read a change: their last retraceSamples
    // kept samples traced again, grouped by first sample.
    std::map<uint32_t, std::vector<uint32_t>> retraceFrom;
    const uint32_t retraced = std::min(c.drawn, carryOver_.retraceSamples);
    for (size_t i = 0; i < n; ++i) {
        if (!c.footprints.meets(i, c.changes)) continue;
        ++p.retracedVoxels;
        film.clearPixel(i);
        c.footprints.clear(i);
        c.firstSample[i] = std::max(c.firstSample[i], c.drawn - retraced);
        if (c.firstSample[i] < c.drawn) retraceFrom[c.firstSample[i]].push_back(uint32_t(i));
    }
    c.changes.clear();
    rounds.result().seconds += secondsSince(t0);
    for (const auto& [first, pixels] : retraceFrom) rounds.render(&pixels, first, c.drawn - first);
    rounds.render(nullptr, c.drawn, rs.spp);
    c.drawn += rs.spp;
    readFilm(film, rs, p);
    p.stats = rounds.stats();
    p.renderSeconds = rounds.result().seconds;
    c.film = std::move(film);
}

bool Predictor::carriesOver() const {
    // One pass per channel keeps each sample's path whole (hero channels
    // go to the film in groups).
    const bool keysFit = PathFootprints::fits(state_->scene.medium->majorants());
    return carryOver_.enabled && !adaptive_.enabled && !acrossRanks_ && settings_.majorants == Majorants::PerBrick &&
           capabilitiesOf(settings_).recordsFootprints && keysFit && !rendersChannelsInOnePass(settings_);
}

SurfacePrediction Predictor::predict() {
    RenderSettings rs = settings_;
    rs.showProgress = false;
    if (carriesOver()) {
        const bool byControlVariates = carryOver_.method == CarryOver::Method::ControlVariates;
        SurfacePrediction p;
        p.voxels = surfaceVoxels();
        try {
            if (byControlVariates) {
                carried_.reset();
                predictByControlVariates(rs, p);
            } else {
                dropRunningEstimate();
                predictCarryingOver(rs, p);
            }
        } catch (...) {  // interrupted: what was half rendered does not carry over
            carried_.reset();
            dropRunningEstimate();
            throw;
        }
        p.updateSeconds = pendingUpdateSeconds_;
        pendingUpdateSeconds_ = 0;
        return p;
    }
    return predictAfresh(rs, nullptr);
}

SurfacePrediction Predictor::predictVoxels(const std::vector<uint32_t>& voxels) {
    const size_t n = surfaceVoxelCount();
    for (uint32_t v : voxels)
        if (v >= n) throw std::out_of_range("predictVoxels: voxel " + std::to_string(v) + " of " + std::to_string(n));
    RenderSettings rs = settings_;
    rs.showProgress = false;
    return predictAfresh(rs, &voxels);
}

void Predictor::dropRunningEstimate() {
    running_.reset();
    if (!majorantsRaised_) return;
    // The exact majorants again: the bits of a predictor that never carried over.
    state_->scene.medium = mediumLike(labels().withChanges({}), *state_->scene.medium);
    majorantsRaised_ = false;
}

SurfacePrediction Predictor::predictAfresh(const RenderSettings& rs, const std::vector<uint32_t>* voxels) {
    carried_.reset();
    dropRunningEstimate();
    const Sensor& sensor = *state_->sensor;
    // One integrator for all rounds: its census and means are made once.
    // Across ranks each renders its share of a round's pixels and every
    // rank receives the whole film after each round (pooled on rank 0), so
    // that all decide the next round alike.
    const auto t0 = std::chrono::steady_clock::now();
    RenderRounds rounds(state_->scene, sensor, rs, acrossRanks_, true);
    RenderResult& r = rounds.result();
    r.seconds += secondsSince(t0);
    if (voxels) {
        rounds.render(voxels, 0, rs.spp);
    } else if (!adaptive_.enabled) {
        rounds.render(nullptr, 0, rs.spp);
    } else {
        const AdaptiveSampling& a = adaptive_;
        rounds.render(nullptr, 0, std::min(std::max(a.firstRoundSpp, 2u), a.maxSpp));
        // Each round renders the voxels that miss the target, in groups of
        // one sample count (sample s is the same path in any round). A
        // voxel's error is pooled with its neighbours', so one that met the
        // target can miss it again when they change: it rejoins. Rounds
        // are deterministic; across ranks every rank has the whole film:
        // the same decisions, but rank 0's clock.
        for (;;) {
            std::map<uint32_t, std::vector<uint32_t>> activeBySamples;
            for (size_t p = 0; p < sensor.pixelCount(); ++p) {
                const uint32_t n = r.film.samples(p, rs.channels.front());
                if (n < a.maxSpp && !converged(r.film, p, rs.channels, a)) activeBySamples[n].push_back(uint32_t(p));
            }
            const bool more = !activeBySamples.empty() && !(a.maxSeconds > 0 && r.seconds >= a.maxSeconds);
            if (!(rounds.acrossRanks() ? broadcastFromRankZero(uint32_t(more)) : more)) break;
            for (const auto& [done, active] : activeBySamples)
                rounds.render(&active, done, std::min(std::max(a.roundSpp, 1u), a.maxSpp - done));
        }
    }
    SurfacePrediction p;
    p.voxels = surfaceVoxels();
    readFilm(r.film, rs, p);
    p.stats = rounds.stats();
    p.voxelsShareSamples = capabilitiesOf(rs).lightPathsServeEveryPixel;
    p.renderSeconds = r.seconds;
    p.updateSeconds = pendingUpdateSeconds_;
    pendingUpdateSeconds_ = 0;
    return p;
}

}  // namespace pl
