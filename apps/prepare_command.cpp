// printlight prepare: a textured mesh to printer voxels, written as one .vdb
// (the pipeline: prepare/prepare_model.h), and optionally scenes for it.
#include <chrono>
#include <cstdio>
#include <sstream>

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
#include "render/scene_io.h"

namespace pl {

namespace {

// Larger than any printer's tray: a model this size has the wrong unit.
constexpr double kLargestTray_mm = 500.0;

// A number option in [lo, hi], or the fallback.
float numberOption(const Arguments& args, const char* opt, float fallback, float lo, float hi) {
    const float x = float(args.number(opt).value_or(fallback));
    if (!(x >= lo && x <= hi)) throw UsageError(std::string(opt) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return x;
}

// The pipeline's settings from the command line.
PrepareSettings prepareSettingsOf(const Arguments& args) {
    const PrepareSettings defaults;
    PrepareSettings ps;
    if (auto v = args.value("--voxel")) ps.voxel_mm = parseTriple("--voxel", *v);
    auto number = [&](const char* opt, float fallback, float lo, float hi) { return numberOption(args, opt, fallback, lo, hi); };
    ps.extrude_mm = number("--extrude-mm", defaults.extrude_mm, 0.0f, 100.0f);
    ps.margin_mm = number("--margin-mm", defaults.margin_mm, 0.0f, 100.0f);
    for (int a = 0; a < 3; ++a)
        if (!(ps.voxel_mm[a] >= 1e-4f && ps.voxel_mm[a] <= 10.0f)) throw UsageError("--voxel sizes must be in [0.0001, 10] mm");
    const std::string halftone = args.value("--halftone").value_or("error-diffusion");
    const std::optional<HalftoneMethod> method = parseEnum(kHalftoneMethodNames, halftone);
    if (!method) throw UsageError("--halftone must be error-diffusion, thresholds or nearest");
    ps.halftone = *method;
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
    ps.showProgress = !args.has("--quiet") && ProgressBar::stderrIsTerminal();
    return ps;
}

// The material table the scenes name and the mixtures come from: --materials,
// or with --scene-out and without it the bundled table and its
// characterisation written beside the scenes (removed again if prepare
// fails: no partial output), or none.
class MaterialsChoice {
public:
    MaterialsChoice(const Arguments& args, const std::optional<std::filesystem::path>& sceneOut,
                    const std::filesystem::path& model) {
        if (sceneOut && !args.has("--materials")) {
            // A table already there (an earlier prepare's, or the user's own
            // edit of it) is used as it stands, never overwritten.
            file = sceneOut->string() + "_materials.json";
            beside = true;
            const std::filesystem::path gamutFile = sceneOut->string() + "_materials.gamut.json";
            if (!std::filesystem::exists(*file)) {
                refuseToOverwriteInputs(*file, {model});
                writeTextFile(*file, bundledMaterialTable());
                written_.push_back(*file);
                bundled = true;
                if (!std::filesystem::exists(gamutFile)) {
                    refuseToOverwriteInputs(gamutFile, {model});
                    writeTextFile(gamutFile, bundledPrinterGamut());
                    written_.push_back(gamutFile);
                }
            }
        }
        if (auto m = args.value("--materials")) file = *m;
        if (file) {
            MaterialTable table = loadMaterials(*file);
            for (Label l : kPrintMaterialLabel)
                if (!table.byLabel[l].defined)
                    throw InputError(file->string(), "label " + std::to_string(l) + " (a printer material) is missing");
        }
    }
    ~MaterialsChoice() {
        std::error_code ec;
        if (!keep_)
            for (const auto& f : written_) std::filesystem::remove(f, ec);
    }
    void keep() { keep_ = true; }
    std::optional<std::filesystem::path> file;
    bool beside = false;   // beside the scenes, for want of --materials
    bool bundled = false;  // the bundled table, written there now

private:
    std::vector<std::filesystem::path> written_;
    bool keep_ = false;
};

// Whether colours become mixtures through the printer's characterisation
// (--mixing gamut, the default with a material table) or the simple model.
bool mixesByGamut(const Arguments& args, bool haveMaterials) {
    const std::string mixing = args.value("--mixing").value_or(haveMaterials ? "gamut" : "simple");
    if (mixing != "gamut" && mixing != "simple") throw UsageError("--mixing must be gamut or simple");
    if (mixing == "gamut" && !haveMaterials)
        throw UsageError("--mixing gamut needs --materials FILE (the printer's gamut is its materials')");
    if (args.has("--gamut") && mixing != "gamut") throw UsageError("--gamut goes with --mixing gamut");
    if (args.has("--intent") && mixing != "gamut") throw UsageError("--intent goes with --mixing gamut");
    if (auto file = args.value("--gamut"); file && !std::filesystem::exists(*file))
        throw InputError(*file, "no such file (the printer's characterisation, --gamut)");
    return mixing == "gamut";
}

// The model in millimetres, as the scenes will place it, and its size.
struct PlacedModel {
    MeshAsset asset;
    MeshPlacement placement;  // with the unit resolved
    double side_mm = 0;       // its largest side
    std::string sizeText;     // "4 x 4 x 4 mm (coordinates in m: ...)"
};

// fitMm: the largest side wanted (--fit-mm), or none.
PlacedModel loadPlacedModel(const std::filesystem::path& model, const Arguments& args, std::optional<double> fitMm,
                            MeshRepairSummary* repaired) {
    PlacedModel m;
    // In the file's coordinates (repaired there, as the scene's load does);
    // scaled below, once the model's size is known.
    m.asset = loadMeshAsset(model, MeshPlacement{LengthUnit::Millimetre, 1.0}, repaired);
    std::optional<LengthUnit> given;
    if (auto u = args.value("--units")) given = parseLengthUnit(*u);
    const FormatUnit formatUnit = formatUnitOf(model);
    const LengthUnit unit = given.value_or(formatUnit.unit);
    m.placement.unit = given;
    Bounds3f fileBounds;
    for (const Point3f& p : m.asset.mesh.positions_mm) fileBounds.expand(p);
    const Vec3f fileExtent = fileBounds.hi - fileBounds.lo;
    const double largestSide = std::max(fileExtent.x, std::max(fileExtent.y, fileExtent.z)) * millimetresPer(unit);
    if (fitMm) m.placement.scale = *fitMm / largestSide;
    scaleMesh(m.asset.mesh, m.placement.millimetresPerFileUnit(model));
    m.side_mm = largestSide * m.placement.scale;
    const double toMm = millimetresPer(unit) * m.placement.scale;
    char fitted[96] = "";
    if (fitMm) std::snprintf(fitted, sizeof fitted, "; --fit-mm: scaled by %.6g", m.placement.scale);
    char size[256];
    std::snprintf(size, sizeof size, "%.4g x %.4g x %.4g mm (coordinates in %s: %s%s)", fileExtent.x * toMm,
                  fileExtent.y * toMm, fileExtent.z * toMm, lengthUnitName(unit),
                  given ? "--units" : formatUnit.why, fitted);
    m.sizeText = size;
    m.placement.unit = unit;
    return m;
}

// The model's size (where someone watches) and a warning where its unit
// looks wrong.
void sayModelSize(const std::filesystem::path& model, const PlacedModel& placed, bool showProgress) {
    if (showProgress) std::fprintf(stderr, "prepare: %s: %s\n", model.string().c_str(), placed.sizeText.c_str());
    if (placed.side_mm < 1.0)
        std::fprintf(stderr, "printlight: warning: the model is %.3g mm across: is its unit right? (--units, --fit-mm)\n", placed.side_mm);
    if (placed.side_mm > kLargestTray_mm)
        std::fprintf(stderr, "printlight: warning: the model is %.4g mm across, more than a printer's tray (%.0f mm): is its unit right? (--units, --fit-mm)\n",
                     placed.side_mm, kLargestTray_mm);
}

// PREFIX_surface.json (the bundled scenes' settings: light tracing over each
// voxel's patch) and PREFIX_preview.json (looking at the centre from a
// corner above, far enough to frame it; it stops at 5 % median noise or
// after a minute). Light that leaves a convex object never comes back: its
// preview needs no re-entry, and printpt serves it (1.8x volpath on the
// greek cube's, docs/particle-methods.md). Returns what it wrote, for the
// summary.
std::string writeScenes(const std::filesystem::path& sceneOut, const std::filesystem::path& model,
                        const PlacedModel& placed, bool repair, const std::filesystem::path& labels,
                        const std::filesystem::path& materials, const Geometry& geometry) {
    const Bounds3f bounds_mm = geometry.bounds();
    const std::string stem = sceneOut.filename().string();
    SceneDescription surface;
    surface.meshFile = model;
    surface.meshPlacement = placed.placement;
    surface.meshRepair = repair;
    surface.labelsFile = labels;
    surface.materialsFile = materials;
    surface.sensor.type = "surface_voxels";
    surface.sensor.footprint = SurfaceVoxelSensor::Footprint::Patch;
    surface.render.integrator = "lighttrace";
    surface.render.spp = 8;
    surface.output = "out/" + stem + "_surface";
    writeScene(surface, sceneOut.string() + "_surface.json");

    SceneDescription preview = surface;
    const Point3f c = (bounds_mm.lo + bounds_mm.hi) * 0.5f;
    const float dist = 1.4f * length(bounds_mm.hi - bounds_mm.lo);
    preview.sensor.type = "perspective";
    preview.sensor.pose = {{c.x + 0.55f * dist, c.y - 0.65f * dist, c.z + 0.5f * dist}, c, {0, 0, 1}};
    preview.sensor.fovY_deg = 30;
    preview.sensor.width = 320;
    preview.sensor.height = 240;
    const bool convex = isConvex(geometry.mesh());
    preview.render.integrator = convex ? "printpt" : "volpath";
    preview.render.spp = uint32_t(RenderSettings::kMostSpp);
    preview.render.targetRelativeError = 0.05;
    preview.render.timeBudget_s = 60;
    preview.render.reentry = !convex;
    preview.output = "out/" + stem + "_preview";
    writeScene(preview, sceneOut.string() + "_preview.json");
    return sceneOut.string() + "_surface.json (lighttrace), " + sceneOut.string() + "_preview.json (" +
           (convex ? "printpt: the mesh is convex, nothing re-enters" : "volpath with re-entry: the mesh is not convex") +
           ")";
}

// What prepare made, on stdout (repairedText: what --repair did, or "").
void printPrepareSummary(const std::filesystem::path& model, const std::string& sizeText, const PreparedModel& prepared,
                         const TriangleMesh& mesh, const MaterialsChoice& materials, const std::string& mixingSource,
                         const std::string& repairedText, const PrepareSettings& ps, const Arguments& args,
                         double tLoad, double tWrite, const std::filesystem::path& output) {
    const LabelGrid& grid = prepared.labels;
    const GridFrame& f = grid.frame();
    const Vec3i& r = f.resolution;
    auto hist = grid.histogram();
    size_t surfaceVoxels = grid.surfaceVoxels().size();
    double dense = double(f.voxelCount()) * 16.0;
    std::printf("prepare: %s: %s\n", model.string().c_str(), sizeText.c_str());
    std::printf("  model:     %zu triangles, colour from %s\n", mesh.triangleCount(), prepared.colorSource.c_str());
    if (materials.bundled)
        std::printf("  materials: the bundled table (%s; no --materials), written to %s\n", kBundledMaterialName,
                    materials.file->string().c_str());
    else if (materials.beside)
        std::printf("  materials: %s (there already; no --materials)\n", materials.file->string().c_str());
    std::printf("  mixtures:  %s\n", mixingSource.c_str());
    if (!repairedText.empty()) std::printf("  repaired:  %s\n", repairedText.c_str());
    std::printf("  grid:      %d x %d x %d = %llu voxels of %.4g x %.4g x %.4g mm\n", r.x, r.y, r.z,
                (unsigned long long)f.voxelCount(), f.voxelSize_mm.x, f.voxelSize_mm.y, f.voxelSize_mm.z);
    std::printf("  voxels:    %llu inside (centre), %llu printed (%s fill), %zu surface, %llu in the colour shell (%.2f mm), %llu in the distance band\n",
                (unsigned long long)prepared.insideVoxels, (unsigned long long)prepared.printedVoxels, args.value("--fill").value_or("conservative").c_str(),
                surfaceVoxels, (unsigned long long)prepared.shellVoxels, ps.extrude_mm,
                (unsigned long long)prepared.bandVoxels);
    std::printf("  labels:   ");
    for (int l = 0; l < 7; ++l)
        if (hist[size_t(l)]) std::printf(" %s %llu", researchLabelName(l), (unsigned long long)hist[size_t(l)]);
    std::printf("\n  memory:    labels tree %.2f MB, sdf+normal%s %.2f MB; dense float albedo+density %.1f MB (labels x%.1f smaller)\n",
                grid.memoryBytes() / 1e6, ps.keepColors ? "+colors" : "", prepared.fields.memoryBytes() / 1e6,
                dense / 1e6, dense / double(grid.memoryBytes()));
    std::printf("  time:      load %.2f s, scanlines+bricks %.2f s, slices (distance, colour, %s) %.2f s, write %.2f s -> %s\n",
                tLoad, prepared.scanSeconds, args.value("--halftone").value_or("error-diffusion").c_str(), prepared.sliceSeconds, tWrite, output.string().c_str());
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
                    kIntentOption,
                    {"--halftone", "error-diffusion|thresholds|nearest", "how a mixture becomes resin labels"},
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

    if (auto u = args.value("--units"); u && !parseLengthUnit(*u)) throw UsageError("--units must be " + enumNames(kLengthUnitNames));
    std::optional<double> fitMm;
    if (args.has("--fit-mm")) fitMm = numberOption(args, "--fit-mm", 0.0f, 0.01f, 10000.0f);
    PrepareSettings ps = prepareSettingsOf(args);
    std::optional<std::filesystem::path> sceneOut;
    if (auto s = args.value("--scene-out")) {
        sceneOut = *s;
        if (sceneOut->extension() == ".json") sceneOut->replace_extension();
    }
    MaterialsChoice materials(args, sceneOut, model);
    const std::optional<std::filesystem::path>& materialsFile = materials.file;
    const bool byGamut = mixesByGamut(args, materialsFile.has_value());
    const RenderingIntent intent = intentOption(args).value_or(RenderingIntent::Colorimetric);
    refuseToOverwriteInputs(output, {model});

    // The model, then the pipeline (prepare/prepare_model.h).
    auto t0 = std::chrono::steady_clock::now();
    MeshRepairSummary repaired;
    const bool repair = args.has("--repair");
    PlacedModel placed = loadPlacedModel(model, args, fitMm, repair ? &repaired : nullptr);
    // Before the long part, where someone watches (the summary repeats it).
    sayModelSize(model, placed, ps.showProgress);
    Geometry geometry(std::move(placed.asset.mesh));
    const TriangleMesh& mesh = geometry.mesh();
    double tLoad = secondsSince(t0);
    // The printer's gamut for the mixtures: characterised for this voxel
    // and shell (the scenes' IOR, 1.5).
    std::optional<PrinterGamut> gamut;
    std::optional<PerceptualIntent> perceptual;
    std::optional<GamutMixing> gamutMixing;
    std::string mixingSource = "a simple subtractive model (--mixing simple)";
    if (byGamut) {
        CharacterisationSettings cs;
        cs.voxel_mm = ps.voxel_mm;
        cs.shellDepth_mm = ps.extrude_mm;
        auto say = [&](const std::string& line) { mixingSource = line; };
        if (auto file = args.value("--gamut")) gamut = readPrinterGamutFile(*file, *materialsFile, cs, say);
        else gamut = printerGamutFor(*materialsFile, cs, say);
        if (intent == RenderingIntent::Perceptual) perceptual.emplace(*gamut);
        std::function<Lab(const Lab&)> compress;
        if (perceptual) compress = [&](const Lab& c) { return (*perceptual)(c); };
        gamutMixing.emplace(*gamut, compress);
        mixingSource += std::string(", ") + enumName(kRenderingIntentNames, intent) + " intent";
        ps.mixtureFor = [&](const RGB& c) { return (*gamutMixing)(c); };
    }
    PreparedModel prepared = [&] {
        try {
            return prepareModel(geometry, placed.asset.appearance, ps);
        } catch (const PrepareError& e) {
            throw InputError(model.string(), e.what());
        }
    }();

    auto t3 = std::chrono::steady_clock::now();
    writePreparedVdb(prepared.labels, prepared.fields, output);
    const std::string scenesText =
        sceneOut ? writeScenes(*sceneOut, model, placed, repair, output, *materialsFile, geometry) : std::string();
    double tWrite = secondsSince(t3);
    materials.keep();

    printPrepareSummary(model, placed.sizeText, prepared, mesh, materials, mixingSource,
                        repair ? repaired.text() : std::string(), ps, args, tLoad, tWrite, output);
    if (!scenesText.empty()) std::printf("  scenes:    %s\n", scenesText.c_str());
    return 0;
}

}  // namespace pl
