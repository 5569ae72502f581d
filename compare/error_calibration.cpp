#include "compare/error_calibration.h"

#include <cmath>

namespace pl {

ErrorCalibration calibrateErrors(const PixelResults& a, const PixelResults& b, const std::vector<bool>& covered) {
    ErrorCalibration e;
    std::array<double, 3> zSqSum{};
    for (size_t p = 0; p < a.size() && p < b.size(); ++p) {
        if (!covered.empty() && !covered[p]) continue;
        for (int c = 0; c < 3; ++c) {
            const double sa = a.standardError[p][c], sb = b.standardError[p][c];
            const double d = double(a.mean[p][c]) - double(b.mean[p][c]);
            ++e.values;
            const double combined = std::sqrt(sa * sa + sb * sb);
            if (!(combined > 0)) {
                if (d != 0) {
                    ++e.zeroErrorButDiffer;
                    ++e.beyondFour;
                }
                continue;
            }
            const double z = d / combined;
            zSqSum[size_t(c)] += z * z;
            ++e.perChannel[size_t(c)];
            if (std::abs(z) > 4) ++e.beyondFour;
        }
    }
    for (size_t c = 0; c < 3; ++c) e.meanZSq[c] = e.perChannel[c] ? zSqSum[c] / double(e.perChannel[c]) : 0.0;
    return e;
}

ErrorCalibration calibrateErrors(const Film& a, const Film& b) {
    PixelResults ra, rb;
    std::vector<bool> covered(a.pixelCount());
    for (size_t p = 0; p < a.pixelCount(); ++p) {
        ra.mean.push_back(a.meanRGB(p));
        ra.standardError.push_back(a.standardErrorRGB(p));
        rb.mean.push_back(b.meanRGB(p));
        rb.standardError.push_back(b.standardErrorRGB(p));
        covered[p] = a.samples(p, 0) > 0 && b.samples(p, 0) > 0;
    }
    return calibrateErrors(ra, rb, covered);
}

}  // namespace pl
