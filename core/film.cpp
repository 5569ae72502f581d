#include "core/film.h"

#include <unordered_map>

namespace pl {

void Film::poolResiduals() {
    struct Moment {
        double residual = 0, residualSq = 0;
        double samples = 0;
    };
    std::unordered_map<int32_t, Moment> moments;
    for (const auto& pixel : acc_)
        for (const Accumulator& a : pixel)
            if (a.poolKey >= 0) {
                Moment& m = moments[a.poolKey];
                m.residual += a.residualSum;
                m.residualSq += a.residualSqSum;
                m.samples += a.pooledSamples;
            }
    for (auto& pixel : acc_)
        for (Accumulator& a : pixel) {
            if (a.poolKey < 0 || a.count == 0) continue;
            const Moment& m = moments[a.poolKey];
            // Variance of the mean of n samples, pooledSamples of them with
            // the pooled residual second moment (a bound on its variance) or variance.
            double perSample = m.residualSq / m.samples;
            if (a.poolWhereFlat) {
                const double mean = m.residual / m.samples;
                perSample = m.samples > 1 ? std::max(0.0, perSample - mean * mean) * m.samples / (m.samples - 1) : 0.0;
            }
            a.pooledError = float(std::sqrt(perSample * a.pooledSamples) / a.count);
        }
}

}  // namespace pl
