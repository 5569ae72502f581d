#include "api/printers_reach.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace pl {

PrintersReach::PrintersReach(size_t voxels)
    : run_(voxels, 0), outwardSum_(voxels, {0, 0, 0}), errorSum_(voxels, {0, 0, 0}), errorWideSum_(voxels, {0, 0, 0}),
      shift_(voxels, {0, 0, 0}), varianceSum_(voxels, {0, 0}), atLimit_(voxels, 0), seenShift_(voxels, RGB{0, 0, 0}) {}

bool PrintersReach::update(const Evidence& e) {
    const size_t n = run_.size();
    std::vector<uint8_t> found(n, 0);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        if (atLimit_[i]) return;
        if (!e.beyond[i]) {
            clearRun(i);
            return;
        }
        const std::array<float, 3>& o = e.outward[i];
        const float length = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        if (!(length > 0)) return;
        if (++run_[i] <= kIterationsClosingIn) return;
        const Lab &g = e.goal[i], &p = e.predicted[i], &gw = e.goalWide[i], &pw = e.predictedWide[i];
        const std::array<float, 3> error{g.L - p.L, g.a - p.a, g.b - p.b}, errorWide{gw.L - pw.L, gw.a - pw.a, gw.b - pw.b};
        for (size_t c = 0; c < 3; ++c) {
            outwardSum_[i][c] += o[c] / length;
            errorSum_[i][c] += error[c];
            errorWideSum_[i][c] += errorWide[c];
        }
        varianceSum_[i][0] += float(e.noiseVariance);
        varianceSum_[i][1] += float(e.noiseVarianceWide);
        if (run_[i] < kIterationsBeyond) return;
        // The mean shortfall along the mean outward direction, kept when it
        // is more than three standard errors of its noise (on a flat face, a
        // target on the gamut's surface sends its request out by noise
        // alone, half of the time).
        const std::array<float, 3>& u = outwardSum_[i];
        const double uLength = std::sqrt(double(u[0]) * u[0] + double(u[1]) * u[1] + double(u[2]) * u[2]);
        if (!(uLength > 0)) return;
        const double runs = double(run_[i] - kIterationsClosingIn);
        double along = 0, alongWide = 0;
        for (size_t c = 0; c < 3; ++c) {
            along += double(errorSum_[i][c]) / runs * u[c] / uLength;
            alongWide += double(errorWideSum_[i][c]) / runs * u[c] / uLength;
        }
        // The variances of the means (each iteration's own noise).
        const double detailVariance = varianceSum_[i][0] / (runs * runs);
        const double wideVariance = varianceSum_[i][1] / (runs * runs);
        const double detail = along - alongWide;
        const double shrink = detail != 0 ? std::max(0.0, 1.0 - detailVariance / (detail * detail)) : 0.0;
        const double shortfall = alongWide + shrink * detail;
        const double variance = wideVariance + shrink * shrink * detailVariance;
        if (shortfall <= std::max(kLeastShortfall, 3 * std::sqrt(variance))) return;
        for (size_t c = 0; c < 3; ++c) shift_[i][c] = float(-shortfall * u[c] / uLength);
        atLimit_[i] = 1;
        found[i] = 1;
    });
    return std::find(found.begin(), found.end(), uint8_t(1)) != found.end();
}

std::vector<RGB> PrintersReach::remap(const std::vector<RGB>& mapped, const SurfaceGaussian& eye) {
    std::vector<RGB> shift(shift_.size());
    for (size_t i = 0; i < shift.size(); ++i) shift[i] = {shift_[i][0], shift_[i][1], shift_[i][2]};
    // Where the eye sees the target move since the last time (by over 0.5
    // Delta E*ab), runs under way start again.
    const std::vector<RGB> seen = eye.apply(shift);
    std::vector<RGB> out(mapped.size());
    tbb::parallel_for(size_t(0), mapped.size(), [&](size_t i) {
        const Lab m = labFromLinearSrgb(mapped[i]);
        out[i] = linearSrgbFromLab({m.L + shift[i][0], m.a + shift[i][1], m.b + shift[i][2]});
        const RGB d{seen[i][0] - seenShift_[i][0], seen[i][1] - seenShift_[i][1], seen[i][2] - seenShift_[i][2]};
        if (!atLimit_[i] && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0.25) clearRun(i);
    });
    seenShift_ = seen;
    return out;
}

void PrintersReach::clearRun(size_t i) {
    run_[i] = 0;
    outwardSum_[i] = errorSum_[i] = errorWideSum_[i] = {0, 0, 0};
    varianceSum_[i] = {0, 0};
}

double PrintersReach::atLimitShare() const {
    if (atLimit_.empty()) return 0;
    return double(std::count(atLimit_.begin(), atLimit_.end(), uint8_t(1))) / double(atLimit_.size());
}

}  // namespace pl
