// 3D-DDA (Amanatides & Woo 1987): visits, in order, the unit cells of an
// integer lattice that the ray o + t d crosses for t in [tStart, tEnd],
// restricted to the cell box [lo, hi). Zero direction components are fine:
// that axis never steps.
#pragma once

#include <cmath>
#include <limits>

#include "core/vecmath.h"

namespace pl {

// Clips [t0, t1] of the ray o + t d to the box [lo, hi) (slab test).
// Returns false if nothing is left.
inline bool clipRayToBox(const Vec3f& o, const Vec3f& d, const Vec3i& lo, const Vec3i& hi,
                         float& t0, float& t1) {
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0f) {
            if (o[a] < lo[a] || o[a] >= hi[a]) return false;
            continue;
        }
        float inv = 1.0f / d[a];
        float tn = (lo[a] - o[a]) * inv, tf = (hi[a] - o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
    }
    return t0 < t1;
}

struct DdaSegment {
    Vec3i cell;
    float t0, t1;  // ray parameter range inside the cell
};

class GridDda {
public:
    GridDda(const Vec3f& o, const Vec3f& d, float tStart, float tEnd, const Vec3i& lo,
            const Vec3i& hi) {
        constexpr float inf = std::numeric_limits<float>::infinity();
        float t0 = tStart, t1 = tEnd;
        if (!clipRayToBox(o, d, lo, hi, t0, t1)) { done_ = true; return; }
        tCur_ = t0;
        tEnd_ = t1;
        // Start in the cell holding the entry point, clamped against round-off.
        for (int a = 0; a < 3; ++a) {
            float p = o[a] + d[a] * t0;
            int c = int(std::floor(p));
            c = std::min(std::max(c, lo[a]), hi[a] - 1);
            cell_[a] = c;
            lo_[a] = lo[a];
            hi_[a] = hi[a];
            o_[a] = o[a];
            invD_[a] = d[a] != 0.0f ? 1.0f / d[a] : inf;
            if (d[a] > 0) {
                step_[a] = 1;
                tNext_[a] = (c + 1 - o[a]) * invD_[a];
            } else if (d[a] < 0) {
                step_[a] = -1;
                tNext_[a] = (c - o[a]) * invD_[a];
            } else {
                step_[a] = 0;
                tNext_[a] = inf;
            }
        }
    }

    // The next cell and its parameter range; false when the ray has left.
    bool next(DdaSegment& seg) {
        if (done_) return false;
        int axis = tNext_[0] < tNext_[1] ? (tNext_[0] < tNext_[2] ? 0 : 2)
                                         : (tNext_[1] < tNext_[2] ? 1 : 2);
        float tExit = std::min(std::max(tNext_[axis], tCur_), tEnd_);
        seg = {cell_, tCur_, tExit};
        tCur_ = tExit;
        if (tExit >= tEnd_) {
            done_ = true;
        } else {
            cell_[axis] += step_[axis];
            // Recompute from the cell rather than accumulating: no drift on long rays.
            tNext_[axis] = (cell_[axis] + (step_[axis] > 0 ? 1 : 0) - o_[axis]) * invD_[axis];
            if (cell_[axis] < lo_[axis] || cell_[axis] >= hi_[axis]) done_ = true;
        }
        return true;
    }

private:
    Vec3i cell_, step_, lo_, hi_;
    Vec3f o_, invD_, tNext_;
    float tCur_ = 0, tEnd_ = 0;
    bool done_ = false;
};

}  // namespace pl
