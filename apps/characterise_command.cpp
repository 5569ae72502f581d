// printlight characterise MATERIALS.json: the printer's colours, rendered
// (api/printer_characterisation.h), written beside the table as
// MATERIALS.gamut.json (or -o FILE), where optimize finds them.

#include <chrono>
#include <cstdio>

#include "api/printer_characterisation.h"
#include "apps/arguments.h"
#include "apps/command_options.h"
#include "io/materials_io.h"
#include "io/output_file.h"
#include "runtime/progress.h"

namespace pl {

int characteriseCommand(const std::vector<std::string>& argv) {
    CharacterisationSettings s;
    Arguments args("characterise", argv,
                   {{"--levels", "N", "grid step 1/N on the mixing simplex (default 8)"},
                    {"--spp", "N", "samples per measured voxel and mixture (default 8)"},
                    {"--cube-mm", "D", "the characterisation cube's side (default 6)"},
                    {"--voxel-mm", "X,Y,Z", "the printer's voxel (default 0.0423,0.0847,0.027, as prepare)"},
                    {"--ior", "N", "the object's index of refraction (default 1.5, as the scenes)"},
                    kThreadsOption,
                    {"-o,--output", "FILE", "where to write it (default MATERIALS.gamut.json beside the table)"}});
    if (args.positional().size() != 1) throw UsageError("characterise needs exactly one MATERIALS.json");
    const std::filesystem::path materialsFile = args.positional()[0];
    s.levels = int(args.integer("--levels", 1, 16).value_or(s.levels));
    s.spp = uint32_t(args.integer("--spp", 1, 1 << 16).value_or(s.spp));
    if (auto d = args.number("--cube-mm")) {
        if (!(*d >= 2 * s.shellDepth_mm + 1 && *d <= 30)) throw UsageError("--cube-mm must be in [3, 30]");
        s.cube_mm = float(*d);
    }
    if (auto v = args.value("--voxel-mm")) {
        s.voxel_mm = parseTriple("--voxel-mm", *v);
        for (float x : {s.voxel_mm.x, s.voxel_mm.y, s.voxel_mm.z})
            if (!(x >= 0.005f && x <= 1.0f)) throw UsageError("--voxel-mm components must be in [0.005, 1]");
    }
    if (auto n = args.number("--ior")) {
        if (!(*n >= 1 && *n <= 3)) throw UsageError("--ior must be in [1, 3]");
        s.ior = float(*n);
    }
    ThreadLimit threads(args);
    const std::filesystem::path out = args.value("-o").value_or(
        (materialsFile.parent_path() / (materialsFile.stem().string() + ".gamut.json")).string());
    refuseToOverwriteInputs(out, {materialsFile});
    const MaterialTable materials = loadMaterials(materialsFile);
    const auto t0 = std::chrono::steady_clock::now();
    const PrinterGamut gamut = characterisePrinter(materials, s, true);
    writeCharacterisation(gamut, materials, s, out);
    double worst = 0;
    for (const RGB& e : gamut.gridStandardError())
        for (float x : e) worst = std::max(worst, double(x));
    const Lab white = gamut.colour({0, 0, 0, 0, 1}), black = gamut.colour({0, 0, 0, 1, 0});
    std::printf("characterised %zu mixtures in %.1f s (largest standard error %.4f); white L* %.1f, black L* %.1f\n"
                "wrote %s\n",
                gamut.gridReflectance().size(), secondsSince(t0), worst, white.L, black.L, out.string().c_str());
    return 0;
}

}  // namespace pl
