// printlight prepare: a textured mesh to printer voxels. Voxelises at the
// printer's voxel size, computes the signed distance and normals in a band
// around the surface, takes the target colours of the surface shell from the
// model, halftones them into material labels, and writes one .vdb.
#include <chrono>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/arguments.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "io/grid_io.h"
#include "io/input_error.h"
#include "io/materials_io.h"
#include "io/mesh_io.h"
#include "io/output_file.h"
#include "prepare/halftone.h"
#include "core/memory_budget.h"
#include "prepare/voxelizer.h"

namespace pl {

namespace {

std::string relativeTo(const std::filesystem::path& target, const std::filesystem::path& fromDir) {
    return std::filesystem::relative(std::filesystem::absolute(target),
                                     std::filesystem::absolute(fromDir.empty() ? "." : fromDir))
        .generic_string();
}

}  // namespace

int prepareCommand(const std::vector<std::string>& argv) {
    Arguments args(argv,
                   {"-o", "--voxel", "--extrude-mm", "--margin-mm", "--materials", "--halftone",
                    "--scene-out", "--color", "--fill"},
                   {"--keep-colors", "--quiet"});
    if (args.positional().size() != 1) throw UsageError("prepare needs exactly one MODEL (.gltf, .glb or .obj)");
    if (!args.has("-o")) throw UsageError("prepare needs -o OUT.vdb");
    std::filesystem::path model = args.positional()[0], output = *args.value("-o");
    if (output.extension() != ".vdb") throw UsageError("-o must name a .vdb file");

    VoxelizeSettings vs;
    if (auto v = args.value("--voxel")) vs.voxel_mm = parseTriple("--voxel", *v);
    float extrude_mm = 1.0f;
    auto number = [&](const char* opt, float fallback, float lo, float hi) {
        auto v = args.value(opt);
        if (!v) return fallback;
        float x;
        try {
            size_t used;
            x = std::stof(*v, &used);
            if (used != v->size()) throw std::invalid_argument("");
        } catch (const std::exception&) {
            throw UsageError(std::string(opt) + " takes a number");
        }
        if (!(x >= lo && x <= hi)) throw UsageError(std::string(opt) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return x;
    };
    extrude_mm = number("--extrude-mm", 1.0f, 0.0f, 100.0f);
    vs.margin_mm = number("--margin-mm", 0.12f, 0.0f, 100.0f);
    for (int a = 0; a < 3; ++a)
        if (!(vs.voxel_mm[a] >= 1e-4f && vs.voxel_mm[a] <= 10.0f)) throw UsageError("--voxel sizes must be in [0.0001, 10] mm");
    float maxVoxel = std::max({vs.voxel_mm.x, vs.voxel_mm.y, vs.voxel_mm.z});
    vs.band_mm = extrude_mm + 2.0f * maxVoxel;
    std::string halftone = args.value("--halftone").value_or("error-diffusion");
    if (halftone != "error-diffusion" && halftone != "nearest")
        throw UsageError("--halftone must be error-diffusion or nearest");
    std::string fill = args.value("--fill").value_or("conservative");
    if (fill != "conservative" && fill != "center") throw UsageError("--fill must be conservative or center");
    RGB constantColor{1, 1, 1};
    bool hasConstant = args.has("--color");
    if (hasConstant) {
        Vec3f c = parseTriple("--color", *args.value("--color"));
        constantColor = {c.x, c.y, c.z};
        for (float x : constantColor)
            if (!(x >= 0 && x <= 1)) throw UsageError("--color components must be in [0, 1] (linear RGB)");
    }
    bool keepColors = args.has("--keep-colors"), quiet = args.has("--quiet");
    std::optional<std::filesystem::path> sceneOut;
    if (auto s = args.value("--scene-out")) {
        if (!args.has("--materials")) throw UsageError("--scene-out needs --materials FILE for the scenes");
        sceneOut = *s;
        if (sceneOut->extension() == ".json") sceneOut->replace_extension();
    }
    std::optional<std::filesystem::path> materialsFile;
    if (auto m = args.value("--materials")) {
        materialsFile = *m;
        MaterialTable table = loadMaterials(*materialsFile);
        for (Label l : kPrintMaterialLabel)
            if (!table.byLabel[l].defined)
                throw InputError(materialsFile->string(), "label " + std::to_string(l) + " (a printer material) is missing");
    }
    refuseToOverwriteInputs(output, {model});

    // Stage 1: the model.
    auto t0 = std::chrono::steady_clock::now();
    MeshAsset asset = loadMeshAsset(model);
    Geometry geometry(std::move(asset.mesh));
    const SurfaceAppearance& look = asset.appearance;
    const TriangleMesh& mesh = geometry.mesh();
    double tLoad = secondsSince(t0);
    std::string colorSource = hasConstant ? "constant --color"
                              : !look.textures.empty() ? "base-colour texture"
                              : !look.vertexColors.empty() ? "vertex colours"
                              : look.hasColor() ? "material base colour" : "none (white)";
    bool useModelColor = !hasConstant && look.hasColor();

    // Stage 2: scanlines and near-surface bricks.
    auto t1 = std::chrono::steady_clock::now();
    {
        GridFrame planned = Voxelizer::frameFor(geometry.bounds(), vs);
        if (planned.voxelCount() > kMaxGridVoxels)
            throw InputError(model.string(), "voxel grid of " + std::to_string(planned.voxelCount()) + " voxels is too large");
        // Scanline intervals, the label tree (up to ~1.2 bytes per voxel) and the band.
        if (auto why = memoryShortfall(uint64_t(double(planned.voxelCount()) * 3.0),
                                       "a " + std::to_string(planned.voxelCount()) + "-voxel grid"))
            throw InputError(model.string(), *why);
    }
    Voxelizer vox(geometry, vs);
    const GridFrame& f = vox.frame();
    double tScan = secondsSince(t1);

    // Stage 3: slices: distances, colours, halftoning, trees.
    auto t2 = std::chrono::steady_clock::now();
    const Vec3i& r = f.resolution;
    LabelGridBuilder labels(f, kVoidLabel);
    VoxelFields fields(vs.band_mm, keepColors);
    ErrorDiffusionHalftoner halftoner(r.x, r.y);
    std::vector<MaterialFractions> targets(size_t(r.x) * r.y);
    std::vector<uint8_t> active(targets.size()), chosen;
    std::vector<RGB> colors(targets.size());
    uint64_t inside = 0, members = 0, shell = 0, band = 0;
    ProgressBar progress(uint64_t(r.z), "prepare", !quiet && ProgressBar::stderrIsTerminal());
    for (int z = 0; z < r.z; ++z) {
        throwIfInterrupted();
        std::vector<VoxelRow> rows = vox.slice(z);
        std::fill(active.begin(), active.end(), 0);
        for (int y = 0; y < r.y; ++y)
            for (const VoxelSample& s : rows[size_t(y)].samples) {
                bool member = fill == "conservative" ? s.member : s.inside;
                if (!member || !s.inBand || s.sdf_mm < -extrude_mm) continue;
                size_t at = size_t(y) * r.x + s.x;
                RGB c = useModelColor ? look.colorAt(mesh, s.prim, s.surfacePoint_mm) : constantColor;
                colors[at] = c;
                targets[at] = fractionsForColor(c);
                active[at] = 1;
            }
        if (halftone == "error-diffusion") {
            halftoner.halftoneSlice(z, targets, active, chosen);
        } else {
            chosen.assign(active.size(), 0);
            for (size_t i = 0; i < active.size(); ++i)
                if (active[i]) chosen[i] = uint8_t(std::max_element(targets[i].begin(), targets[i].end()) - targets[i].begin());
        }
        for (int y = 0; y < r.y; ++y)
            for (const VoxelSample& s : rows[size_t(y)].samples) {
                Vec3i v{s.x, y, z};
                size_t at = size_t(y) * r.x + s.x;
                bool member = fill == "conservative" ? s.member : s.inside;
                inside += s.inside;
                members += member;
                if (member) labels.set(v, active[at] ? kPrintMaterialLabel[chosen[at]] : kWhiteLabel);
                if (active[at]) {
                    ++shell;
                    if (keepColors) fields.setColor(v, colors[at]);
                }
                if (s.inBand) {
                    ++band;
                    fields.setSdf(v, s.sdf_mm);
                    fields.setNormal(v, s.normal);
                }
            }
        if (z % 16 == 15) labels.compact();
        progress.advance(1);
    }
    progress.finish();
    LabelGrid grid = labels.finish();
    fields.finish();
    double tSlices = secondsSince(t2);

    // Stage 4: output.
    auto t3 = std::chrono::steady_clock::now();
    writePreparedVdb(grid, fields, output);
    if (sceneOut) {
        std::filesystem::path dir = sceneOut->parent_path();
        Bounds3f b = geometry.bounds();
        Point3f c = (b.lo + b.hi) * 0.5f;
        float size = length(b.hi - b.lo);
        nlohmann::json object = {{"mesh", relativeTo(model, dir)},
                                 {"labels", relativeTo(output, dir)},
                                 {"materials", relativeTo(*materialsFile, dir)},
                                 {"ior", 1.5}};
        std::string stem = sceneOut->filename().string();
        nlohmann::json surface = {{"object", object},
                                  {"environment", {{"radiance", {1, 1, 1}}}},
                                  {"sensor", {{"type", "surface_voxels"}}},
                                  {"render", {{"integrator", "volpath"}, {"spp", 4}, {"seed", 1}, {"channel", "rgb"}, {"reentry", false}}},
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
        preview["render"]["spp"] = 16;
        preview["render"]["reentry"] = true;
        preview["output"]["path"] = "out/" + stem + "_preview";
        writeTextFile(sceneOut->string() + "_surface.json", surface.dump(2) + "\n");
        writeTextFile(sceneOut->string() + "_preview.json", preview.dump(2) + "\n");
    }
    double tWrite = secondsSince(t3);

    // Summary.
    auto hist = grid.histogram();
    size_t surfaceVoxels = grid.surfaceVoxels().size();
    double dense = double(f.voxelCount()) * 16.0;
    std::printf("prepare: %s: %zu triangles, colour from %s\n", model.string().c_str(), mesh.triangleCount(), colorSource.c_str());
    std::printf("  grid:      %d x %d x %d = %llu voxels of %.4g x %.4g x %.4g mm\n", r.x, r.y, r.z,
                (unsigned long long)f.voxelCount(), f.voxelSize_mm.x, f.voxelSize_mm.y, f.voxelSize_mm.z);
    std::printf("  voxels:    %llu inside (centre), %llu printed (%s fill), %zu surface, %llu in the colour shell (%.2f mm), %llu in the distance band\n",
                (unsigned long long)inside, (unsigned long long)members, fill.c_str(), surfaceVoxels,
                (unsigned long long)shell, extrude_mm, (unsigned long long)band);
    std::printf("  labels:   ");
    for (int l = 0; l < 7; ++l)
        if (hist[size_t(l)]) std::printf(" %s %llu", researchLabelName(l), (unsigned long long)hist[size_t(l)]);
    std::printf("\n  memory:    labels tree %.2f MB, sdf+normal%s %.2f MB; dense float albedo+density %.1f MB (labels x%.1f smaller)\n",
                grid.memoryBytes() / 1e6, keepColors ? "+colors" : "", fields.memoryBytes() / 1e6, dense / 1e6,
                dense / double(grid.memoryBytes()));
    std::printf("  time:      load %.2f s, scanlines+bricks %.2f s, slices (distance, colour, %s) %.2f s, write %.2f s -> %s\n",
                tLoad, tScan, halftone.c_str(), tSlices, tWrite, output.string().c_str());
    return 0;
}

}  // namespace pl
