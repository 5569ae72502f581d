#include "api/printers_reach.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace pl {

PrintersReach::PrintersReach(size_t voxels)
    : run_(voxels, 0), outward_(voxels, {0, 0, 0}), error_(voxels, {0, 0, 0}), errorWide_(voxels, {0, 0, 0}),
      variance_(voxels, {0, 0}), atLimit_(voxels, 0) {}

void PrintersReach::update(const Evidence& e) {
    tbb::parallel_for(size_t(0), run_.size(), [&](size_t i) {
        const std::array<float, 3>& o = e.outward[i];
        const float length = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        if (!e.beyond[i] || !(length > 0)) {
            run_[i] = 0;
            return;
        }
        const Lab &g = e.goal[i], &p = e.predicted[i], &gw = e.goalWide[i], &pw = e.predictedWide[i];
        const std::array<float, 3> error{g.L - p.L, g.a - p.a, g.b - p.b}, errorWide{gw.L - pw.L, gw.a - pw.a, gw.b - pw.b};
        // Weights halving into the past: the average's variance is a
        // quarter of the last one's plus a quarter of the new noise's.
        const float keep = run_[i] == 0 ? 0.0f : 0.5f, add = 1.0f - keep;
        for (size_t c = 0; c < 3; ++c) {
            outward_[i][c] = keep * outward_[i][c] + add * o[c] / length;
            error_[i][c] = keep * error_[i][c] + add * error[c];
            errorWide_[i][c] = keep * errorWide_[i][c] + add * errorWide[c];
        }
        variance_[i][0] = keep * keep * variance_[i][0] + add * add * float(e.noiseVariance);
        variance_[i][1] = keep * keep * variance_[i][1] + add * add * float(e.noiseVarianceWide);
        if (run_[i] < UINT16_MAX) ++run_[i];
    });
}

std::vector<RGB> PrintersReach::remap(const std::vector<RGB>& mapped) {
    std::vector<RGB> out(mapped);
    tbb::parallel_for(size_t(0), mapped.size(), [&](size_t i) {
        atLimit_[i] = 0;
        if (run_[i] < kIterationsBeyond) return;
        const std::array<float, 3>& u = outward_[i];
        const double uLength = std::sqrt(double(u[0]) * u[0] + double(u[1]) * u[1] + double(u[2]) * u[2]);
        if (!(uLength > 0)) return;
        double along = 0, alongWide = 0;
        for (size_t c = 0; c < 3; ++c) {
            along += double(error_[i][c]) * u[c] / uLength;
            alongWide += double(errorWide_[i][c]) * u[c] / uLength;
        }
        const double detail = along - alongWide, detailVariance = variance_[i][0];
        const double shrink = detail != 0 ? std::max(0.0, 1.0 - detailVariance / (detail * detail)) : 0.0;
        const double shortfall = alongWide + shrink * detail;
        const double variance = variance_[i][1] + shrink * shrink * detailVariance;
        if (shortfall <= std::max(kLeastShortfall, 3 * std::sqrt(variance))) return;
        const Lab m = labFromLinearSrgb(mapped[i]);
        const double s = shortfall / uLength;
        out[i] = linearSrgbFromLab({float(m.L - s * u[0]), float(m.a - s * u[1]), float(m.b - s * u[2])});
        atLimit_[i] = 1;
    });
    return out;
}

}  // namespace pl
