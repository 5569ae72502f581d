// printlight bench's measurement: each configuration renders at each time
// budget (seconds; the spp is chosen from a 1-spp calibration run) and is
// compared with a reference (compare/render_error.h) or, under
// --self-variance, with its own variance estimate: the expected MSE of an
// unbiased estimator, estimated per pixel from the samples themselves
// (stderr^2, at least kMinSelfSpp samples; with hero channels, which go
// round groups of three samples, at least two groups). Cheap for large
// scenes; it cannot see bias (the tests and the reference mode do) and it
// underestimates heavy-tailed estimators at few samples. Its relative MSE
// divides each pixel's variance by one squared mean for all renders of
// the run (their means pooled, weighted by 1 / MSE), not by each render's
// own.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "apps/arguments.h"
#include "apps/bench_configurations.h"
#include "compare/surface_colour_error.h"
#include "io/image_io.h"
#include "render/render.h"

namespace pl {

// Self-variance renders at least this many samples, unless --spp says
// otherwise (>= 2: the sample variance is unbiased from two samples on).
constexpr uint32_t kMinSelfSpp = 4;

// What the errors are measured against and at which budgets.
struct Measurement {
    std::optional<std::string> referenceFile;  // none: self-variance
    RadianceImage reference;
    double referenceVariance = 0;  // its mean squared standard error per pixel channel
    std::vector<double> budgets_s;  // each render's time budget
    double target = 0.02;          // the whole-object median relative error (timeToTarget)
    bool self() const { return !referenceFile; }
};

// From --reference or --self-variance, --budgets and
// --target-relative-error; the reference must fit the sensor's image.
Measurement measurementOf(const Arguments& args, const Sensor& sensor);

// One render of one configuration at one budget.
struct BenchRow {
    std::string config;
    double budget, seconds;
    uint32_t spp;
    RGB rmseChannel;
    double rmse, relMse, mseTime;
    RGB passSeconds;  // per channel (separate passes; zero for one pass)
    double medianRelativeError = 0, secondsToTarget = 0;  // whole-object quality (timeToTarget)
    double eventsPerSecondPerCore = 0;  // scattering events over wall time and threads
    // Against a reference on the surface-voxel sensor: CIEDE2000 of the
    // reflectance (compare/surface_colour_error.h); none otherwise.
    std::optional<SurfaceColourError> colour;
    RGB reflectanceBias{0, 0, 0};  // mean of (render - reference) reflectance over the surface voxels
    double withinTwoErrors = 0;    // SurfaceReflectances::withinTwoErrors
};

// A configuration's CIEDE2000 per surface voxel at its last budget, and
// where each voxel is in the reference's image (the atlas).
struct VoxelErrorMap {
    std::string config;
    std::vector<float> deltaE;
    std::vector<int64_t> imageIndex;
};

// Every configuration at every budget: a row each (on rank 0), and with
// self-variance each render's film, kept until all are done for the
// relative MSE (one denominator for all renders); per configuration, its
// per-voxel CIEDE2000 (surface sensor, reference).
struct Measured {
    std::vector<BenchRow> rows;
    std::vector<Film> selfFilms;
    std::vector<VoxelErrorMap> errorMaps;
};

// cores: threads over all ranks. Across ranks every render is split over
// them; only rank 0 (speaks) measures.
Measured measure(const Scene& scene, const Sensor& sensor, const ChosenConfigurations& chosen, const Measurement& m,
                 const Arguments& args, int cores, bool acrossRanks, bool speaks);

// Self-variance over several renders: each row's relative MSE redone over
// one denominator for all (pooledMeanSquares).
void poolRelativeMse(Measured& measured);

}  // namespace pl
