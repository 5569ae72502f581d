// A render's error over all its pixels and channels, as printlight bench
// reports it (docs/performance.md, "What bench does"): against a
// converged reference, or against the render's own variance estimate
// (the expected squared error of an unbiased estimator), and what that
// error implies for the time a render needs.
#pragma once

#include <array>
#include <vector>

#include "core/film.h"
#include "core/rgb.h"
#include "core/sensors.h"

namespace pl {

struct RenderError {
    RGB rmse{0, 0, 0};    // per channel, over the pixels
    double rmseAll = 0;   // over every pixel channel
    double relMse = 0;    // mean of squared error / (squared mean + 1e-3)
};

// A squared mean per pixel and channel: what the relative MSE divides by.
using MeanSquares = std::vector<std::array<double, 3>>;

// Against a reference's means, laid out in the sensor's image
// (Sensor::pixelImageIndex); pixels the image hides are left out.
RenderError errorAgainstReference(const Film& film, const Sensor& sensor, const std::vector<RGB>& referenceMean);

// The film's own variance estimate as the expected squared error: per
// pixel the samples' spread (unbiased, so its sum over pixels is too,
// where a pixel's own may miss rare events; the per-pixel standard error,
// Film::standardError, is conservative there) and what samples share
// through printpt's estimated control means. The relative MSE divides by
// `relativeTo`: with the film's own means, whose noise differs from one
// configuration to the next, dark pixels weigh in by how noisy each
// render's estimate of their darkness is, and a noisier configuration can
// come out ahead (pooledMeanSquares).
RenderError selfVarianceError(const Film& film, const MeanSquares& relativeTo);

// The film's own means, squared.
MeanSquares ownMeanSquares(const Film& film);

// One denominator for several renders of the same pixels: their means
// pooled with weights 1 / MSE (rmse: each render's rmseAll), squared, so
// the comparison between them is like for like and the least noisy render
// counts most.
MeanSquares pooledMeanSquares(const std::vector<Film>& films, const std::vector<double>& rmse);

// MSE x time: lower is better; a ratio of two is their equal-error speed-up.
inline double mseTimesSeconds(double rmse, double seconds) { return rmse * rmse * seconds; }

// The time to bring a median relative error down to the target, from a
// render that took `seconds`: error falls as 1 / sqrt(time) for these
// estimators (an extrapolation where the render did not reach it; the
// render's own time where it did).
double timeToTarget(double seconds, double medianRelativeError, double target);

}  // namespace pl
