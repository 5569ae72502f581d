// What the light paths of a render did, counted over its paths (the
// render's report and bench's tables): summed across threads and ranks.
#pragma once

#include <cstdint>

namespace pl {

// The control variates printpt's walks can use (integrators/printpt/printpt.h).
enum class ControlKind { HalfSpace, Wedge, Curved };
constexpr int kControlKinds = 3;

struct PathStats {
    uint64_t paths = 0;
    uint64_t scatterEvents = 0;  // real collisions that scattered
    uint64_t ballEvents = 0;     // of which sampled inside printpt's homogeneous balls
    uint64_t leaks = 0;          // rays inside that found no boundary (mesh not closed)
    uint64_t trapped = 0;        // paths ended after kMaxBoundaryBounces without scattering
    uint64_t controlledWalks[kControlKinds] = {0, 0, 0};  // printpt's walks with a control, per ControlKind
    uint64_t allControlledWalks() const { return controlledWalks[0] + controlledWalks[1] + controlledWalks[2]; }
    void operator+=(const PathStats& o) {
        paths += o.paths;
        scatterEvents += o.scatterEvents;
        ballEvents += o.ballEvents;
        leaks += o.leaks;
        trapped += o.trapped;
        for (int k = 0; k < kControlKinds; ++k) controlledWalks[k] += o.controlledWalks[k];
    }
};

}  // namespace pl
