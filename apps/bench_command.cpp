// printlight bench: error against run time (docs/performance.md, "What
// bench does").
//   printlight bench SCENE.json --make-reference REF.exr [--spp N] [--integrator I]
//   printlight bench SCENE.json --reference REF.exr [--budgets 1,2,4,8] [--configs a,b,...] [--out PREFIX]
//   printlight bench SCENE.json --self-variance [--budgets ...|--spp N] [--configs ...] [--out PREFIX]
//   (both: [--target-relative-error 0.02], the whole-object quality the
//   "time to" column extrapolates to: medianRelativeError, timeToTarget)
// Each configuration (apps/bench_configurations.h) renders at each time
// budget and is compared with the reference or with its own variance
// (apps/bench_measurement.h): RMSE and relative MSE over all pixels and
// channels, MSE x time (lower is better), and the equal-error speed-up
// over volpath (or, without a volpath configuration, over the first one)
// = (MSE x time)_volpath / (MSE x time)_config. Writes PREFIX.md,
// PREFIX.csv and PREFIX.svg (apps/bench_report.h).
//   printlight bench --limit [--threads N]: the limit walk's rate alone
//   (apps/limit_walk.h). Every bench run measures it too, and the tables give
//   each render's scattering events per second per core against it.
//   printlight bench SCENE.json --loop CHANGES: apps/bench_loop.h.
//   printlight bench SCENE.json --error-check 1,2,8: apps/bench_error_check.h.
//   printlight bench SCENE.json --transmittance: apps/bench_transmittance.h.
#include <cmath>
#include <cstdio>
#include <memory>

#include "apps/arguments.h"
#include "apps/bench_configurations.h"
#include "apps/bench_error_check.h"
#include "apps/bench_loop.h"
#include "apps/bench_measurement.h"
#include "apps/bench_transmittance.h"
#include "apps/bench_report.h"
#include "apps/command_options.h"
#include "apps/limit_walk.h"
#include "apps/number_text.h"
#include "io/image_io.h"
#include "io/output_file.h"
#include "render/registry.h"
#include "render/scene_io.h"
#include "runtime/distributed.h"
#include "runtime/progress.h"

namespace pl {

namespace {

// --make-reference: many samples of the trusted estimator, with their own
// RMS standard error.
void makeReference(const Scene& scene, const Sensor& sensor, RenderSettings s, const std::string& file,
                   const Arguments& args, const SceneDescription& desc, bool acrossRanks, bool speaks) {
    s.spp = uint32_t(args.integer("--spp", 1, RenderSettings::kMostSpp).value_or(256));
    s.seed = 0x5eed;
    s.showProgress = speaks && ProgressBar::stderrIsTerminal();
    refuseToOverwriteInputs(file, desc.inputFiles());
    RenderResult r = render(scene, sensor, s, acrossRanks);
    if (!speaks) return;
    RadianceImage im = filmToImage(r.film, sensor);
    im.metadata = {{"reference_spp", std::to_string(s.spp)}, {"integrator", s.integrator}};
    writeExr(im, file);
    double var = 0;
    size_t n = 0;
    for (size_t p = 0; p < r.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c, ++n) var += double(r.film.standardError(p, c)) * r.film.standardError(p, c);
    std::printf("reference %s: %s, %u spp, %.1f s; its own RMS standard error per pixel %.3g\n", file.c_str(),
                s.integrator.c_str(), s.spp, r.seconds, std::sqrt(var / double(n)));
}

// --error-check: whether the reported errors are honest at these spp.
void checkErrors(const Scene& scene, const Sensor& sensor, const ChosenConfigurations& chosen,
                 const std::string& spps, const Arguments& args, bool acrossRanks, bool speaks) {
    std::vector<uint32_t> counts;
    for (const std::string& n : splitList(spps)) {
        long v = 0;
        try {
            v = std::stol(n);
        } catch (const std::exception&) {
        }
        if (v < 1 || v > long(RenderSettings::kMostSpp)) throw UsageError("--error-check takes sample counts, e.g. 1,2,8");
        counts.push_back(uint32_t(v));
    }
    std::vector<std::pair<std::string, RenderSettings>> configs;
    for (const std::string& n : chosen.names) configs.emplace_back(n, chosen.settings.at(n));
    const uint64_t seed = uint64_t(args.integer("--seed", 0, RenderSettings::kMostSeed - 1).value_or(11));
    const std::string md = errorCheckTable(scene, sensor, configs, counts, seed, acrossRanks);
    if (!speaks) return;
    writeTextFile(args.value("--out").value_or("bench") + ".md", md);
    std::fputs(md.c_str(), stdout);
}

}  // namespace

int benchCommand(const std::vector<std::string>& argv) {
    Arguments args("bench", argv,
                   {{"--make-reference", "REF.exr", "render a reference (with --spp, default 256, and --integrator)"},
                    {"--reference", "REF.exr", "the error of each configuration against a reference"},
                    {"--self-variance", "", "the error from each render's own variance (no reference)"},
                    {"--error-check", "1,2,8", "whether the reported errors are honest at these spp (two seeds each)"},
                    kSeedOption,
                    {"--budgets", "1,2,4,...", "time budgets in seconds: each configuration renders the samples that fit"},
                    {"--configs", "A,B,...", "estimator configurations (default volpath,printpt)"},
                    kSppOption,
                    integratorOption(),
                    {"--out", "PREFIX",
                     "tables and plot: PREFIX.md, .csv, .svg (default bench; --loop: PREFIX_loop.md, "
                     "--transmittance: PREFIX_transmittance.md)"},
                    {"--target-relative-error", "E", "the time to that median per-pixel relative error (default 0.02)"},
                    kThreadsOption,
                    {"--limit", "", "the limit walk (a lookup-free walk in an infinite medium) alone"},
                    {"--loop", "CHANGES",
                     "the optimisation loop's predictions on recorded label changes (optimize --record-changes): "
                     "noise over the footprint and seconds per iteration"},
                    {"--carry-over", "none,kept,control-variates", "with --loop: the ways of predicting (default all)"},
                    {"--transmittance", "",
                     "fixed segments' transmittance: regular tracking, ratio tracking and pins (variance x time)"}});
    ThreadLimit threads(args);
    if (args.has("--limit") && args.positional().empty()) {
        const LimitWalkRate limit = measureLimitWalk(threads.count);
        std::printf("limit walk: %s scattering events/s/core (%s events on %d thread(s) in %.2f s)\n",
                    siRate(limit.eventsPerSecondPerCore).c_str(), withThousands(limit.events).c_str(), limit.threads,
                    limit.seconds);
        return 0;
    }
    if (args.positional().size() != 1) throw UsageError("bench needs exactly one SCENE.json (or --limit alone)");
    SceneDescription desc = parseScene(args.positional()[0]);
    if (args.has("--transmittance")) {
        const Scene scene = loadScene(desc);
        const std::string md =
            transmittanceTable(scene, uint64_t(args.integer("--seed", 0, RenderSettings::kMostSeed - 1).value_or(1)));
        const std::string out = args.value("--out").value_or("bench") + "_transmittance.md";
        refuseToOverwriteInputs(out, desc.inputFiles());
        writeTextFile(out, md);
        std::fputs(md.c_str(), stdout);
        return 0;
    }
    if (auto file = args.value("--loop")) {
        const LabelChangeHistory changes = readLabelChanges(*file);
        std::vector<std::string> methods = splitList(args.value("--carry-over").value_or("none,kept,control-variates"));
        for (const std::string& m : methods)
            if (m != "none" && m != "kept" && m != "control-variates")
                throw UsageError("--carry-over takes none, kept and control-variates");
        RenderSettings loop = desc.render;
        loop.channels = {0, 1, 2};
        loop.reentry = false;
        loop.spp = uint32_t(args.integer("--spp", 1, RenderSettings::kMostSpp).value_or(2));
        if (auto name = args.value("--integrator")) chooseIntegrator(loop, *name, "--integrator");
        const std::string md = loopTable(desc, loop, changes, methods,
                                         uint64_t(args.integer("--seed", 0, RenderSettings::kMostSeed - 1).value_or(1)));
        const std::string out = args.value("--out").value_or("bench") + "_loop.md";
        refuseToOverwriteInputs(out, desc.inputFiles());
        writeTextFile(out, md);
        std::fputs(md.c_str(), stdout);
        return 0;
    }
    RenderSettings base = desc.render;
    base.channels = {0, 1, 2};
    base.reentry = false;  // surface prediction: the estimators must agree
    ChosenConfigurations chosen = chooseConfigurations(args.value("--configs").value_or("volpath,printpt"), base);
    // The reference: many samples of the trusted estimator (volpath by default).
    RenderSettings reference = base;
    chooseIntegrator(reference, args.value("--integrator").value_or("volpath"), "--integrator");
    auto makeRefPath = args.value("--make-reference");
    if (makeRefPath) chosen.needs |= sceneNeedsOf(reference);
    Scene scene;
    std::unique_ptr<Sensor> sensor;
    runOnEveryRank([&] {  // on every rank, or none (rank 0 says why)
        scene = loadScene(desc, chosen.needs);
        sensor = makeSensor(desc, scene);
    });
    // Across MPI ranks every render is split over them (each renders its
    // share of the pixels); rank 0 measures, prints and writes. Times are
    // rank 0's wall times; events/s/core count every rank's threads.
    const bool acrossRanks = Distributed::ranks() > 1, speaks = Distributed::rank() == 0;
    const int cores = threads.count * Distributed::ranks();
    if (makeRefPath) {
        makeReference(scene, *sensor, reference, *makeRefPath, args, desc, acrossRanks, speaks);
        return 0;
    }
    if (auto spps = args.value("--error-check")) {
        checkErrors(scene, *sensor, chosen, *spps, args, acrossRanks, speaks);
        return 0;
    }
    const Measurement m = measurementOf(args, *sensor);
    // The floor every configuration's event rate is read against, in this
    // process and run.
    const LimitWalkRate limit = measureLimitWalk(threads.count);
    if (speaks) std::fprintf(stderr, "bench: limit walk %s events/s/core\n", siRate(limit.eventsPerSecondPerCore).c_str());
    Measured measured = measure(scene, *sensor, chosen, m, args, cores, acrossRanks, speaks);
    if (!speaks) return 0;
    poolRelativeMse(measured);
    writeBenchTables(measured, m, chosen.names, desc, limit, threads.count, acrossRanks,
                     args.value("--out").value_or("bench"));
    return 0;
}

}  // namespace pl
