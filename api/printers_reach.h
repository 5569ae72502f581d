// Targets the print can show at every point: the flat-face gamut
// (prepare/printer_gamut.h) is what halftoned mixtures show on a wide flat
// face; at edges, corners, thin walls and fine detail the print's blur
// shows less (darker, less saturated). The loop finds where: a voxel whose
// request has stayed beyond the flat-face gamut for the loop's last
// iterations is printed at the printer's limit, and what its prediction
// still lacks in the direction the request was pushed out of the gamut is
// the printer's limit there, not the loop's error. That shortfall, where
// significant against the predictions' noise, is taken off the voxel's
// target when the loop ends: the judge and the report measure the loop
// against what the print can show; the mapping loss holds the rest.
//
// The loop itself keeps aiming at the flat-face targets (its best effort
// where the printer is at its limit): re-mapped while it still closed in,
// the greek cube's targets took off errors the loop would have removed,
// and its print ended 7.0 (re-mapped after 3 iterations beyond) and 4.6
// (after 6) from the flat-face targets, against 4.0 without.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "compare/colour_difference.h"

namespace pl {

class PrintersReach {
public:
    // Iterations in a row, up to the loop's end, a request must lie beyond
    // the gamut; the least shortfall kept (Delta E*ab).
    static constexpr int kIterationsBeyond = 6;
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
    // After each move. Within a run beyond the gamut, the evidence is
    // averaged with weights halving into the past (as much noise as a mean
    // of three iterations; the first ones, where the loop still closed in,
    // weigh little).
    void update(const Evidence& e);

    // The targets with the limits found taken off (linear sRGB reflectance
    // per surface voxel, `mapped` the flat-face ones). The shortfall is the
    // wide one plus the footprint's detail shrunk by James-Stein's rule
    // against its noise (sharp at edges, not blotched by noise on faces),
    // kept where over three standard errors and over kLeastShortfall; it is
    // measured over the eye's footprint, as the loop and the judge see the
    // targets, so there the re-mapped targets show no seam.
    std::vector<RGB> remap(const std::vector<RGB>& mapped);

    // Per surface voxel, after remap: whether it is at the printer's limit.
    const std::vector<uint8_t>& atLimit() const { return atLimit_; }

private:
    // Per voxel: the iterations in a row beyond the gamut, the averages
    // over them of the shortfall's direction and of the target minus the
    // prediction at both scales, and those averages' noise variances at
    // both (the samples may rise during a run).
    std::vector<uint16_t> run_;
    std::vector<std::array<float, 3>> outward_, error_, errorWide_;
    std::vector<std::array<float, 2>> variance_;
    std::vector<uint8_t> atLimit_;
};

}  // namespace pl
