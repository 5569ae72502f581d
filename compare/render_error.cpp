#include "compare/render_error.h"

#include <algorithm>
#include <cmath>

namespace pl {

namespace {

// From the sums of squared errors per channel and of relative squared
// errors over n pixels.
RenderError errorOf(const double squaredError[3], double relativeSquaredError, size_t n) {
    RenderError e;
    for (int c = 0; c < 3; ++c) e.rmse[c] = float(std::sqrt(squaredError[c] / double(n)));
    e.rmseAll = std::sqrt((squaredError[0] + squaredError[1] + squaredError[2]) / (3.0 * n));
    e.relMse = relativeSquaredError / (3.0 * n);
    return e;
}

}  // namespace

RenderError errorAgainstReference(const Film& film, const Sensor& sensor, const std::vector<RGB>& referenceMean) {
    double se[3] = {0, 0, 0}, rel = 0;
    size_t n = 0;
    for (size_t p = 0; p < film.pixelCount(); ++p) {
        int64_t i = sensor.pixelImageIndex(p);
        if (i < 0) continue;  // hidden in the atlas: not in the reference image
        ++n;
        for (int c = 0; c < 3; ++c) {
            double r = referenceMean[size_t(i)][c], d = film.mean(p, c) - r;
            se[c] += d * d;
            rel += d * d / (r * r + 1e-3);
        }
    }
    return errorOf(se, rel, n);
}

RenderError selfVarianceError(const Film& film, const MeanSquares& relativeTo) {
    double se[3] = {0, 0, 0}, rel = 0;
    size_t n = film.pixelCount();
    for (size_t p = 0; p < n; ++p)
        for (int c = 0; c < 3; ++c) {
            double mSq = relativeTo[p][c], v = std::pow(double(film.spreadError(p, c)), 2) +
                                               std::pow(double(film.sharedError(p, c)), 2);
            se[c] += v;
            rel += v / (mSq + 1e-3);
        }
    return errorOf(se, rel, n);
}

MeanSquares ownMeanSquares(const Film& film) {
    MeanSquares m(film.pixelCount());
    for (size_t p = 0; p < m.size(); ++p)
        for (int c = 0; c < 3; ++c) m[p][c] = double(film.mean(p, c)) * film.mean(p, c);
    return m;
}

MeanSquares pooledMeanSquares(const std::vector<Film>& films, const std::vector<double>& rmse) {
    const size_t n = films.front().pixelCount();
    MeanSquares pooled(n, {0, 0, 0});
    double weights = 0;
    for (size_t i = 0; i < films.size(); ++i) {
        const double w = 1.0 / std::max(rmse[i] * rmse[i], 1e-30);
        weights += w;
        for (size_t p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c) pooled[p][c] += w * films[i].mean(p, c);
    }
    for (auto& pixel : pooled)
        for (double& v : pixel) {
            const double m = v / weights;
            v = m * m;
        }
    return pooled;
}

double timeToTarget(double seconds, double medianRelativeError, double target) {
    return medianRelativeError <= target ? seconds : seconds * std::pow(medianRelativeError / target, 2);
}

}  // namespace pl
