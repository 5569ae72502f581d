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
#include "runtime/distributed.h"
#include "runtime/progress.h"
#include "render/registry.h"
#include "io/grid_io.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "core/input_error.h"
#include "io/output_file.h"
#include "render/progressive_render.h"
#include "render/scene_io.h"

namespace pl {

namespace {

std::filesystem::path outputBase(std::filesystem::path p) {
    std::string ext = p.extension().string();
    if (ext == ".exr" || ext == ".png" || ext == ".vdb" || ext == ".glb") p.replace_extension();
    return p;
}

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

}  // namespace

int renderCommand(const std::vector<std::string>& argv) {
    Arguments args("render", argv,
                   {kSppOption, kSeedOption, kThreadsOption, kChannelOption, kChannelSamplingOption, integratorOption(),
                    {"--time", "SECONDS", "stop at this wall time; the images refine after each round"},
                    {"--target-error", "E", "stop at this median per-pixel relative standard error (e.g. 0.05)"},
                    {"-o,--output", "OUT", "output path without extension (overrides the scene's)"}, kQuietOption});
    if (args.positional().size() != 1) throw UsageError("render needs exactly one SCENE.json");
    auto t0 = std::chrono::steady_clock::now();

    SceneDescription desc = parseScene(args.positional()[0]);
    applyRenderOptions(args, desc.render);
    auto positiveNumber = [&](const char* option) {
        const std::optional<double> x = args.number(option);
        if (x && !(*x > 0 && std::isfinite(*x))) throw UsageError(std::string(option) + " takes a positive number");
        return x;
    };
    if (auto t = positiveNumber("--time")) desc.render.timeBudget_s = *t;
    if (auto e = positiveNumber("--target-error")) desc.render.targetRelativeError = *e;
    const bool progressive = desc.render.timeBudget_s > 0 || desc.render.targetRelativeError > 0;
    if ((args.has("--time") || args.has("--target-error")) && !args.has("--spp"))
        desc.render.spp = uint32_t(RenderSettings::kMostSpp);  // the budget or the target decides
    ThreadLimit threads(args);
    if (auto o = args.value("-o")) desc.output = *o;

    // Outputs: never over an input, never partial (see io/output_file.h).
    std::filesystem::path base = outputBase(desc.output);
    bool surface = desc.sensor.type == "surface_voxels";
    std::vector<std::filesystem::path> outputs = {base.string() + ".exr", base.string() + ".png"};
    if (surface) {
        outputs.push_back(base.string() + ".vdb");
        outputs.push_back(base.string() + ".glb");
    }
    for (const auto& o : outputs) refuseToOverwriteInputs(o, desc.inputFiles());

    // Under MPI only rank 0 speaks and writes.
    const int rank = Distributed::rank(), ranks = Distributed::ranks();
    bool quiet = args.has("--quiet") || rank != 0;
    const RenderSettings& rs = desc.render;
    // Every rank loads the scene; if any cannot, all stop and rank 0 says why.
    Scene scene;
    std::unique_ptr<Sensor> sensor;
    runOnEveryRank([&] {
        scene = loadScene(desc, sceneNeedsOf(rs));
        sensor = makeSensor(desc, scene);
    });
    if (sceneNeedsOf(rs).surfaceFields && !scene.medium->hasSurfaceFields() && rank == 0)
        std::fprintf(stderr, "printlight: warning: %s has no sdf/normal grids: next-event estimation is off\n",
                     desc.labelsFile.string().c_str());
    double setupSeconds = secondsSince(t0);
    const GridFrame& f = scene.medium->frame();
    if (!quiet)
        std::fprintf(stderr,
                     "printlight: %s: %zu triangles, grid %dx%dx%d, sensor %s with %s pixels, %s, "
                     "%u spp, %zu channel pass(es) (%s), %d thread(s), set-up %.2f s\n",
                     desc.sceneFile.string().c_str(), scene.geometry->mesh().triangleCount(),
                     f.resolution.x, f.resolution.y, f.resolution.z, desc.sensor.type.c_str(),
                     withThousands(sensor->pixelCount()).c_str(), desc.render.integrator.c_str(), desc.render.spp,
                     rendersChannelsInOnePass(desc.render) ? size_t(1) : desc.render.channels.size(),
                     channelSamplingName(desc.render.channelSampling), threads.count, setupSeconds);
    if (scene.homogeneousCore && !quiet)
        std::fprintf(stderr, "printlight: homogeneous core deeper than %g mm: %s voxels, %s of them relabelled\n",
                     desc.homogeneousCoreDepth_mm, withThousands(scene.homogeneousCore->coreVoxels).c_str(),
                     withThousands(scene.homogeneousCore->changedVoxels).c_str());
    if (auto* voxels = dynamic_cast<const SurfaceVoxelSensor*>(sensor.get()); voxels && voxels->patches() && !quiet) {
        const SurfacePatches& p = *voxels->patches();
        std::fprintf(stderr, "printlight: patch footprint: %s voxels with no patch (measured along their ray), %.4g mm^2 of "
                             "surface given to none\n",
                     withThousands(p.emptyPatches()).c_str(), p.unassignedArea_mm2());
    }

    desc.render.showProgress = !quiet && ProgressBar::stderrIsTerminal();
    // The images, with how they were made; written after each round of a
    // progressive render too (each write complete: io/output_file.h).
    auto imageOf = [&](const RenderResult& r, uint32_t spp) {
        RadianceImage image = filmToImage(r.film, *sensor);
        image.metadata = {{"scene", desc.sceneFile.string()},  {"integrator", desc.render.integrator},
                          {"sensor", desc.sensor.type},        {"spp", std::to_string(spp)},
                          {"seed", std::to_string(desc.render.seed)}, {"channels", channelNames(desc.render.channels)},
                          {"channel_sampling", channelSamplingName(desc.render.channelSampling)}};
        return image;
    };
    auto writeImage = [&](const RadianceImage& image) {
        writeExr(image, outputs[0]);
        writePng(image, outputs[1]);
    };
    auto writeImages = [&](const RenderResult& r, uint32_t spp) { writeImage(imageOf(r, spp)); };
    // Across MPI ranks each renders its share of the pixels and rank 0
    // gathers, writes and speaks.
    const bool acrossRanks = ranks > 1;
    RenderResult result;
    uint32_t sppDone = desc.render.spp;
    std::string stopped;
    std::optional<RadianceImage> image;  // written once the film is let go
    if (progressive) {
        ProgressiveRender p = renderProgressively(scene, *sensor, desc.render, writeImages, acrossRanks);
        if (rank != 0) return 0;
        result = std::move(p.result);
        sppDone = p.spp;
        char line[160];
        std::snprintf(line, sizeof line, ", stopped by %s at %u spp, median relative error %.3g", p.stoppedBy.c_str(),
                      p.spp, p.medianRelativeError);
        stopped = line;
    } else {
        result = render(scene, *sensor, desc.render, acrossRanks);
        if (rank != 0) return 0;
        image = imageOf(result, sppDone);
    }
    if (acrossRanks) {
        stopped += ", " + std::to_string(ranks) + " MPI ranks";
        if (!result.communicationShare.empty()) {
            const auto [least, most] =
                std::minmax_element(result.communicationShare.begin(), result.communicationShare.end());
            char line[96];
            std::snprintf(line, sizeof line, " (communicating %.0f-%.0f %% of the time)", 100 * *least, 100 * *most);
            stopped += line;
        }
    }
    const std::string controls = controlSummary(result);  // before the film is let go (below)
    // The film's means and errors for the surface's outputs; then the film
    // is let go before the image, the result grid and the prediction on
    // the model are written.
    PixelResults results;
    if (surface) {
        results.mean.resize(sensor->pixelCount());
        results.standardError.resize(sensor->pixelCount());
        for (size_t p = 0; p < sensor->pixelCount(); ++p) {
            results.mean[p] = result.film.meanRGB(p);
            results.standardError[p] = result.film.standardErrorRGB(p);
        }
    }
    result.film = Film();
    if (image) writeImage(*image);
    image.reset();
    // The labels, the sensor and its patches are let go too before the
    // result grid is built (on a large object that grid is the largest
    // thing written: about 190 bytes a surface voxel).
    const size_t pixelCount = sensor->pixelCount();
    const GridFrame worldFrame = scene.worldFrame();
    std::vector<Vec3i> voxels;
    if (surface) {
        voxels.reserve(pixelCount);
        for (const auto& px : static_cast<const SurfaceVoxelSensor&>(*sensor).pixels()) voxels.push_back(px.voxel);
    }
    sensor.reset();
    scene.medium.reset();
    scene.clearance.reset();
    if (surface) {
        writeSurfaceResultVdb(worldFrame, voxels, results, outputs[2]);
        results.standardError = {};
        try {
            writePredictionGlb(scene.geometry->mesh(), worldFrame, voxels, results.mean, outputs[3]);
        } catch (const GlbTooLarge& e) {
            std::fprintf(stderr, "printlight: warning: %s\n", e.what());
            outputs.pop_back();
        }
    }
    if (result.stats.trapped)
        std::fprintf(stderr, "printlight: warning: %s paths were trapped (over %lld boundary events without scattering)\n",
                     withThousands(result.stats.trapped).c_str(), (long long)kMaxBoundaryBounces);
    if (result.stats.leaks)
        std::fprintf(stderr,
                     "printlight: warning: %s of %s paths (%.1e) escaped through the mesh (numerical leaks: a "
                     "collision within round-off of an edge; docs/reliability.md)\n",
                     withThousands(result.stats.leaks).c_str(), withThousands(result.stats.paths).c_str(),
                     double(result.stats.leaks) / double(std::max<uint64_t>(result.stats.paths, 1)));

    // Summary: wall time, samples, paths per second, scattering events per second.
    uint64_t samples = uint64_t(pixelCount) * sppDone * desc.render.channels.size();
    double s = result.seconds;
    char balls[64] = "";
    if (result.stats.ballEvents)
        std::snprintf(balls, sizeof balls, " (%.0f %% in ball walks)",
                      100.0 * double(result.stats.ballEvents) / double(result.stats.scatterEvents));
    std::printf("render %.2f s wall (%.2f s total), %s samples (%s px x %u spp x %zu ch), "
                "%s paths/s, %s scattering events/s%s%s%s, %d thread(s) -> %s\n",
                s, secondsSince(t0), withThousands(samples).c_str(),
                withThousands(pixelCount).c_str(), sppDone,
                desc.render.channels.size(), siRate(result.stats.paths / s).c_str(),
                siRate(result.stats.scatterEvents / s).c_str(), balls, controls.c_str(), stopped.c_str(),
                threads.count, (base.string() + (outputs.size() == 4 ? ".{exr,png,vdb,glb}" : surface ? ".{exr,png,vdb}" : ".{exr,png}")).c_str());
    return 0;
}

}  // namespace pl
