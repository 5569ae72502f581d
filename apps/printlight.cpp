// printlight: predicts the appearance of full-colour 3D prints.
#include <cstdio>
#include <cstring>

#include "apps/commands.h"
#include "runtime/interrupt.h"
#include "io/input_error.h"

namespace {
const char* kUsage =
    "usage: printlight <command> [options]\n"
    "commands:\n"
    "  render SCENE.json [--spp N] [--seed S] [--threads N] [--channel r|g|b|rgb]\n"
    "         [--channel-sampling separate|hero|spectral]\n"
    "         [--integrator volpath|printpt|lighttrace] [-o OUT] [--quiet]\n"
    "         renders a scene; writes OUT.exr, OUT.png and, for the surface-voxel sensor, OUT.vdb\n"
    "  prepare MODEL.gltf|.glb|.obj -o OUT.vdb [--voxel X,Y,Z] [--extrude-mm D] [--margin-mm M]\n"
    "          [--materials FILE] [--halftone error-diffusion|nearest] [--fill conservative|center]\n"
    "          [--color R,G,B] [--keep-colors] [--scene-out PREFIX]\n"
    "         voxelises a textured mesh into labels, sdf and normal grids\n"
    "  bench SCENE.json --make-reference REF.exr [--spp N] [--integrator volpath|printpt]\n"
    "  bench SCENE.json --reference REF.exr [--budgets 1,2,4,8] [--configs volpath,printpt,...] [--out PREFIX]\n"
    "  bench SCENE.json --self-variance [--budgets 1,2,4,8 | --spp N] [--configs ...] [--out PREFIX]\n"
    "         error against run time of estimator configurations (writes PREFIX.md/.csv/.svg);\n"
    "         [--target-relative-error 0.02]: the time to that median per-pixel relative error;\n"
    "         [--threads N]; every table has events/s/core against the limit walk\n"
    "  bench --limit [--threads N]\n"
    "         the limit walk alone: events/s/core of a lookup-free walk in an infinite medium\n"
    "  batch MANIFEST.json -o DIR [--compare STORED_DIR] [--threads N] [--seed-offset N]\n"
    "        [--max-outlier-fraction F] [--quiet]\n"
    "         renders every scene of a manifest; with --compare, checks each result against a stored\n"
    "         one (bit-identical for the same code and seed, else per-pixel t tests and a bias test); exit 1 on failure\n"
    "  stability [--quick] [-o REPORT.md] [--seed S] [--threads N]\n"
    "         numerical stability suite (stiff and extreme cases, both estimators); writes REPORT.md\n"
    "         (default docs/stability.md if ./docs exists, else stability.md); exit 1 if a case fails\n"
    "  predict SCENE.json [--iterations N] [--changes K] [--spp N] [--seed S] [--channel r|g|b|rgb] [--threads N]\n"
    "         runs the prediction API like an optimisation loop (K surface voxels relabelled per\n"
    "         iteration) and reports the share of an iteration spent outside path tracing\n"
    "  optimize SCENE.json --target MODEL.gltf|R,G,B [--iterations N] [--spp N] [--seed S] [--step X]\n"
    "           [--shell-mm D] [--score-radius R] [--no-gamut-map] [--integrator volpath|printpt]\n"
    "           [--channel-sampling separate|hero|spectral] [--threads N] [-o PREFIX]\n"
    "         compensation loop on the surface shell: CIEDE2000 per iteration, PREFIX.csv, PREFIX_labels.vdb\n"
    "  info VOLUME [--void-label N]\n"
    "         describes a label grid (.vdb, .bin, .gz, .vol)\n";
}

int main(int argc, char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help")) {
        std::fputs(kUsage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    std::string command = argv[1];
    std::vector<std::string> args(argv + 2, argv + argc);
    pl::installInterruptHandler();
    try {
        if (command == "render") return pl::renderCommand(args);
        if (command == "info") return pl::infoCommand(args);
        if (command == "prepare") return pl::prepareCommand(args);
        if (command == "bench") return pl::benchCommand(args);
        if (command == "batch") return pl::batchCommand(args);
        if (command == "stability") return pl::stabilityCommand(args);
        if (command == "predict") return pl::predictCommand(args);
        if (command == "optimize") return pl::optimizeCommand(args);
        throw pl::UsageError("unknown command '" + command + "'");
    } catch (const pl::Interrupted&) {
        std::fprintf(stderr, "\nprintlight: interrupted; nothing written\n");
        return 130;
    } catch (const pl::UsageError& e) {
        std::fprintf(stderr, "printlight: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "printlight: error: %s\n", e.what());
        return 1;
    }
}
