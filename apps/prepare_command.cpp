// printlight prepare: a textured mesh to printer voxels, written as one .vdb
// (the pipeline: prepare/prepare_model.h), and optionally scenes for it.
#include <chrono>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "api/printer_characterisation.h"
#include "apps/arguments.h"
#include "apps/command_options.h"
#include "runtime/progress.h"
#include "io/grid_io.h"
#include "core/input_error.h"
#include "io/materials_io.h"
#include "io/mesh_io.h"
#include "io/mesh_repair.h"
#include "io/output_file.h"
#include "prepare/halftone.h"
#include "prepare/prepare_model.h"
#include "prepare/printer_gamut.h"

namespace pl {

namespace {

// Larger than any printer's tray: a model this size has the wrong unit.
constexpr double kLargestTray_mm = 500.0;

std::string relativeTo(const std::filesystem::path& target, const std::filesystem::path& fromDir) {
    return std::filesystem::relative(std::filesystem::absolute(target),
                                     std::filesystem::absolute(fromDir.empty() ? "." : fromDir))
        .generic_string();
}

}  // namespace

int prepareCommand(const std::vector<std::string>& argv) {
    const PrepareSettings defaults;
    auto text = [](float x) {
        std::ostringstream s;
        s << x;
        return s.str();
    };
    Arguments args("prepare", argv,
                   {{"-o,--output", "OUT.vdb", "the label grid, with sdf and normal grids (required)"},
                    {"--units", "m|mm|in", "the unit of the model's coordinates (default: glTF's metres; OBJ: mm)"},
                    {"--fit-mm", "L", "scale the model so that its largest side is L mm"},
                    {"--repair", "", "repair a mesh that is not one closed surface (weld, orient, stitch, fill holes)"},
                    {"--voxel", "X,Y,Z",
                     "voxel size in mm (default the printer's, " + text(defaults.voxel_mm.x) + "," +
                         text(defaults.voxel_mm.y) + "," + text(defaults.voxel_mm.z) + ")"},
                    {"--extrude-mm", "D", "depth of the coloured shell (default " + text(defaults.extrude_mm) + ")"},
                    {"--margin-mm", "M", "void margin around the model (default " + text(defaults.margin_mm) + ")"},
                    {"--materials", "FILE",
                     "the material table (default with --scene-out: the bundled one, written beside the scenes)"},
                    {"--mixing", "gamut|simple",
                     "how a colour becomes a mixture of the resins: the printer's characterisation of the material "
                     "table (default with --materials or --scene-out; made on first use) or a simple subtractive model"},
                    {"--gamut", "FILE", "the printer's characterisation for --mixing gamut (default: the material table's)"},
                    {"--halftone", "error-diffusion|nearest", "how a mixture becomes resin labels"},
                    {"--fill", "conservative|center", "which voxels the mesh fills"},
                    {"--color", "R,G,B", "one linear colour for the whole surface instead of the model's"},
                    {"--keep-colors", "", "also write the colour grid the labels were halftoned from"},
                    {"--band-mm", "D", "half-width of the sdf/normal band, at most the default (the shell depth plus "
                                       "two voxels); 0: none; only printpt's --nee reads it"},
                    {"--scene-out", "PREFIX", "also write scenes for the result (PREFIX_surface.json, _preview.json)"},
                    kThreadsOption,
                    kQuietOption});
    ThreadLimit threads(args);
    if (args.positional().size() != 1) throw UsageError("prepare needs exactly one MODEL (.gltf, .glb or .obj)");
    if (!args.has("-o")) throw UsageError("prepare needs -o OUT.vdb");
    std::filesystem::path model = args.positional()[0], output = *args.value("-o");
    if (output.extension() != ".vdb") throw UsageError("-o must name a .vdb file");

    PrepareSettings ps;
    if (auto v = args.value("--voxel")) ps.voxel_mm = parseTriple("--voxel", *v);
    auto number = [&](const char* opt, float fallback, float lo, float hi) {
        const float x = float(args.number(opt).value_or(fallback));
        if (!(x >= lo && x <= hi)) throw UsageError(std::string(opt) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return x;
    };
    if (auto u = args.value("--units"); u && !parseLengthUnit(*u)) throw UsageError("--units must be " + enumNames(kLengthUnitNames));
    std::optional<double> fitMm;
    if (args.has("--fit-mm")) fitMm = number("--fit-mm", 0.0f, 0.01f, 10000.0f);
    ps.extrude_mm = number("--extrude-mm", defaults.extrude_mm, 0.0f, 100.0f);
    ps.margin_mm = number("--margin-mm", defaults.margin_mm, 0.0f, 100.0f);
    for (int a = 0; a < 3; ++a)
        if (!(ps.voxel_mm[a] >= 1e-4f && ps.voxel_mm[a] <= 10.0f)) throw UsageError("--voxel sizes must be in [0.0001, 10] mm");
    const std::string halftone = args.value("--halftone").value_or("error-diffusion");
    if (halftone != "error-diffusion" && halftone != "nearest")
        throw UsageError("--halftone must be error-diffusion or nearest");
    ps.halftone = halftone == "nearest" ? PrepareSettings::Halftone::Nearest : PrepareSettings::Halftone::ErrorDiffusion;
    const std::string fill = args.value("--fill").value_or("conservative");
    if (fill != "conservative" && fill != "center") throw UsageError("--fill must be conservative or center");
    ps.fill = fill == "center" ? PrepareSettings::Fill::Centre : PrepareSettings::Fill::Conservative;
    if (args.has("--color")) {
        Vec3f c = parseTriple("--color", *args.value("--color"));
        ps.color = RGB{c.x, c.y, c.z};
        for (float x : *ps.color)
            if (!(x >= 0 && x <= 1)) throw UsageError("--color components must be in [0, 1] (linear RGB)");
    }
    ps.keepColors = args.has("--keep-colors");
    if (args.has("--band-mm")) ps.fieldBand_mm = number("--band-mm", 0.0f, 0.0f, 100.0f);
    const bool quiet = args.has("--quiet");
    ps.showProgress = !quiet && ProgressBar::stderrIsTerminal();
    std::optional<std::filesystem::path> sceneOut;
    if (auto s = args.value("--scene-out")) {
        sceneOut = *s;
        if (sceneOut->extension() == ".json") sceneOut->replace_extension();
    }
    std::optional<std::filesystem::path> materialsFile;
    // Scenes need a material table: without --materials, the bundled one
    // and its characterisation are written beside them (removed again if
    // prepare fails: no partial output).
    std::vector<std::filesystem::path> bundledCopies;
    struct RemoveUnlessKept {
        std::vector<std::filesystem::path>* files;
        bool keep = false;
        ~RemoveUnlessKept() {
            std::error_code ec;
            if (!keep)
                for (const auto& f : *files) std::filesystem::remove(f, ec);
        }
    } bundledGuard{&bundledCopies};
    bool bundledTable = false;
    if (sceneOut && !args.has("--materials")) {
        // A table already there (an earlier prepare's, or the user's own
        // edit of it) is used as it stands, never overwritten.
        materialsFile = sceneOut->string() + "_materials.json";
        const std::filesystem::path gamutFile = sceneOut->string() + "_materials.gamut.json";
        if (!std::filesystem::exists(*materialsFile)) {
            refuseToOverwriteInputs(*materialsFile, {model});
            writeTextFile(*materialsFile, bundledMaterialTable());
            bundledCopies.push_back(*materialsFile);
            bundledTable = true;
            if (!std::filesystem::exists(gamutFile)) {
                refuseToOverwriteInputs(gamutFile, {model});
                writeTextFile(gamutFile, bundledPrinterGamut());
                bundledCopies.push_back(gamutFile);
            }
        }
    }
    if (auto m = args.value("--materials")) materialsFile = *m;
    if (materialsFile) {
        MaterialTable table = loadMaterials(*materialsFile);
        for (Label l : kPrintMaterialLabel)
            if (!table.byLabel[l].defined)
                throw InputError(materialsFile->string(), "label " + std::to_string(l) + " (a printer material) is missing");
    }
    const std::string mixing = args.value("--mixing").value_or(materialsFile ? "gamut" : "simple");
    if (mixing != "gamut" && mixing != "simple") throw UsageError("--mixing must be gamut or simple");
    if (mixing == "gamut" && !materialsFile)
        throw UsageError("--mixing gamut needs --materials FILE (the printer's gamut is its materials')");
    if (args.has("--gamut") && mixing != "gamut") throw UsageError("--gamut goes with --mixing gamut");
    if (auto file = args.value("--gamut"); file && !std::filesystem::exists(*file))
        throw InputError(*file, "no such file (the printer's characterisation, --gamut)");
    refuseToOverwriteInputs(output, {model});

    // The model, then the pipeline (prepare/prepare_model.h).
    auto t0 = std::chrono::steady_clock::now();
    MeshRepairSummary repaired;
    const bool repair = args.has("--repair");
    // In the file's coordinates (repaired there, as the scene's load does);
    // scaled below, once the model's size is known.
    MeshAsset asset = loadMeshAsset(model, MeshPlacement{LengthUnit::Millimetre, 1.0}, repair ? &repaired : nullptr);
    MeshPlacement placement;
    if (auto u = args.value("--units")) placement.unit = parseLengthUnit(*u);
    const FormatUnit formatUnit = formatUnitOf(model);
    const LengthUnit unit = placement.unit.value_or(formatUnit.unit);
    Bounds3f fileBounds;
    for (const Point3f& p : asset.mesh.positions_mm) fileBounds.expand(p);
    const Vec3f fileExtent = fileBounds.hi - fileBounds.lo;
    const double largestSide = std::max(fileExtent.x, std::max(fileExtent.y, fileExtent.z)) * millimetresPer(unit);
    if (fitMm) placement.scale = *fitMm / largestSide;
    scaleMesh(asset.mesh, placement.millimetresPerFileUnit(model));
    const double side_mm = largestSide * placement.scale;
    const double toMm = millimetresPer(unit) * placement.scale;
    char fitted[96] = "";
    if (fitMm) std::snprintf(fitted, sizeof fitted, "; --fit-mm: scaled by %.6g", placement.scale);
    char size[256];
    std::snprintf(size, sizeof size, "%.4g x %.4g x %.4g mm (coordinates in %s: %s%s)", fileExtent.x * toMm,
                  fileExtent.y * toMm, fileExtent.z * toMm, lengthUnitName(unit),
                  placement.unit ? "--units" : formatUnit.why, fitted);
    // Before the long part, where someone watches (the summary repeats it).
    if (ps.showProgress) std::fprintf(stderr, "prepare: %s: %s\n", model.string().c_str(), size);
    if (side_mm < 1.0)
        std::fprintf(stderr, "printlight: warning: the model is %.3g mm across: is its unit right? (--units, --fit-mm)\n", side_mm);
    if (side_mm > kLargestTray_mm)
        std::fprintf(stderr, "printlight: warning: the model is %.4g mm across, more than a printer's tray (%.0f mm): is its unit right? (--units, --fit-mm)\n",
                     side_mm, kLargestTray_mm);
    Geometry geometry(std::move(asset.mesh));
    const TriangleMesh& mesh = geometry.mesh();
    double tLoad = secondsSince(t0);
    // The printer's gamut for the mixtures: characterised for this voxel
    // and shell (the scenes' IOR, 1.5).
    std::optional<PrinterGamut> gamut;
    std::optional<GamutMixing> gamutMixing;
    std::string mixingSource = "a simple subtractive model (--mixing simple)";
    if (mixing == "gamut") {
        CharacterisationSettings cs;
        cs.voxel_mm = ps.voxel_mm;
        cs.shellDepth_mm = ps.extrude_mm;
        auto say = [&](const std::string& line) { mixingSource = line; };
        if (auto file = args.value("--gamut")) gamut = readPrinterGamutFile(*file, *materialsFile, cs, say);
        else gamut = printerGamutFor(*materialsFile, cs, say);
        gamutMixing.emplace(*gamut);
        ps.mixtureFor = [&](const RGB& c) { return (*gamutMixing)(c); };
    }
    PreparedModel prepared = [&] {
        try {
            return prepareModel(geometry, asset.appearance, ps);
        } catch (const PrepareError& e) {
            throw InputError(model.string(), e.what());
        }
    }();
    const LabelGrid& grid = prepared.labels;
    const GridFrame& f = grid.frame();
    const Vec3i& r = f.resolution;

    // Stage 4: output.
    auto t3 = std::chrono::steady_clock::now();
    writePreparedVdb(grid, prepared.fields, output);
    if (sceneOut) {
        std::filesystem::path dir = sceneOut->parent_path();
        Bounds3f b = geometry.bounds();
        Point3f c = (b.lo + b.hi) * 0.5f;
        float size = length(b.hi - b.lo);
        nlohmann::json object = {{"mesh", relativeTo(model, dir)},
                                 {"mesh_units", lengthUnitName(unit)},
                                 {"labels", relativeTo(output, dir)},
                                 {"materials", relativeTo(*materialsFile, dir)},
                                 {"ior", 1.5}};
        if (placement.scale != 1.0) object["mesh_scale"] = placement.scale;
        if (repair) object["mesh_repair"] = true;
        std::string stem = sceneOut->filename().string();
        nlohmann::json surface = {{"object", object},
                                  {"environment", {{"radiance", {1, 1, 1}}}},
                                  // The bundled scenes' settings (data/scenes): light
                                  // tracing over each voxel's patch.
                                  {"sensor", {{"type", "surface_voxels"}, {"footprint", "patch"}}},
                                  {"render", {{"integrator", "lighttrace"}, {"spp", 8}, {"seed", 1}, {"channel", "rgb"}, {"reentry", false}}},
                                  {"output", {{"path", "out/" + stem + "_surface"}}}};
        nlohmann::json preview = surface;
        // Looking at the centre from a corner above, far enough to frame it.
        float dist = 1.4f * size;
        preview["sensor"] = {{"type", "perspective"},
                             {"position", {c.x + 0.55f * dist, c.y - 0.65f * dist, c.z + 0.5f * dist}},
                             {"look_at", {c.x, c.y, c.z}},
                             {"up", {0, 0, 1}},
                             {"fov_deg", 30},
                             {"resolution", {320, 240}}};
        // A preview stops at 5 % median noise or after a minute.
        preview["render"]["integrator"] = "volpath";
        preview["render"].erase("spp");
        preview["render"]["target_relative_error"] = 0.05;
        preview["render"]["time_budget_s"] = 60;
        preview["render"]["reentry"] = true;
        preview["output"]["path"] = "out/" + stem + "_preview";
        writeTextFile(sceneOut->string() + "_surface.json", surface.dump(2) + "\n");
        writeTextFile(sceneOut->string() + "_preview.json", preview.dump(2) + "\n");
    }
    double tWrite = secondsSince(t3);
    bundledGuard.keep = true;

    // Summary.
    auto hist = grid.histogram();
    size_t surfaceVoxels = grid.surfaceVoxels().size();
    double dense = double(f.voxelCount()) * 16.0;
    std::printf("prepare: %s: %s\n", model.string().c_str(), size);
    std::printf("  model:     %zu triangles, colour from %s\n", mesh.triangleCount(), prepared.colorSource.c_str());
    if (bundledTable)
        std::printf("  materials: the bundled table (%s; no --materials), written to %s\n", kBundledMaterialName,
                    materialsFile->string().c_str());
    else if (sceneOut && !args.has("--materials"))
        std::printf("  materials: %s (there already; no --materials)\n", materialsFile->string().c_str());
    std::printf("  mixtures:  %s\n", mixingSource.c_str());
    if (repair) std::printf("  repaired:  %s\n", repaired.text().c_str());
    std::printf("  grid:      %d x %d x %d = %llu voxels of %.4g x %.4g x %.4g mm\n", r.x, r.y, r.z,
                (unsigned long long)f.voxelCount(), f.voxelSize_mm.x, f.voxelSize_mm.y, f.voxelSize_mm.z);
    std::printf("  voxels:    %llu inside (centre), %llu printed (%s fill), %zu surface, %llu in the colour shell (%.2f mm), %llu in the distance band\n",
                (unsigned long long)prepared.insideVoxels, (unsigned long long)prepared.printedVoxels, fill.c_str(),
                surfaceVoxels, (unsigned long long)prepared.shellVoxels, ps.extrude_mm,
                (unsigned long long)prepared.bandVoxels);
    std::printf("  labels:   ");
    for (int l = 0; l < 7; ++l)
        if (hist[size_t(l)]) std::printf(" %s %llu", researchLabelName(l), (unsigned long long)hist[size_t(l)]);
    std::printf("\n  memory:    labels tree %.2f MB, sdf+normal%s %.2f MB; dense float albedo+density %.1f MB (labels x%.1f smaller)\n",
                grid.memoryBytes() / 1e6, ps.keepColors ? "+colors" : "", prepared.fields.memoryBytes() / 1e6,
                dense / 1e6, dense / double(grid.memoryBytes()));
    std::printf("  time:      load %.2f s, scanlines+bricks %.2f s, slices (distance, colour, %s) %.2f s, write %.2f s -> %s\n",
                tLoad, prepared.scanSeconds, halftone.c_str(), prepared.sliceSeconds, tWrite, output.string().c_str());
    return 0;
}

}  // namespace pl
