#include "prepare/prepare_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "runtime/interrupt.h"
#include "runtime/memory_budget.h"
#include "runtime/progress.h"
#include "prepare/halftone.h"
#include "prepare/threshold_matrix.h"

namespace pl {

PreparedModel prepareModel(const Geometry& geometry, const SurfaceAppearance& look, const PrepareSettings& settings) {
    const TriangleMesh& mesh = geometry.mesh();
    const bool useModelColor = !settings.color && look.hasColor();
    const RGB constantColor = settings.color.value_or(RGB{1, 1, 1});
    std::string colorSource = settings.color               ? "constant --color"
                              : !look.textures.empty()     ? "base-colour texture"
                              : !look.vertexColors.empty() ? "vertex colours"
                              : look.hasColor()            ? "material base colour"
                                                           : "none (white)";
    VoxelizeSettings vs;
    vs.voxel_mm = settings.voxel_mm;
    vs.margin_mm = settings.margin_mm;
    vs.band_mm = settings.extrude_mm + 2.0f * std::max({vs.voxel_mm.x, vs.voxel_mm.y, vs.voxel_mm.z});
    const float fieldBand_mm = std::min(settings.fieldBand_mm.value_or(vs.band_mm), vs.band_mm);

    // Scanlines and near-surface bricks.
    auto t1 = std::chrono::steady_clock::now();
    {
        GridFrame planned = Voxelizer::frameFor(geometry.bounds(), vs);
        if (planned.voxelCount() > kMaxGridVoxels)
            throw PrepareError("voxel grid of " + std::to_string(planned.voxelCount()) + " voxels is too large");
        // Measured on the greek cubes (docs/prepare.md, "Limits and what is
        // left out"): the sdf/normal band ~20 bytes a band voxel, the
        // labels ~4 bytes a shell voxel (the white core collapses to
        // tiles), the colour grid ~14, per-slice arrays ~80 bytes a slice
        // voxel.
        const double voxel_mm3 = double(vs.voxel_mm.x) * vs.voxel_mm.y * vs.voxel_mm.z;
        double area_mm2 = 0;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) area_mm2 += mesh.triangleArea_mm2(t);
        const double bandVoxels = area_mm2 * (fieldBand_mm + std::min(fieldBand_mm, vs.margin_mm)) / voxel_mm3;
        const double shellVoxels = area_mm2 * (settings.extrude_mm + vs.voxel_mm.z) / voxel_mm3;
        const Vec3i& r = planned.resolution;
        const double bandBytes = 20.0 * bandVoxels;
        const double bytes = bandBytes + (4.0 + (settings.keepColors ? 14.0 : 0.0)) * shellVoxels +
                             80.0 * double(r.x) * r.y + 24.0 * double(r.y) * r.z + double(planned.voxelCount()) / 8;
        std::string remedy = "a coarser --voxel or a smaller --fit-mm would fit";
        if (bandBytes > 0.2 * bytes)
            remedy = "--band-mm 0 needs " + std::to_string(int64_t(bandBytes) >> 20) +
                     " MiB less (the sdf/normal band only printpt's --nee reads); " + remedy;
        if (auto why = memoryShortfall(uint64_t(bytes), "a " + std::to_string(planned.voxelCount()) + "-voxel grid",
                                       memoryInUseBytes(), remedy))
            throw PrepareError(*why);
    }
    Voxelizer vox(geometry, vs);
    const GridFrame& f = vox.frame();
    const double scanSeconds = secondsSince(t1);

    // Slices: distances, colours, halftoning, trees.
    auto t2 = std::chrono::steady_clock::now();
    const Vec3i& r = f.resolution;
    const bool conservative = settings.fill == PrepareSettings::Fill::Conservative;
    LabelGridBuilder labels(f, kVoidLabel);
    VoxelFields fields(vs.band_mm, settings.keepColors);
    ErrorDiffusionHalftoner halftoner(r.x, r.y);
    const ThresholdMatrix* thresholds =
        settings.halftone == HalftoneMethod::Thresholds ? &ThresholdMatrix::forVoxel(f.voxelSize_mm) : nullptr;
    std::vector<MaterialFractions> targets(size_t(r.x) * r.y);
    std::vector<uint8_t> active(targets.size()), chosen;
    std::vector<RGB> colors(targets.size());
    uint64_t inside = 0, members = 0, shell = 0, band = 0;
    ProgressBar progress(uint64_t(r.z), "prepare", settings.showProgress);
    for (int z = 0; z < r.z; ++z) {
        throwIfInterrupted();
        std::vector<VoxelRow> rows = vox.slice(z);
        std::fill(active.begin(), active.end(), 0);
        for (int y = 0; y < r.y; ++y)
            for (const VoxelSample& s : rows[size_t(y)].samples) {
                bool member = conservative ? s.member : s.inside;
                if (!member || !s.inBand || s.sdf_mm < -settings.extrude_mm) continue;
                size_t at = size_t(y) * r.x + s.x;
                RGB c = useModelColor ? look.colorAt(mesh, s.prim, s.surfacePoint_mm) : constantColor;
                colors[at] = c;
                targets[at] = settings.mixtureFor ? settings.mixtureFor(c) : fractionsForColor(c);
                active[at] = 1;
            }
        if (settings.halftone == HalftoneMethod::ErrorDiffusion) {
            halftoner.halftoneSlice(z, targets, active, chosen);
        } else {
            chosen.assign(active.size(), 0);
            for (size_t i = 0; i < active.size(); ++i) {
                if (!active[i]) continue;
                const Vec3i v{int(i % r.x), int(i / r.x), z};  // as the labels are set below
                chosen[i] = uint8_t(materialOfVoxel(targets[i], thresholds, v));
            }
        }
        for (int y = 0; y < r.y; ++y)
            for (const VoxelSample& s : rows[size_t(y)].samples) {
                Vec3i v{s.x, y, z};
                size_t at = size_t(y) * r.x + s.x;
                bool member = conservative ? s.member : s.inside;
                inside += s.inside;
                members += member;
                if (member) labels.set(v, active[at] ? kPrintMaterialLabel[chosen[at]] : Label(kWhiteLabel));
                if (active[at]) {
                    ++shell;
                    if (settings.keepColors) fields.setColor(v, colors[at]);
                }
                if (s.inBand && std::abs(s.sdf_mm) <= fieldBand_mm) {
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
    return {std::move(grid), std::move(fields), colorSource, inside, members, shell, band, scanSeconds,
            secondsSince(t2)};
}

}  // namespace pl
