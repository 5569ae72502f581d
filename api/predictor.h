// The prediction API an appearance-optimisation loop calls every iteration
// (docs/api.md): mesh, BVH, surface clearance, sensor and materials are
// loaded once; each iteration swaps in new labels (a whole grid or a list of
// changed voxels) and returns, for every surface voxel, the RGB radiance
// leaving it along its normal and the standard error of that estimate.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "render/render.h"
#include "media/label_grid.h"

namespace pl {

struct SceneDescription;

struct SurfacePrediction {
    std::vector<Vec3i> voxels;  // the surface voxels, in sensor order (z, then y, then x)
    std::vector<RGB> radiance, standardError;
    std::vector<uint32_t> samples;  // per voxel (per channel rendered)
    // Carrying over (Predictor::carryOver): the voxels some of whose
    // samples were traced again because their paths read a change (kept
    // samples: with the new labels; control variates: with the previous),
    // and whether the prediction started afresh.
    size_t retracedVoxels = 0;
    bool startedAfresh = true;
    // Whether voxels share samples (light paths score many): their errors
    // are then correlated, not independent.
    bool voxelsShareSamples = false;
    PathStats stats;
    double updateSeconds = 0;  // swapping labels in: grid, majorants, sensor check
    double renderSeconds = 0;
};

// Render until every surface voxel's standard error is below a target, in
// rounds: all voxels get firstRoundSpp, then the voxels not yet there get
// roundSpp more per round, up to maxSpp (or until maxSeconds).
struct AdaptiveSampling {
    bool enabled = false;
    float maxStandardError = 0;  // absolute target per channel (0: none)
    float maxRelativeError = 0;  // standard error / mean per channel (0: none)
    uint32_t firstRoundSpp = 8;  // before this, a standard error is not trusted
    uint32_t roundSpp = 8;
    uint32_t maxSpp = 1024;
    double maxSeconds = 0;  // 0: none; a time budget makes results depend on the machine
};

// Predictions that carry over (docs/api.md), by one of two methods:
//  - KeptSamples: the samples of earlier predictions are kept while what
//    their paths read of the labels stays as it was. Each prediction adds
//    settings().spp samples per voxel, the next sample indices of the same
//    seed; a voxel whose paths read a change (PathFootprints) has its kept
//    samples traced again with the same random numbers, so every voxel
//    holds the bits of a render of its samples in one go (one pass per
//    channel). Of a touched voxel's kept samples at most the last
//    retraceSamples are traced again, the older ones dropped (by index,
//    whatever their paths did: the estimate stays unbiased).
//  - ControlVariates: a running estimate by recursive control variates
//    (Nicolet et al. 2023). Each prediction draws settings().spp new
//    samples (the seed as the caller sets it) and traces each with the
//    current labels and, only if it read a change, with the labels of the
//    last prediction, with the same random numbers (integrators/
//    coupled_samples.h); per voxel and channel X = w X_before + (1 - w) F
//    + w D, F the samples' mean and D their differences', with variance
//    w^2 V_before plus the squared error of the samples f - w h (measured
//    on them, pooled by the film); w is chosen before the samples, from
//    the last prediction's errors. Its majorants only rise meanwhile
//    (MajorantGrid::update; exact again once it is dropped). Unbiased for
//    a fixed w; w follows the last errors, which move a little with the
//    estimate, so a small bias is possible (none seen against references:
//    docs/api.md). A prediction with the last one's seed starts afresh.
// Both need an estimator that records footprints (volpath), per-brick
// majorants, one process, no adaptive sampling and one pass per channel
// (channel sampling "separate"; carriesOver()). Otherwise every
// prediction starts afresh, as after setLabels, a change of shape, or a
// change of any setting but spp (KeptSamples) or spp and seed
// (ControlVariates).
struct CarryOver {
    enum class Method { KeptSamples, ControlVariates };
    bool enabled = false;
    Method method = Method::KeptSamples;
    uint32_t retraceSamples = 1u << 30;  // KeptSamples
};

class Predictor {
public:
    // Loads the scene's mesh, materials and labels (sensor must be
    // surface_voxels); `settings` chooses estimator, spp, seed and channels.
    // alsoNeeds: what other estimators the caller will switch to need
    // (an optimisation loop's judge).
    Predictor(const SceneDescription& scene, const RenderSettings& settings, SceneNeeds alsoNeeds = {});
    static std::unique_ptr<Predictor> fromSceneFile(const std::filesystem::path& sceneFile);
    ~Predictor();

    // The next iteration's labels: a grid on the same voxels (same frame and
    // void label), or changes to the current one. Labels must be in the
    // material table (std::invalid_argument otherwise). If the set of
    // surface voxels changes (the shape changed), the sensor is rebuilt.
    void setLabels(LabelGrid grid);
    void changeLabels(const std::vector<LabelGrid::Change>& changes);

    // Renders the current labels. Same labels and seed, same bits.
    SurfacePrediction predict();
    // These surface voxels only (indices into predict()'s order), with
    // settings().spp samples each, afresh (no adaptive sampling, nothing
    // carried over); the others have no samples (radiance and error 0).
    // A judge of sampled footprints renders their neighbourhoods so.
    SurfacePrediction predictVoxels(const std::vector<uint32_t>& voxels);

    // Across MPI ranks (runtime/distributed.h): each rank renders its share
    // of every prediction and all receive the whole, with the bits of one
    // process. Every rank must then make the same calls, in step.
    void setAcrossRanks(bool on) { acrossRanks_ = on; }

    RenderSettings& settings() { return settings_; }
    const RenderSettings& settings() const { return settings_; }
    AdaptiveSampling& adaptive() { return adaptive_; }
    CarryOver& carryOver() { return carryOver_; }
    // Whether the next prediction carries over (asked, and possible with
    // these settings: CarryOver).
    bool carriesOver() const;
    const LabelGrid& labels() const;
    size_t surfaceVoxelCount() const;
    // The surface voxels in the order predict() reports them, and where
    // each meets the surface (the render's local frame).
    std::vector<Vec3i> surfaceVoxels() const;
    std::vector<Point3f> surfacePoints_mm() const;
    // Radiance of the surroundings (divide by it for reflectance) and the
    // grid's placement in the world (labels() is in the render's local frame).
    RGB environment() const;
    GridFrame worldFrame() const;

private:
    // occupancyChanged: whether any voxel may have turned void or non-void;
    // changed: the relabelled voxels (null: the whole grid is new).
    void install(LabelGrid grid, bool occupancyChanged, const std::vector<Vec3i>* changed);
    // predict() with the samples carried over (CarryOver), into p.
    void predictCarryingOver(const RenderSettings& rs, SurfacePrediction& p);
    void predictByControlVariates(const RenderSettings& rs, SurfacePrediction& p);
    // A prediction of all voxels (none: adaptive if asked) or these, afresh.
    SurfacePrediction predictAfresh(const RenderSettings& rs, const std::vector<uint32_t>* voxels);

    struct State;
    std::unique_ptr<State> state_;
    RenderSettings settings_;
    AdaptiveSampling adaptive_;
    CarryOver carryOver_;
    struct CarriedSamples;
    std::unique_ptr<CarriedSamples> carried_;  // what the last prediction left; none: start afresh
    struct RunningEstimate;
    std::unique_ptr<RunningEstimate> running_;  // the same, for ControlVariates
    bool majorantsRaised_ = false;              // by the running estimate (MajorantGrid::update)
    // Drops the running estimate, and majorants it raised.
    void dropRunningEstimate();
    bool acrossRanks_ = false;
    double pendingUpdateSeconds_ = 0;
};

}  // namespace pl
