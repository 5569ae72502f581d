#include "core/film.h"

#include <unordered_map>

namespace pl {

void Film::poolResiduals() {
    struct Moment {
        double residualSum = 0, residualSqSum = 0;
        double samples = 0;
    };
    std::unordered_map<int32_t, Moment> moments;
    for (const auto& pixel : acc_)
        for (const Accumulator& a : pixel)
            if (a.poolKey >= 0) {
                Moment& m = moments[a.poolKey];
                m.residualSum += a.residualSum;
                m.residualSqSum += a.residualSqSum;
                m.samples += a.pooledSamples;
            }
    for (auto& pixel : acc_)
        for (Accumulator& a : pixel) {
            if (a.poolKey < 0 || a.count == 0) continue;
            const Moment& m = moments[a.poolKey];
            // Variance of the mean of n samples, pooledSamples of them with
            // the key's residual second moment (a bound on the variance) or,
            // pooled where flat, the key's residual variance.
            double perSample = m.residualSqSum / m.samples;
            if (a.poolWhereFlat) {
                const double mean = m.residualSum / m.samples;
                perSample = m.samples > 1 ? std::max(0.0, perSample - mean * mean) * m.samples / (m.samples - 1) : 0.0;
            }
            a.pooledError = float(std::sqrt(perSample * a.pooledSamples) / a.count);
        }
}

}  // namespace pl
