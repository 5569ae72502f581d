// A loop's label changes, iteration by iteration (optimize
// --record-changes, replayed by bench --loop): binary, little-endian.
//   "printlight-label-changes 1\n", uint32 iterations, then per iteration
//   uint64 count and count x (int32 x, y, z, uint8 label).
#pragma once

#include <filesystem>
#include <vector>

#include "media/label_grid.h"

namespace pl {

using LabelChangeHistory = std::vector<std::vector<LabelGrid::Change>>;

// Written through a temporary file (never a partial file).
void writeLabelChanges(const std::filesystem::path& file, const LabelChangeHistory& history);
// Throws InputError (one line naming the file) if it is not such a file.
LabelChangeHistory readLabelChanges(const std::filesystem::path& file);

}  // namespace pl
