#include "compare/surface_reflectances.h"

#include <cmath>

namespace pl {

SurfaceReflectances surfaceReflectances(const Film& film, const SurfaceVoxelSensor& sensor,
                                        const std::vector<RGB>& referenceMean,
                                        const std::vector<RGB>& referenceStandardError, const RGB& environment) {
    SurfaceReflectances s;
    for (size_t p = 0; p < film.pixelCount(); ++p) {
        const int64_t i = sensor.pixelImageIndex(p);
        if (i < 0) continue;
        s.points_mm.push_back(sensor.pixels()[p].surfacePoint_mm);
        RGB f, r;
        for (int c = 0; c < 3; ++c) {
            f[c] = film.mean(p, c) / environment[c];
            r[c] = referenceMean[size_t(i)][c] / environment[c];
        }
        s.film.push_back(f);
        s.reference.push_back(r);
        s.imageIndex.push_back(i);
        for (int c = 0; c < 3; ++c) {
            const double e = std::hypot(double(film.standardError(p, c)), double(referenceStandardError[size_t(i)][c]));
            if (std::abs(double(film.mean(p, c)) - referenceMean[size_t(i)][c]) <= 2.0 * e) s.withinTwoErrors += 1;
        }
    }
    for (size_t k = 0; k < s.film.size(); ++k)
        for (int c = 0; c < 3; ++c) s.meanBias[c] += (s.film[k][c] - s.reference[k][c]) / float(s.film.size());
    if (!s.film.empty()) s.withinTwoErrors /= 3.0 * double(s.film.size());
    return s;
}

}  // namespace pl
