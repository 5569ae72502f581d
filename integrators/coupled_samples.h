// Samples of the previous labels and the current with the same random
// numbers (common random numbers), for a running estimate that carries
// over between predictions (api/predictor.h, recursive control variates,
// Nicolet et al. 2023): each sample's path is traced with the current
// labels, recording what it reads; only if it read something that changed
// is it traced again with the previous labels (a path that read nothing
// that changed is the same path under both, and their difference is 0).
// The pass's film receives f, the current labels' samples as a plain
// render's; `differences` receives f - h (h: the previous labels'), and
// `combined` (1 - w) f + w (f - h) = f - w h with the pixel's weight w
// chosen before the samples: the new samples' share of the running
// estimate w X_before + (1 - w) F + w D, whose spread it measures directly.
#pragma once

#include <cstdint>
#include <vector>

#include "core/film.h"
#include "integrators/path_footprints.h"

namespace pl {

struct CoupledSampling {
    const LabelMedium* previous = nullptr;  // the labels of the last prediction
    const LabelChanges* changes = nullptr;  // between those and the current
    Film* differences = nullptr;            // per pixel: f - h, no pool key
    std::vector<uint32_t>* tracedTwice = nullptr;  // per pixel: samples that read a change
    const std::vector<RGB>* weights = nullptr;     // per pixel: w
    Film* combined = nullptr;                      // per pixel: f - w h, no pool key
};

}  // namespace pl
