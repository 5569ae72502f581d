#include "api/printers_reach.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace pl {

PrintersReach::PrintersReach(size_t voxels)
    : run_(voxels, 0), outwardSum_(voxels, {0, 0, 0}), errorSum_(voxels, {0, 0, 0}), shift_(voxels, {0, 0, 0}),
      atLimit_(voxels, 0) {}

bool PrintersReach::update(const std::vector<Lab>& goal, const std::vector<Lab>& predicted, double noiseVariance,
                           const std::vector<uint8_t>& beyond, const std::vector<std::array<float, 3>>& outward) {
    const size_t n = run_.size();
    std::vector<uint8_t> found(n, 0);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        if (atLimit_[i]) return;
        if (!beyond[i]) {
            run_[i] = 0;
            outwardSum_[i] = errorSum_[i] = {0, 0, 0};
            return;
        }
        const std::array<float, 3>& o = outward[i];
        const float length = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        if (!(length > 0)) return;
        const std::array<float, 3> error{goal[i].L - predicted[i].L, goal[i].a - predicted[i].a,
                                         goal[i].b - predicted[i].b};
        for (int c = 0; c < 3; ++c) {
            outwardSum_[i][size_t(c)] += o[size_t(c)] / length;
            errorSum_[i][size_t(c)] += error[size_t(c)];
        }
        if (++run_[i] < kIterationsBeyond) return;
        // The mean shortfall along the mean outward direction, kept when it
        // is more than two standard errors of the mean of the predictions'
        // noise along it (on a flat face, a target on the gamut's surface
        // sends its request out by noise alone, half of the time).
        const std::array<float, 3>& u = outwardSum_[i];
        const double uLength = std::sqrt(double(u[0]) * u[0] + double(u[1]) * u[1] + double(u[2]) * u[2]);
        if (!(uLength > 0)) return;
        const double runs = double(run_[i]);
        double shortfall = 0;
        for (int c = 0; c < 3; ++c) shortfall += double(errorSum_[i][size_t(c)]) / runs * u[size_t(c)] / uLength;
        if (shortfall <= 2 * std::sqrt(noiseVariance / runs)) return;
        for (int c = 0; c < 3; ++c) shift_[i][size_t(c)] = float(-shortfall * u[size_t(c)] / uLength);
        atLimit_[i] = 1;
        found[i] = 1;
    });
    return std::find(found.begin(), found.end(), uint8_t(1)) != found.end();
}

std::vector<RGB> PrintersReach::reachable(const std::vector<RGB>& mapped, const SurfaceGaussian& eye) const {
    std::vector<RGB> shift(shift_.size());
    for (size_t i = 0; i < shift.size(); ++i) shift[i] = {shift_[i][0], shift_[i][1], shift_[i][2]};
    const std::vector<RGB> smooth = eye.apply(shift);
    std::vector<RGB> out(mapped.size());
    tbb::parallel_for(size_t(0), mapped.size(), [&](size_t i) {
        const Lab m = labFromLinearSrgb(mapped[i]);
        out[i] = linearSrgbFromLab({m.L + smooth[i][0], m.a + smooth[i][1], m.b + smooth[i][2]});
    });
    return out;
}

double PrintersReach::atLimitShare() const {
    if (atLimit_.empty()) return 0;
    return double(std::count(atLimit_.begin(), atLimit_.end(), uint8_t(1))) / double(atLimit_.size());
}

}  // namespace pl
