// A random, stratified subset of the eye's footprints over a surface, for
// a judge that renders only them (each with its whole neighbourhood) and
// estimates the mean error over every footprint with a confidence
// interval. Footprints are SurfaceGaussian's: weights exp(-d^2 / (2
// sigma^2)) over the points within 3 sigma of the centre.
#pragma once

#include <cstdint>
#include <vector>

#include "core/rgb.h"
#include "core/vecmath.h"
#include "compare/surface_gaussian.h"

namespace pl {

class FootprintSample {
public:
    // `count` centres (at most one per point), one drawn uniformly from
    // each of `count` strata of equal size (to a point) along a Morton
    // order of the points (cells of the footprint's sigma): spread over the
    // surface, every point (nearly) as likely a centre as any other; the
    // same bits for the same seed. The footprints are `eye`'s, built on
    // the same points.
    FootprintSample(const std::vector<Point3f>& points_mm, const SurfaceGaussian& eye, float sigma_mm, size_t count,
                    uint64_t seed);

    size_t size() const { return centres_.size(); }
    // In the strata's order.
    const std::vector<uint32_t>& centres() const { return centres_; }
    // Every point some footprint weighs, sorted: what a judge renders.
    const std::vector<uint32_t>& points() const { return points_; }
    // The footprints' weighted means of values given for every point (or
    // only for points(); the others are not read).
    std::vector<RGB> apply(const std::vector<RGB>& values) const;

private:
    std::vector<uint32_t> centres_, points_;
    std::vector<std::vector<SurfaceGaussian::Weight>> weights_;  // per centre
};

// The mean of values drawn once per stratum (in the strata's order), as
// an estimate of their mean over the whole surface, with the half-width of
// its 95 % interval: the variance by collapsed strata (neighbouring strata
// paired, each pair's squared difference standing for the two strata's
// variances: conservative by the pair's difference of means, which the
// Morton order keeps small) and Student's t on the pairs' count.
struct SampledMean {
    double mean = 0, halfWidth95 = 0;
};
SampledMean stratifiedMean(const std::vector<double>& values);

}  // namespace pl
