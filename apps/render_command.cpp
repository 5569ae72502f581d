// printlight render: scene file -> surface-radiance prediction or preview.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include "apps/arguments.h"
#include "apps/command_options.h"
#include "apps/number_text.h"
#include "core/input_error.h"
#include "io/output_file.h"
#include "render/progressive_render.h"
#include "render/registry.h"
#include "render/render_outputs.h"
#include "render/scene_io.h"
#include "runtime/distributed.h"
#include "runtime/progress.h"

namespace pl {

namespace {

// Which of printpt's controls ran (shares of the walks), and the part of
// the variance that samples share through estimated control means when
// it is over 1 %: "" where no control ran.
std::string controlSummary(const RenderResult& r) {
    const uint64_t* walks = r.stats.controlledWalks;
    if (r.stats.allControlledWalks() == 0 || r.stats.paths == 0) return "";
    auto percent = [&](uint64_t n) { return 100.0 * double(n) / double(r.stats.paths); };
    char text[192];
    int length = std::snprintf(text, sizeof text, ", controls on %.0f %% of walks (half-space %.0f %%, wedge %.0f %%, curved %.0f %%)",
                               percent(r.stats.allControlledWalks()), percent(walks[0]), percent(walks[1]),
                               percent(walks[2]));
    double shared = 0, total = 0;
    for (size_t p = 0; p < r.film.pixelCount(); ++p)
        for (int c = 0; c < kChannels; ++c) {
            shared += std::pow(double(r.film.sharedError(p, c)), 2);
            total += std::pow(double(r.film.standardError(p, c)), 2);
        }
    if (total > 0 && shared > 0.01 * total)
        std::snprintf(text + length, sizeof text - size_t(length), ", %.0f %% of the variance shared through their means",
                      100.0 * shared / total);
    return text;
}


// The scene and its settings with the command line's overrides.
SceneDescription describeRender(const Arguments& args) {
    SceneDescription desc = parseScene(args.positional()[0]);
    applyRenderOptions(args, desc.render);
    applyRenderOption(args, "--time", "time_budget_s", desc.render);
    applyRenderOption(args, "--target-error", "target_relative_error", desc.render);
    // The scene's 0 (none) is no stop on the command line, where these set one.
    if (args.has("--time") && !(desc.render.timeBudget_s > 0)) throw UsageError("--time must be positive (seconds)");
    if (args.has("--target-error") && !(desc.render.targetRelativeError > 0))
        throw UsageError("--target-error must be positive");
    if ((args.has("--time") || args.has("--target-error")) && !args.has("--spp"))
        desc.render.spp = uint32_t(RenderSettings::kMostSpp);  // the budget or the target decides
    if (auto o = args.value("-o")) desc.output = *o;
    return desc;
}

// What was loaded and how it will be rendered, on stderr.
void describeSetup(const SceneDescription& desc, const Scene& scene, const Sensor& sensor, int threads,
                   double setupSeconds) {
    const GridFrame& f = scene.medium->frame();
    std::fprintf(stderr,
                 "printlight: %s: %zu triangles, grid %dx%dx%d, sensor %s with %s pixels, %s, "
                 "%u spp, %zu channel pass(es) (%s), %d thread(s), set-up %.2f s\n",
                 desc.sceneFile.string().c_str(), scene.geometry->mesh().triangleCount(), f.resolution.x,
                 f.resolution.y, f.resolution.z, desc.sensor.type.c_str(), withThousands(sensor.pixelCount()).c_str(),
                 desc.render.integrator.c_str(), desc.render.spp,
                 rendersChannelsInOnePass(desc.render) ? size_t(1) : desc.render.channels.size(),
                 channelSamplingName(desc.render.channelSampling), threads, setupSeconds);
    if (scene.homogeneousCore)
        std::fprintf(stderr, "printlight: homogeneous core deeper than %g mm: %s voxels, %s of them relabelled\n",
                     desc.homogeneousCoreDepth_mm, withThousands(scene.homogeneousCore->coreVoxels).c_str(),
                     withThousands(scene.homogeneousCore->changedVoxels).c_str());
    if (auto* voxels = dynamic_cast<const SurfaceVoxelSensor*>(&sensor); voxels && voxels->patches()) {
        const SurfacePatches& p = *voxels->patches();
        std::fprintf(stderr, "printlight: patch footprint: %s voxels with no patch (measured along their ray), %.4g mm^2 of "
                             "surface given to none\n",
                     withThousands(p.emptyPatches()).c_str(), p.unassignedArea_mm2());
    }
}

// ", N MPI ranks (communicating a-b % of the time)".
std::string ranksSummary(const RenderResult& result, int ranks) {
    std::string text = ", " + std::to_string(ranks) + " MPI ranks";
    if (!result.communicationShare.empty()) {
        const auto [least, most] = std::minmax_element(result.communicationShare.begin(), result.communicationShare.end());
        char line[96];
        std::snprintf(line, sizeof line, " (communicating %.0f-%.0f %% of the time)", 100 * *least, 100 * *most);
        text += line;
    }
    return text;
}

// Paths trapped or leaked, if any.
void warnAboutPaths(const PathStats& stats) {
    if (stats.trapped)
        std::fprintf(stderr, "printlight: warning: %s paths were trapped (over %lld boundary events without scattering)\n",
                     withThousands(stats.trapped).c_str(), (long long)kMaxBoundaryBounces);
    if (stats.leaks)
        std::fprintf(stderr,
                     "printlight: warning: %s of %s paths (%.1e) escaped through the mesh (numerical leaks: a "
                     "collision within round-off of an edge; docs/reliability.md)\n",
                     withThousands(stats.leaks).c_str(), withThousands(stats.paths).c_str(),
                     double(stats.leaks) / double(std::max<uint64_t>(stats.paths, 1)));
}

// The film's means and errors per surface voxel.
PixelResults surfaceResultsOf(const Film& film) {
    PixelResults results;
    results.mean.resize(film.pixelCount());
    results.standardError.resize(film.pixelCount());
    for (size_t p = 0; p < film.pixelCount(); ++p) {
        results.mean[p] = film.meanRGB(p);
        results.standardError[p] = film.standardErrorRGB(p);
    }
    return results;
}

// The render's result on rank 0, as its images are written: a progressive
// render writes them after every round, a render in one go once its film
// is let go (the caller's).
struct Rendered {
    RenderResult result;
    uint32_t spp = 0;
    std::string runNote;  // for the summary: what stopped a progressive render, the MPI ranks
    std::optional<RadianceImage> image;  // not yet written
};

}  // namespace

int renderCommand(const std::vector<std::string>& argv) {
    Arguments args("render", argv,
                   {kSppOption, kSeedOption, kThreadsOption, kChannelOption, kChannelSamplingOption, integratorOption(),
                    {"--time", "SECONDS", "stop at this wall time; the images refine after each round"},
                    {"--target-error", "E", "stop at this median per-pixel relative standard error (e.g. 0.05)"},
                    {"-o,--output", "OUT", "output path without extension (overrides the scene's)"}, kQuietOption});
    if (args.positional().size() != 1) throw UsageError("render needs exactly one SCENE.json");
    auto t0 = std::chrono::steady_clock::now();
    SceneDescription desc = describeRender(args);
    ThreadLimit threads(args);
    // Outputs: never over an input, never partial (see io/output_file.h).
    RenderOutputs outputs(desc.output, desc.sensor);
    for (const auto& o : outputs.files()) refuseToOverwriteInputs(o, desc.inputFiles());

    // Under MPI only rank 0 speaks and writes. Every rank loads the scene;
    // if any cannot, all stop and rank 0 says why.
    const int rank = Distributed::rank(), ranks = Distributed::ranks();
    const bool quiet = args.has("--quiet") || rank != 0;
    Scene scene;
    std::unique_ptr<Sensor> sensor;
    runOnEveryRank([&] {
        scene = loadScene(desc, sceneNeedsOf(desc.render));
        sensor = makeSensor(desc, scene);
    });
    if (sceneNeedsOf(desc.render).surfaceFields && !scene.medium->hasSurfaceFields() && rank == 0)
        std::fprintf(stderr, "printlight: warning: %s has no sdf/normal grids: next-event estimation is off\n",
                     desc.labelsFile.string().c_str());
    if (!quiet) describeSetup(desc, scene, *sensor, threads.count, secondsSince(t0));

    desc.render.showProgress = !quiet && ProgressBar::stderrIsTerminal();
    auto imageOf = [&](const RenderResult& r, uint32_t spp) {
        RadianceImage image = filmToImage(r.film, *sensor);
        image.metadata = renderMetadata(desc, spp);
        return image;
    };
    // Across MPI ranks each renders its share of the pixels and rank 0
    // gathers, writes and speaks.
    const bool acrossRanks = ranks > 1;
    Rendered done;
    if (desc.render.timeBudget_s > 0 || desc.render.targetRelativeError > 0) {
        auto writeRound = [&](const RenderResult& r, uint32_t spp) { outputs.writeImage(imageOf(r, spp)); };
        ProgressiveRender p = renderProgressively(scene, *sensor, desc.render, writeRound, acrossRanks);
        if (rank != 0) return 0;
        done.result = std::move(p.result);
        done.spp = p.spp;
        char line[160];
        std::snprintf(line, sizeof line, ", stopped by %s at %u spp, median relative error %.3g", p.stoppedBy.c_str(),
                      p.spp, p.medianRelativeError);
        done.runNote = line;
    } else {
        done.result = render(scene, *sensor, desc.render, acrossRanks);
        if (rank != 0) return 0;
        done.spp = desc.render.spp;
        done.image = imageOf(done.result, done.spp);
    }
    RenderResult& result = done.result;
    if (acrossRanks) done.runNote += ranksSummary(result, ranks);
    const std::string controls = controlSummary(result);  // before the film is let go (below)
    // The film's means and errors for the surface's outputs; then the film
    // is let go before the image, the result grid and the prediction on
    // the model are written.
    PixelResults results;
    if (outputs.surface()) results = surfaceResultsOf(result.film);
    result.film = Film();
    if (done.image) outputs.writeImage(*done.image);
    done.image.reset();
    // The labels, the sensor and its patches are let go too before the
    // result grid is built (on a large object that grid is the largest
    // thing written: about 190 bytes a surface voxel).
    const size_t pixelCount = sensor->pixelCount();
    const GridFrame worldFrame = scene.worldFrame();
    std::vector<Vec3i> voxels;
    if (outputs.surface()) {
        voxels.reserve(pixelCount);
        for (const auto& px : static_cast<const SurfaceVoxelSensor&>(*sensor).pixels()) voxels.push_back(px.voxel);
    }
    sensor.reset();
    scene.medium.reset();
    scene.clearance.reset();
    if (outputs.surface()) outputs.writeSurface(scene.geometry->mesh(), worldFrame, voxels, std::move(results));
    warnAboutPaths(result.stats);

    // Summary: wall time, samples, paths per second, scattering events per second.
    const uint64_t samples = uint64_t(pixelCount) * done.spp * desc.render.channels.size();
    const double s = result.seconds;
    char balls[64] = "";
    if (result.stats.ballEvents)
        std::snprintf(balls, sizeof balls, " (%.0f %% in ball walks)",
                      100.0 * double(result.stats.ballEvents) / double(result.stats.scatterEvents));
    std::printf("render %.2f s wall (%.2f s total), %s samples (%s px x %u spp x %zu ch), "
                "%s paths/s, %s scattering events/s%s%s%s, %d thread(s) -> %s\n",
                s, secondsSince(t0), withThousands(samples).c_str(), withThousands(pixelCount).c_str(), done.spp,
                desc.render.channels.size(), siRate(result.stats.paths / s).c_str(),
                siRate(result.stats.scatterEvents / s).c_str(), balls, controls.c_str(), done.runNote.c_str(),
                threads.count, outputs.writtenText().c_str());
    return 0;
}

}  // namespace pl
