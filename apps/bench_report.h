// printlight bench's report: the tables (markdown and CSV), with the
// equal-error speed-up over the baseline (volpath, or else the first
// configuration) per budget, the ratio of MSE x time; the per-channel
// and colour tables; a log-log SVG plot of RMSE against time; and per
// configuration a PNG of its CIEDE2000 per surface voxel.
#pragma once

#include <string>
#include <vector>

#include "apps/bench_measurement.h"
#include "apps/limit_walk.h"
#include "render/scene_io.h"

namespace pl {

// Writes PREFIX.md, PREFIX.csv, PREFIX.svg and PREFIX_CONFIG_deltaE.png
// and prints the markdown. names: the configurations in the order asked;
// limit: the limit walk of the same run; threads: per rank.
void writeBenchTables(const Measured& measured, const Measurement& m, const std::vector<std::string>& names,
                      const SceneDescription& desc, const LimitWalkRate& limit, int threads, bool acrossRanks,
                      const std::string& prefix);

}  // namespace pl
