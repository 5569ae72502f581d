// Targets the print can show at every point: the flat-face gamut
// (prepare/printer_gamut.h) is what halftoned mixtures show on a wide flat
// face; at edges, corners, thin walls and fine detail the print's blur
// shows less (darker, less saturated). The loop finds where: a voxel whose
// request stays beyond the flat-face gamut for several iterations is
// printed at the printer's limit, and what its prediction still lacks in
// the direction the request was pushed out of the gamut, once the loop
// has closed in, is the printer's limit there, not the loop's error. That shortfall, once significant
// against the predictions' noise, is taken off the voxel's target
// (frozen: the loop no longer chases it). The shortfall is measured over
// the eye's footprint, as the loop and the judge see the targets, so the
// re-mapped targets show no seam there. What is left, the error across
// that direction and everywhere else, is the loop's.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "compare/colour_difference.h"
#include "compare/surface_gaussian.h"

namespace pl {

class PrintersReach {
public:
    // Iterations in a row a request must lie beyond the gamut before its
    // shortfall is taken off; the first of them are not measured (the loop
    // still closing in: measured from the start, the greek cube's targets
    // took off errors the loop would have removed, and its print ended
    // 7.0 from the flat-face targets against 4.0 without the re-map); and
    // the least shortfall kept (Delta E*ab).
    static constexpr int kIterationsBeyond = 6;
    static constexpr int kIterationsClosingIn = 3;
    static constexpr double kLeastShortfall = 1.0;

    explicit PrintersReach(size_t voxels);

    // What a move of the requests answered, per surface voxel (CIELAB):
    // the target and the prediction over the eye's footprint and over
    // three (the wide scale, a tenth of the noise), the variance per
    // component of one prediction's noise at both scales, whether the
    // moved request lay beyond the gamut and in which direction (from the
    // printable request to the wanted one, any length).
    struct Evidence {
        const std::vector<Lab>&goal, &predicted, &goalWide, &predictedWide;
        double noiseVariance, noiseVarianceWide;
        const std::vector<uint8_t>& beyond;
        const std::vector<std::array<float, 3>>& outward;
    };
    // After each move; returns whether voxels newly reached the printer's
    // limit. The shortfall is the wide one plus the footprint's detail
    // shrunk by James-Stein's rule against its noise (sharp at edges, not
    // blotched by noise on faces).
    bool update(const Evidence& e);

    // The targets with the limits found taken off (linear sRGB reflectance
    // per surface voxel). Runs under way start again where the target
    // moved (their sums were against the old one).
    std::vector<RGB> remap(const std::vector<RGB>& mapped, const SurfaceGaussian& eye);


    // Per surface voxel: whether it is at the printer's limit.
    const std::vector<uint8_t>& atLimit() const { return atLimit_; }
    double atLimitShare() const;

private:
    void clearRun(size_t voxel);
    // Per voxel: the iterations in a row beyond the gamut, the sums over
    // the measured ones of the shortfall's direction, of the target minus
    // the prediction at both scales and of the predictions' noise
    // variances at both (the samples may rise during a run); and, once at
    // the limit, the shift of its target.
    std::vector<uint16_t> run_;
    std::vector<std::array<float, 3>> outwardSum_, errorSum_, errorWideSum_, shift_;
    std::vector<std::array<float, 2>> varianceSum_;
    std::vector<uint8_t> atLimit_;
    std::vector<RGB> seenShift_;  // the shifts over the eye's footprint at the last remap
};

}  // namespace pl
