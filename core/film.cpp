#include "core/film.h"

#include <unordered_map>

namespace pl {

void Film::poolResiduals() {
    struct Moment {
        double residualSq = 0;
        double samples = 0;
    };
    std::unordered_map<int32_t, Moment> moments;
    for (const auto& pixel : acc_)
        for (const Accumulator& a : pixel)
            if (a.poolKey >= 0) {
                Moment& m = moments[a.poolKey];
                m.residualSq += a.residualSqSum;
                m.samples += a.pooledSamples;
            }
    for (auto& pixel : acc_)
        for (Accumulator& a : pixel) {
            if (a.poolKey < 0 || a.count == 0) continue;
            const Moment& m = moments[a.poolKey];
            // Variance of the mean of n samples, pooledSamples of them with
            // the pooled residual second moment (a bound on its variance).
            a.pooledError = float(std::sqrt(m.residualSq / m.samples * a.pooledSamples) / a.count);
        }
}

}  // namespace pl
