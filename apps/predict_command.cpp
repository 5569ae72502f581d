// printlight predict: runs the prediction API the way an optimisation loop
// does, N iterations that each relabel K random surface voxels, and reports
// how the time of an iteration splits between the label update (grid,
// majorants, sensor check) and path tracing.

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "api/predictor.h"
#include "apps/arguments.h"
#include "apps/command_options.h"
#include "runtime/distributed.h"
#include "runtime/progress.h"
#include "core/rng.h"
#include "render/scene_io.h"

namespace pl {

int predictCommand(const std::vector<std::string>& argv) {
    Arguments args("predict", argv,
                   {{"--iterations", "N", "loop iterations (default 5)"},
                    {"--changes", "K", "surface voxels relabelled per iteration (default 1000)"},
                    kSppOption, kSeedOption, kThreadsOption, kChannelOption});
    if (args.positional().size() != 1) throw UsageError("predict needs exactly one SCENE.json");
    int iterations = int(args.integer("--iterations", 1, 100000).value_or(5));
    int changesPerIteration = int(args.integer("--changes", 0, 1 << 24).value_or(1000));
    ThreadLimit threadLimit(args);

    auto t0 = std::chrono::steady_clock::now();
    SceneDescription desc = parseScene(args.positional()[0]);
    applyRenderOptions(args, desc.render);
    std::unique_ptr<Predictor> predictor;  // on every rank, or none (rank 0 says why)
    runOnEveryRank([&] { predictor = std::make_unique<Predictor>(desc, desc.render); });
    // Across MPI ranks every rank makes the same changes and renders its
    // share of each prediction; rank 0 speaks.
    predictor->setAcrossRanks(Distributed::ranks() > 1);
    const bool speaks = Distributed::rank() == 0;
    if (speaks) std::printf("predict: loaded in %.2f s: %zu surface voxels, %s, %u spp\n", secondsSince(t0),
                predictor->surfaceVoxelCount(), predictor->settings().integrator.c_str(), predictor->settings().spp);

    // The labels the relabelling draws from: those already on the surface.
    SurfacePrediction p = predictor->predict();
    std::vector<Label> palette;
    for (const Vec3i& v : p.voxels) {
        Label l = predictor->labels().label(v);
        if (std::find(palette.begin(), palette.end(), l) == palette.end()) palette.push_back(l);
    }
    Rng rng = Rng::forPath(predictor->settings().seed, 0, 0, 99);
    double update = 0, renderTime = 0;
    if (speaks) std::printf("iteration,update_s,render_s,update_share\n");
    for (int it = 0; it < iterations; ++it) {
        std::vector<LabelGrid::Change> changes;
        for (int k = 0; k < changesPerIteration; ++k) {
            const Vec3i& v = p.voxels[std::min(p.voxels.size() - 1, size_t(rng.uniform() * p.voxels.size()))];
            changes.push_back({v, palette[std::min(palette.size() - 1, size_t(rng.uniform() * palette.size()))]});
        }
        predictor->settings().seed += 1;
        predictor->changeLabels(changes);
        p = predictor->predict();
        double total = p.updateSeconds + p.renderSeconds;
        if (speaks) std::printf("%d,%.4f,%.4f,%.4f\n", it + 1, p.updateSeconds, p.renderSeconds, p.updateSeconds / total);
        update += p.updateSeconds;
        renderTime += p.renderSeconds;
    }
    if (speaks)
        std::printf("predict: %d iterations: update %.3f s, render %.3f s: update is %.2f %% of an iteration\n", iterations,
                update, renderTime, 100.0 * update / (update + renderTime));
    return 0;
}

}  // namespace pl
