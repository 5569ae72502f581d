// lighttrace: light tracing into the surface-voxel sensor's patches, where
// one light path serves every voxel whose measurement lines it crosses
// (docs/lighttrace.md).
// A patch's value, the radiance leaving it along its normal averaged over
// it, is split in two:
//  - the camera side (cameraSide): the environment reflected at the surface, and
//    the light that reaches the patch along its inward normal line's first
//    segment without scattering on it (through the segment's far boundary);
//  - the light side (scoreLightBlock): light scattered last on that
//    segment. Particles enter from the environment and walk with volpath's
//    walk; points along their flights (or their real collisions,
//    LightTraceOptions::scoring) score into each patch whose inward normal
//    line holds them, through the transmittance to the surface, the phase
//    function towards the normal, the Fresnel transmission out and 1/n^2.
// Each sample of a pixel is its camera sample plus one block of particles'
// score, with the block's own estimate of that score's variance from its
// particles (LightBlockScores): honest from one sample on, where the
// spread of a few blocks is not. Separate channel passes only.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "core/mesh_point_sampler.h"
#include "core/option_table.h"
#include "core/prism_index.h"
#include "core/sensors.h"
#include "integrators/printpt/printpt.h"
#include "integrators/volpath/volpath.h"

namespace pl {

struct LightTraceOptions {
    // Particles per block (per sample) for each sensor pixel.
    float particlesPerPixel = 1.0f;
    // printpt takes the pixels it serves better: over one resin (the
    // pixel's 8^3 brick holds one label besides void: its ball walks are
    // cheap there) or where its walks run with a control. False: the light
    // side scores into every pixel but slivers.
    bool hybrid = true;
    // Where particles score. Collisions: at their real collisions. Tracks:
    // all along their flights, at points trackSpacing apart (a random
    // offset per flight), each weighted by sigma_s times the spacing (where
    // that is below 0.01, as in clear resin, connected by Russian
    // roulette): the track-length estimator, whose scores do not depend on
    // where the collisions fell (1.2x faster to the same error on the
    // patterned test-set scenes, docs/performance.md).
    enum class Scoring { Collisions, Tracks };
    Scoring scoring = Scoring::Tracks;
    // The spacing of track points, in scattering mean free paths of the
    // most scattering label in the grid (per channel).
    float trackSpacing_mfp = 1.0f;
};
inline constexpr std::array<EnumName<LightTraceOptions::Scoring>, 2> kLightTraceScoringNames{
    {{LightTraceOptions::Scoring::Collisions, "collisions"}, {LightTraceOptions::Scoring::Tracks, "tracks"}}};
// Its numeric and boolean options by their scene-file names
// (core/option_table.h; lighttrace_scoring is a name, LightTrace::parameters).
const std::vector<OptionParameter<LightTraceOptions>>& lightTraceParameters();

// One block of light paths' scores per pixel. The block's particles are
// independent, so the variance of a pixel's score is the sum of each
// particle's, which the sum of the particles' squared scores (each
// particle's whole score in the pixel, squared) estimates, without bias for
// particles that enter anywhere with one density and conservatively where
// entries are stratified (it also counts each particle's mean squared).
// It rests on every particle that reached the pixel, not on a few blocks.
struct LightBlockScores {
    std::vector<double> score, scoreSq;
    void assign(size_t pixels) {
        score.assign(pixels, 0.0);
        scoreSq.assign(pixels, 0.0);
    }
};

class LightTrace : public Integrator {
public:
    // The sensor must be the surface-voxel sensor with the patch footprint
    // (std::invalid_argument otherwise).
    // printpt: the camera estimator of the pixels the light side leaves
    // out.
    LightTrace(const Scene& scene, const Sensor& sensor, LightTraceOptions options, VolPathOptions volpath,
               PrintPtOptions printpt, Majorants majorants, uint64_t seed);

    // Light paths serve every pixel; particles walk one channel (separate
    // passes); the patches of a surface-voxel sensor only.
    // Its own keys, and volpath's and printpt's for its camera side.
    static std::vector<ParameterInfo> parameters();
    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) { return refusalWithoutReentry("lighttrace", settings); }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);

    // printpt's census, then (hybrid) the pixels whose walks run with a
    // control go to printpt.
    void preprocess(const Sensor& sensor, const std::vector<int>& channels) override;
    // Sample by sample, the block of light paths, then every pixel's camera
    // side plus what the block scored there, with the block's own estimate
    // of that score's variance. Across MPI ranks the samples go in waves of
    // one block per rank, each rank receiving every block's scores at its
    // own pixels (runtime/distributed.h): a pixel's samples are the same
    // sums in the same order as in one process. Single channel only.
    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;
    // For sample `sample` of a channel's pass, one block of light paths
    // scored into every pixel: block.score[p] (zeroed by the caller) is
    // added to pixel p's camera sample, and block.scoreSq[p], the block's
    // own estimate of that score's variance, goes with it.
    void scoreLightBlock(int channel, uint32_t sample, LightBlockScores& block, PathStats& stats) const;
    // The reflection and the unscattered light of the line's first segment
    // where the light side scores; elsewhere printpt's whole estimate
    // (patches too small for the light side, and entries where printpt's
    // walks run with a control, which is nearly exact there).
    ChannelSample cameraSide(size_t pixel, Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                             PathStats& stats) const;
    // The light side scores into pixels whose patch is at least this
    // fraction of the voxel's cross section along the patch's normal:
    // smaller ones (slivers of triangles the cut gave to a voxel) would take
    // 1 / area of every score that lands under them, rare and large. Empty
    // patches (voxels the mesh does not cross) are printpt's along the
    // sensor's ray.
    static constexpr float kMinPatchFraction = 0.25f;
    // Pixels the light side leaves to printpt, in a channel.
    size_t cameraOnlyPixels(int channel) const;
    // A block's particles are cut into this many parts, each traced by one
    // thread into a tally of its own (a double score and a float square a
    // pixel) and added in part order: the same bits whatever the threads.
    static constexpr size_t kBlockParts = 16;
    // The threads a block is traced with, and the most tallies alive at once.
    static size_t blockWorkers();
    static size_t mostTalliesAlive();

private:
    // One part of a block's particles, traced by one thread: their scores
    // per pixel, and per pixel the sum of each particle's squared score
    // (float: a variance needs no more), for which the current particle's
    // scores are kept until it ends. Held for the pixels [firstPixel,
    // firstPixel + score.size()) the part's particles have reached so far: they score
    // near where they enter, and a part's entries are a run of pixels in
    // z, y, x order, so on a large model a window of the sensor holds them.
    struct ParticleTally {
        explicit ParticleTally(size_t pixels) : sensorPixels(pixels) {}
        size_t sensorPixels;
        size_t firstPixel = 0;
        std::vector<double> score;
        std::vector<float> scoreSq;
        std::vector<std::pair<uint32_t, double>> particle;
        void add(uint32_t pixel, double value) {
            if (pixel < firstPixel || pixel >= firstPixel + score.size()) reach(pixel);
            score[pixel - firstPixel] += value;
            particle.emplace_back(pixel, value);
        }
        // Widens the window to hold the pixel.
        void reach(uint32_t pixel);
        void endParticle();
    };
    // Sets nearLitPixels_ from lightServes_.
    void decideEmissionShares();
    // One particle's walk from the environment through `entry`, scoring
    // into the tally with its starting weight.
    void traceParticle(int channel, const SurfaceHit& entry, double weight, LabelMedium::Tracker& medium, Rng& rng,
                       ParticleTally& tally, PathStats& stats) const;

    const Scene& scene_;
    const SurfaceVoxelSensor& sensor_;
    const SurfacePatches& patches_;
    LightTraceOptions options_;
    VolPathOptions volpathOptions_;
    VolPath volpath_;  // beyond the far end of a line's first segment
    PrintPt printpt_;
    Majorants majorants_;
    uint64_t lightSeed_;
    RGB leastSigmaT_;  // per channel, of the labels the grid holds
    // The prisms at depths lineDepth / 8, / 4, / 2 and lineDepth: a
    // collision queries the shallowest that holds every line its roulette
    // keeps (shallow prisms overlap less).
    std::vector<std::unique_ptr<PrismIndex>> prismLevels_;
    MeshPointSampler entries_;  // where particles enter
    // Per channel and pixel: whether the light side scores into it (bytes:
    // prepare writes them from several threads).
    std::array<std::vector<uint8_t>, 3> lightServes_;
    // Per channel and pixel: whether its patch is near the pixels the light
    // side scores into (its brick or a neighbour holds one). Its share of
    // particlesPerPixel per block (stratified entries) is 1 there and
    // kFarEmissionShare elsewhere (emissionShare).
    std::array<std::vector<uint8_t>, 3> nearLitPixels_;
    float emissionShare(int channel, size_t pixel) const;
    RGB trackSpacing_mm_{};  // per channel (Scoring::Tracks)
};

}  // namespace pl
