// printlight bench SCENE.json --error-check 1,2,8 [--configs ...] [--seed S]:
// whether each configuration's reported standard errors are honest at
// those sample counts. Two renders per configuration and count, seeds S
// and S + 1, compared value by value (compare/error_calibration.h).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "render/render.h"

namespace pl {

// The table (markdown) of mean z^2 per channel, the share with |z| > 4 and
// the share whose combined error is 0 where the renders differ, with each
// render's time. Across ranks every render is split over them; only rank 0
// gets the table.
std::string errorCheckTable(const Scene& scene, const Sensor& sensor,
                            const std::vector<std::pair<std::string, RenderSettings>>& configurations,
                            const std::vector<uint32_t>& spps, uint64_t seed, bool acrossRanks);

}  // namespace pl
