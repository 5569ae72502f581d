// prepare as a library call: a closed, textured mesh to printer voxels.
// Voxelises at the printer's voxel size, computes the signed distance and
// normals in a band around the surface, takes the target colours of the
// outer shell from the model, and halftones them into the research
// convention's material labels (white inside). The command line
// (`printlight prepare`), and any other caller, read the model and write
// the result; this holds the pipeline (docs/prepare.md).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/geometry.h"
#include "core/rgb.h"
#include "media/label_grid.h"
#include "media/voxel_fields.h"
#include "prepare/halftone.h"
#include "prepare/surface_appearance.h"
#include "prepare/voxelizer.h"

namespace pl {

struct PrepareSettings {
    Vec3f voxel_mm = kPrinterVoxel_mm;
    float margin_mm = 0.12f;                   // void padding around the mesh
    float extrude_mm = 1.0f;                   // depth of the colour shell
    HalftoneMethod halftone = HalftoneMethod::ErrorDiffusion;
    // Which voxels are printed: any the surface crosses (conservative) or
    // those whose centre is inside.
    enum class Fill { Conservative, Centre } fill = Fill::Conservative;
    std::optional<RGB> color;  // one colour for the whole shell instead of the model's
    bool keepColors = false;   // keep the target colours as a grid
    // Half-width of the signed-distance and normal band written beside the
    // labels (printpt's --nee reads it; nothing else does). Default: the
    // shell depth plus two voxels. 0: none (a tray-sized model's band is
    // most of prepare's memory, ~20 bytes a band voxel).
    std::optional<float> fieldBand_mm;
    bool showProgress = false;
    // A colour's mixture of the printing materials; empty: fractionsForColor
    // (prepare/halftone.h), a simple mixing model. prepare's command gives
    // the printer's gamut (GamutMixing, prepare/printer_gamut.h) when it
    // has the material table.
    std::function<MaterialFractions(const RGB&)> mixtureFor;
};

struct PreparedModel {
    LabelGrid labels;
    VoxelFields fields;
    std::string colorSource;  // where the shell's colours came from
    uint64_t insideVoxels = 0, printedVoxels = 0, shellVoxels = 0, bandVoxels = 0;
    double scanSeconds = 0, sliceSeconds = 0;
};

// A model that cannot be prepared (too large a grid, not enough memory).
struct PrepareError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

PreparedModel prepareModel(const Geometry& geometry, const SurfaceAppearance& look, const PrepareSettings& settings);

}  // namespace pl
