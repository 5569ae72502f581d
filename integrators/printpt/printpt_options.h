// printpt's switches: the struct holds them and their defaults, and
// printPtParameters() declares each once by its scene-file name
// (render.<key>, docs/scene-format.md), with its range and what it does,
// for the scene parser and bench's "printpt/key=value" configurations.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/option_table.h"

namespace pl {

struct PrintPtOptions {
    static constexpr float kAbsorbingAlbedo = 0.5f;
    bool mediumFirst = true;
    bool fresnelWeighting = true;
    float rrCap = 1.0f;  // Brecka: 0.99, which lets weights grow as (albedo / 0.99)^n
    int branches = 4;
    bool nee = false;
    float neeMaxKappa = 50.0f;
    float neePruneScale = 4.0f;
    float neeMinProbability = 0.05f;
    // Russian roulette on the NEE transmittance past this optical depth
    // (unbiased; trackers.h TransmittanceRoulette); 100: exact.
    float neeRouletteDepth = 2.0f;  // measured: docs/performance.md
    float rrThreshold = 0.25f;  // measured best on the test set (docs/performance.md)
    bool clearance = true;
    bool ballWalks = true;
    float ballMinMfp = 1.0f;  // smallest ball worth it, in mean free paths (docs/performance.md)
    // The threshold at collisions in absorbing resin (albedo below
    // kAbsorbingAlbedo in the path's channel: the inks and black).
    float rrThresholdAbsorbing = 1.0f;
    bool controlVariate = true;  // measured: docs/performance.md
    // Monte Carlo walks behind the mean of a wedge (a quarter of this) or
    // of a curved region (a 32nd); the half-space's mean is exact.
    int64_t controlWalks = int64_t(1) << 17;
    float controlProbe = 0.5f;  // diffusion lengths (ControlVariate::fit; measured in docs/performance.md)
    // Where that fails: a second try over this reach, if the body is a
    // diffusion length thick below the entry (curved surfaces); 0: none.
    float controlProbeShort = 0.0f;
    // How far (diffusion lengths) an edge is looked for; 0: half-space controls only.
    float controlEdgeReach = 6.0f;
    // Under convex curved surfaces that fail the flat probes: the control
    // under a paraboloid with the surface's principal curvatures (tabulated).
    bool controlCurved = true;
    // ... where the object holds a ball this many diffusion lengths deep
    // (and wide) below the entry (measured: docs/performance.md).
    float controlCurvedThickness = 2.0f;
    // ... and where the tabulated paraboloid follows the surface within this
    // many mean free paths at all 16 probes (measured: docs/performance.md).
    float controlCurvedTolerance = 1.0f;
    // Where the two walks part, the control's remainder is the mean of this
    // many independent continuations from its state (an unbiased estimate
    // of the remainder's expectation: less of its variance, more walks;
    // measured in docs/performance.md).
    int controlContinuations = 4;
    // Before a render, the sensor's survey rays (Sensor::surveyRay) are
    // counted by the control they would use; a wedge or curved control
    // (material, channel, shape) whose mean is a Monte Carlo estimate is
    // used only where its mean's walks come to at most this many per
    // surveyed entry that shares it (wedges: 512 entries, curved: 64):
    // otherwise they cost more than it saves (measured:
    // docs/performance.md). 0: every control is used. Half-space controls
    // have exact means and always run.
    int64_t controlMeanWalksPerEntry = 64;
};

// printpt's switches by their scene-file names (core/option_table.h).
using PrintPtParameter = OptionParameter<PrintPtOptions>;
const std::vector<PrintPtParameter>& printPtParameters();
inline std::string setPrintPtOption(PrintPtOptions& options, const std::string& name, double value) {
    return setOption(printPtParameters(), options, name, value);
}

}  // namespace pl
