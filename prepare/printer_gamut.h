// The colours the printer can show: the reflectance of halftoned mixtures
// of its five printing materials on a flat face (a printer
// characterisation, as colour-printing pipelines make one; Babaei et al.
// 2017, Brunton et al. 2015), measured by rendering mixtures on a regular
// grid of the mixing simplex (api/printer_characterisation.h) and
// interpolated between them.
//  - Forward: mixture -> reflectance. Piecewise linear in Kubelka-Munk's
//    K/S = (1 - R)^2 / 2R (linear in the concentrations of the absorbers
//    and scatterers of an opaque layer; from a grid of step 1/2 it predicts
//    the step-1/4 grid within 2.4 CIEDE2000 on average, against 7.2 for
//    -ln R and 12.7 for R itself; docs/api.md) over the Kuhn
//    triangulation of the grid in cumulative coordinates (c, c+m, c+m+y,
//    c+m+y+k), whose simplices never cross the mixing simplex's faces.
//  - Inverse: a colour -> the mixture whose colour is nearest in CIELAB
//    (Euclidean, Delta E*ab): the best of a dense table of mixtures, then
//    projected Levenberg-Marquardt on the simplex. Inside the gamut it
//    reaches the colour; outside it is minimum-Delta-E clipping (CIE
//    156:2004's MinDE), the mapping of the target the loop aims at.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <absl/container/flat_hash_map.h>

#include "compare/colour_difference.h"
#include "prepare/halftone.h"

namespace pl {

class PrinterGamut {
public:
    // The grid's mixtures, fractions in multiples of 1/levels, in the order
    // the measurements are given.
    static std::vector<MaterialFractions> gridMixtures(int levels);

    // reflectance[i], standardError[i]: of gridMixtures(levels)[i].
    PrinterGamut(int levels, std::vector<RGB> reflectance, std::vector<RGB> standardError);

    int levels() const { return levels_; }
    const std::vector<RGB>& gridReflectance() const { return reflectance_; }
    const std::vector<RGB>& gridStandardError() const { return standardError_; }

    RGB reflectance(const MaterialFractions& mixture) const;
    Lab colour(const MaterialFractions& mixture) const { return labFromLinearSrgb(reflectance(mixture)); }

    struct Match {
        MaterialFractions mixture{};
        RGB reflectance{};
        Lab colour{};
        double deltaEab = 0;  // from the colour asked for
    };
    // The mixture whose colour is nearest `target`; from `start` (a
    // previous match, for a target that moved a little: at most maxSteps
    // descent steps) or else from the nearest of the dense table.
    Match closest(const Lab& target) const;
    Match closest(const Lab& target, const MaterialFractions& start, int maxSteps = 60) const;

private:
    int levels_;
    std::vector<RGB> reflectance_, standardError_;
    std::vector<std::array<float, 3>> absorptionOverScattering_;  // K/S per grid mixture
    std::vector<int32_t> gridIndexOfVertex_;     // cumulative coordinates -> grid index (-1: outside)
    std::vector<MaterialFractions> denseMixtures_;
    std::vector<Lab> denseColours_;
};

// prepare's mixtures from the gamut's inverse: each linear colour to the
// mixture of its nearest printable colour (after `compress`, if given: a
// rendering intent's, prepare/rendering_intent.h), the colour first
// rounded to 0.1 in CIELAB (a texture has few distinct colours, and the
// same rounded colour gets the same mixture whatever the order). One
// thread at a time.
class GamutMixing {
public:
    explicit GamutMixing(const PrinterGamut& gamut, std::function<Lab(const Lab&)> compress = {})
        : gamut_(gamut), compress_(std::move(compress)) {}
    MaterialFractions operator()(const RGB& linear);

private:
    const PrinterGamut& gamut_;
    std::function<Lab(const Lab&)> compress_;
    absl::flat_hash_map<uint64_t, MaterialFractions> known_;
};

}  // namespace pl
