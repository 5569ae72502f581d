// printlight bench SCENE.json --transmittance: the transmittance along
// fixed segments inside the object, estimated exactly by regular tracking
// and without bias by ratio tracking and by pins
// (media/segment_transmittance.h), on the same segments: for each,
// the time per estimate, the variance (the mean over segments of each
// segment's own variance over repeated estimates), variance x time (lower
// is better) and the mean difference from the exact value with its error.
// Segments start just inside the surface, uniform by area, in
// cosine-weighted directions inwards, and run 2, 8 or 32 voxel sides or
// to the far side, whichever is nearer. One thread.
#pragma once

#include <cstdint>
#include <string>

#include "scene/scene.h"

namespace pl {

// The table (markdown).
std::string transmittanceTable(const Scene& scene, uint64_t seed);

}  // namespace pl
