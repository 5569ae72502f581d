// printlight: predicts the appearance of full-colour 3D prints.
#include <cstdio>
#include <cstring>

#include "apps/code_fingerprint.h"
#include "apps/commands.h"
#include "core/input_error.h"
#include "runtime/distributed.h"
#include "runtime/interrupt.h"

namespace pl {

const std::vector<Command>& commands() {
    static const std::vector<Command> table = {
        {"render", "SCENE.json", "the scene file (docs/scene-format.md)",
         "renders a scene: OUT.exr, OUT.png and, for the surface-voxel sensor, OUT.vdb", renderCommand},
        {"prepare", "MODEL", "a .gltf, .glb, .obj, .stl, .ply or .3mf model",
         "voxelises a textured mesh into labels, sdf and normal grids", prepareCommand},
        {"optimize", "SCENE.json", "the scene file of the object to print",
         "compensation loop on the surface shell: CIEDE2000 per iteration, PREFIX.csv, PREFIX_labels.vdb",
         optimizeCommand},
        {"predict", "SCENE.json", "the scene file",
         "runs the prediction API like an optimisation loop and reports its overheads", predictCommand},
        {"bench", "SCENE.json", "the scene file (none with --limit)",
         "error against run time of estimator configurations (PREFIX.md/.csv/.svg)", benchCommand},
        {"batch", "MANIFEST.json", "the manifest of scenes",
         "renders every scene of a manifest; with --compare, checks each against stored results", batchCommand},
        {"stability", "", "", "numerical stability suite (stiff and extreme cases); writes a report",
         stabilityCommand},
        {"report", "MODEL.glb", "glTF binaries: a prediction (render's OUT.glb), a target, an error map",
         "a self-contained HTML page: the models on rotating views, an optimisation's history", reportCommand},
        {"learned-data", "SCENE.json", "a scene whose sensor is surface_voxels with the patch footprint",
         "the learned predictor's training rows from a render (scripts/train_learned.py)", learnedDataCommand},
        {"characterise", "MATERIALS.json", "a material table (docs/formats.md)",
         "the printer's colours: halftoned mixtures rendered, for optimize's gamut (MATERIALS.gamut.json)",
         characteriseCommand},
        {"info", "VOLUME", "a label grid (.vdb, .bin, .gz, .vol)", "describes a label grid", infoCommand},
    };
    return table;
}

const Command& commandNamed(const std::string& name) {
    for (const Command& c : commands())
        if (name == c.name) return c;
    throw UsageError("unknown command '" + name + "' (see printlight --help)");
}

}  // namespace pl

namespace {

void printHelp(FILE* to) {
    std::fprintf(to, "usage: printlight COMMAND [options]   (printlight COMMAND --help: its options)\ncommands:\n");
    for (const pl::Command& c : pl::commands()) {
        std::string head = std::string(c.name) + (*c.operands ? std::string(" ") + c.operands : "");
        std::fprintf(to, "  %-24s %s\n", head.c_str(), c.summary);
    }
    std::fprintf(to, "  %-24s %s\n  %-24s %s\n", "--version", "the version and the code's fingerprint", "--help",
                 "this list");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        printHelp(stderr);
        return 2;
    }
    const std::string command = argv[1];
    if (command == "-h" || command == "--help") {
        printHelp(stdout);
        return 0;
    }
    if (command == "--version") {
        std::printf("printlight %s (code %s%s)\n", PRINTLIGHT_VERSION, pl::codeFingerprint().c_str(),
                    pl::Distributed::enabled() ? ", with MPI" : "");
        return 0;
    }
    std::vector<std::string> args(argv + 2, argv + argc);
    pl::Distributed distributed(&argc, &argv);
    pl::installInterruptHandler();
    try {
        return pl::commandNamed(command).run(args);
    } catch (const pl::HelpRequested& help) {
        std::fputs(help.text.c_str(), stdout);
        return 0;
    } catch (const pl::Interrupted&) {
        if (pl::Distributed::rank() != 0) return 130;
        std::fprintf(stderr, "\nprintlight: interrupted; nothing written\n");
        return 130;
    } catch (const pl::UsageError& e) {
        if (pl::Distributed::rank() != 0) return 2;  // every rank has it: one line, from rank 0
        const std::string hint = " (see printlight " + command + " --help)";
        std::fprintf(stderr, "printlight: %s%s\n", e.what(), e.message.find("--help") == std::string::npos ? hint.c_str() : "");
        return 2;
    } catch (const std::exception& e) {
        if (pl::Distributed::rank() != 0) return 1;  // failures reach rank 0 (runOnEveryRank)
        std::fprintf(stderr, "printlight: error: %s\n", e.what());
        return 1;
    }
}
