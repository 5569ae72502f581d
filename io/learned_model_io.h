// The learned predictor's model file (JSON, written by
// scripts/train_learned.py; docs/learned.md):
//   {"format": "printlight-learned-1",
//    "trained_for": {"materials": <a material table>, "voxel_size_mm": [x, y, z]},
//    "descriptor_size": N,
//    "layers": [{"inputs": I, "outputs": O, "weights": [O x I, row-major], "bias": [O]}, ...],
//    "error_bound": {"share": s, "floor": f}, ...}
// By default a scene's model lies beside its material table:
// resins.json -> resins.learned.json.
#pragma once

#include <filesystem>
#include <memory>

#include "io/learned_model.h"

namespace pl {

// Read once per process and file (an optimisation loop makes a predictor
// per iteration). Throws InputError on a missing or malformed file.
std::shared_ptr<const LearnedModel> loadLearnedModel(const std::filesystem::path& file);

std::filesystem::path learnedModelBeside(const std::filesystem::path& materialsFile);

}  // namespace pl
