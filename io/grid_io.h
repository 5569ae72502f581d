// Label grid files (see docs/formats.md, "Label grids"):
//  - OpenVDB .vdb: a grid named "labels" (8-bit, or int32/float holding
//    integer labels); background = void label.
//  - research LabelGrid .bin, or gzipped .gz: int32 res[3]; float64
//    bbox_min[3], bbox_max[3]; uint8 labels, x fastest.
//  - Mitsuba 0.6 .vol: "VOL" 3, int32 encoding (1 float32, 3 uint8),
//    int32 res[3], int32 channels (1), float32 bbox[6], data x fastest.
// Plus the surface-voxel result grids (Vec3 "radiance" and "stderr").
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "compare/result_comparison.h"
#include "core/film.h"
#include "media/label_grid.h"
#include "media/voxel_fields.h"

namespace pl {

// Reads by extension. voidLabel overrides the file's notion of void
// (the .vdb background; 5, air, for formats without one).
LabelGrid loadLabelGrid(const std::filesystem::path& file, std::optional<Label> voidLabel);

// The "sdf" and "normal" grids of a prepared .vdb, if it has them (null
// otherwise, and for the other formats). They must share the labels' voxels.
std::shared_ptr<const VoxelFields> loadVoxelFields(const std::filesystem::path& file, const GridFrame& labels);

void writeLabelGridVdb(const LabelGrid& grid, const std::filesystem::path& file);
// Labels plus the prepared fields: "sdf" (float, mm, negative inside),
// "normal" (Vec3, unit outward gradient) and, if present, "colors" (Vec3,
// linear RGB targets), all in the labels' transform.
void writePreparedVdb(const LabelGrid& grid, const VoxelFields& fields, const std::filesystem::path& file);
void writeLabelGridBin(const LabelGrid& grid, const std::filesystem::path& file);  // .bin or .gz
void writeLabelGridVol(const LabelGrid& grid, const std::filesystem::path& file);

// Surface-voxel results at the voxels' own index coordinates, in the label
// grid's transform: Vec3 grids "radiance" and "stderr".
void writeSurfaceResultVdb(const GridFrame& frame, const std::vector<Vec3i>& voxels,
                           const PixelResults& results, const std::filesystem::path& file);

}  // namespace pl
