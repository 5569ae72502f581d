// printlight bench SCENE.json --loop CHANGES [--carry-over none,kept,...]:
// the optimisation loop's own measure on a recorded sequence of label
// changes (optimize --record-changes). For each way of predicting
// (afresh each iteration, or carried over: api/predictor.h), a predictor
// replays the changes and reports, per iteration, the noise its
// prediction adds over the eye's footprint (CIEDE2000, as optimize
// reports it), the seconds of the update and the render, and the surface
// voxels some of whose samples were traced again.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/label_changes_io.h"
#include "render/render.h"
#include "render/scene_io.h"

namespace pl {

// The table (markdown), one row per iteration, one column per method
// ("none", "kept", "control-variates"). Seeds: `seed` for kept samples,
// seed + iteration otherwise (as optimize).
std::string loopTable(const SceneDescription& desc, const RenderSettings& settings, const LabelChangeHistory& changes,
                      const std::vector<std::string>& methods, uint64_t seed);

}  // namespace pl
