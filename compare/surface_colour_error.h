// Colour error on the object's surface as the eye sees it (the
// measure of a predictor against a converged reference): CIEDE2000 per
// surface voxel, and after both sides are averaged over the eye's
// footprint, a Gaussian on the surface (distances between the voxels'
// surface points).
#pragma once

#include <cstdint>
#include <vector>

#include "core/rgb.h"
#include "compare/surface_gaussian.h"
#include "core/vecmath.h"

namespace pl {

// The eye's footprint on a print seen at reading distance (sigma, mm).
constexpr float kEyeFootprint_mm = 0.2f;

struct SurfaceColourError {
    double mean = 0, p95 = 0;                  // per voxel
    double meanFiltered = 0, p95Filtered = 0;  // over the footprint
    std::vector<float> perVoxel;               // CIEDE2000 per voxel (unfiltered)
};

// Mean and 95th percentile (nearest rank) of the CIEDE2000 between two
// lists of linear sRGB colours.
struct DeltaEStats {
    double mean = 0, p95 = 0;
};
DeltaEStats deltaEStats(const std::vector<RGB>& a, const std::vector<RGB>& b);
// The mean and 95th percentile of some values.
DeltaEStats meanAndP95(std::vector<float> values);

// predicted, reference: reflectance (linear sRGB, white 1) per voxel, at
// points_mm.
SurfaceColourError surfaceColourError(const std::vector<Point3f>& points_mm, const std::vector<RGB>& predicted,
                                      const std::vector<RGB>& reference, float footprintSigma_mm = kEyeFootprint_mm);

// The same with a footprint built once (a loop scores many times).
SurfaceColourError surfaceColourError(const SurfaceGaussian& footprint, const std::vector<RGB>& predicted,
                                      const std::vector<RGB>& reference);

// The CIEDE2000 a render's own noise makes: the error between its colours
// and the same colours moved by one draw of their standard errors (normal,
// from `seed`). For noise small against the colours that is distributed
// as the error against the noiseless colours, so its mean is what the
// render's noise adds to a comparison (per voxel, and over the footprint).
SurfaceColourError noiseColourError(const std::vector<Point3f>& points_mm, const std::vector<RGB>& colours,
                                    const std::vector<RGB>& standardErrors, uint64_t seed = 1,
                                    float footprintSigma_mm = kEyeFootprint_mm);
SurfaceColourError noiseColourError(const SurfaceGaussian& footprint, const std::vector<RGB>& colours,
                                    const std::vector<RGB>& standardErrors, uint64_t seed = 1);

// Radiance (or its standard error) as reflectance: over the surroundings'
// radiance (0 where that is 0).
std::vector<RGB> reflectance(const std::vector<RGB>& radiance, const RGB& environment);

// The colours moved by one draw of their standard errors (normal, from
// `seed`; the same bits whatever the threads).
std::vector<RGB> movedByNoise(const std::vector<RGB>& colours, const std::vector<RGB>& standardErrors, uint64_t seed);

// A render judged from two independent halves (the same samples each,
// different seeds) against reference, per voxel and over the footprint.
// The halves' disagreement measures the noise of their mean for every
// estimator, samples shared between voxels included (light tracing): half
// their difference is distributed as the mean's own noise. The noise is
// also taken out of the error: the halves' errors dA, dB are independent
// draws around the same bias, so the polarised cross term
// (q(dA + dB) - q(dA - dB)) / 4, q(d) = CIEDE2000(reference, reference + d)^2,
// has the bias's q as its mean (exactly where q is quadratic, CIEDE2000's
// local form), whatever the noise.
struct SplitRenderError {
    SurfaceColourError error;       // the halves' mean against reference
    SurfaceColourError noise;       // the mean's own noise (mean and p95 CIEDE2000)
    double rmsFilteredNoiseRemoved = 0;  // root mean square CIEDE2000 over the footprint, noise taken out
    std::vector<RGB> meanSeen;           // the halves' mean over the footprint
    std::vector<float> deltaESeen;       // its CIEDE2000 from the reference over the footprint
};
SplitRenderError splitRenderError(const SurfaceGaussian& footprint, const std::vector<RGB>& halfA,
                                  const std::vector<RGB>& halfB, const std::vector<RGB>& reference);

// One footprint judged from two halves' colours a, b against the
// reference (as splitRenderError does for every voxel): CIEDE2000 of
// their mean, of its noise (half their difference), and q, the polarised
// cross term whose mean is the squared error without the noise.
struct FootprintError {
    double deltaE = 0, noiseDeltaE = 0, squareNoiseRemoved = 0;
};
FootprintError footprintError(const RGB& a, const RGB& b, const RGB& reference);

// A colour for a CIEDE2000 value (linear RGB): blue 0, green 2.5, yellow
// 5, red 10 and above.
RGB deltaEColour(float deltaE);

}  // namespace pl
