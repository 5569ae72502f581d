// Halftoning: continuous linear RGB targets to one printer material per
// voxel.
//  - fractionsForColor: a documented simple mixing model (subtractive
//    coverage with grey-component replacement): c = 1-R, m = 1-G, y = 1-B,
//    k = min(c, m, y); cyan, magenta, yellow = c-k, m-k, y-k; black = k;
//    white = 1 - (cyan + magenta + yellow + black). Real pipelines replace
//    it by a measured model; the halftoner only needs fractions summing to 1.
//  - ErrorDiffusionHalftoner: vector error diffusion in 3D (in the spirit of
//    Brunton et al. 2015): voxels are visited slice by slice, row by row,
//    serpentine in x; each takes the material with the largest target plus
//    accumulated error, and the difference between what it wanted and what
//    it got goes to unvisited neighbours (5/16 next in the row, 3/16, 2/16,
//    1/16 in the next row, 5/16 in the next slice), renormalised over the
//    neighbours that take part, so material fractions are preserved.
//  - Halftoning by thresholds (materialAtThreshold): ordered dithering with
//    a blue-noise threshold matrix (prepare/threshold_matrix.h).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/enum_names.h"
#include "core/rgb.h"
#include "core/vecmath.h"
#include "media/materials.h"

namespace pl {

constexpr int kPrintMaterials = 5;  // cyan, magenta, yellow, black, white
using MaterialFractions = std::array<float, kPrintMaterials>;
// Labels of the research convention for the five materials.
constexpr Label kPrintMaterialLabel[kPrintMaterials] = {kCyanLabel, kMagentaLabel, kYellowLabel, kBlackLabel,
                                                        kWhiteLabel};

MaterialFractions fractionsForColor(const RGB& linear);

// How mixtures become labels: vector error diffusion, thresholds of a
// blue-noise matrix, or each voxel's largest fraction (no halftone).
enum class HalftoneMethod { ErrorDiffusion, Thresholds, Nearest };
inline constexpr std::array<EnumName<HalftoneMethod>, 3> kHalftoneMethodNames{
    {{HalftoneMethod::ErrorDiffusion, "error-diffusion"},
     {HalftoneMethod::Thresholds, "thresholds"},
     {HalftoneMethod::Nearest, "nearest"}}};

// Halftoning by thresholds: the materials, from the lightest to the
// darkest (white, yellow, cyan, magenta, black), share [0, 1) by their
// fractions, and a voxel takes the one whose share holds its threshold
// (ThresholdMatrix::at). A voxel's material follows from its own fractions
// alone: a request whose materials' shares move by d relabels the share of
// its voxels that the boundaries between the shares sweep (2d when d moves
// from white to cyan past yellow), where error diffusion carries any change
// along the rest of the slice. The darkness of a uniform mixture's pattern is a monotone
// function of the blue-noise matrix, so its grain is blue too.
int materialAtThreshold(const MaterialFractions& fractions, float threshold);
// The same with hysteresis, for a voxel that holds material `current`: it
// keeps it while its share comes within `hysteresis` of the threshold (a
// request that only wanders by its noise relabels nothing; a loop that
// sees the print corrects the lag).
int materialAtThreshold(const MaterialFractions& fractions, float threshold, int current, float hysteresis);

// The material index of a print label, or -1 (not one of the five).
int printMaterialOf(Label label);

// The material of each voxel that has no neighbours' say: its largest fraction.
int largestFraction(const MaterialFractions& fractions);

class ThresholdMatrix;
// A voxel's material decided alone: by the matrix's threshold at `voxel`
// (with hysteresis for a voxel holding material `current`, -1: none), or
// without a matrix its largest fraction.
int materialOfVoxel(const MaterialFractions& fractions, const ThresholdMatrix* thresholds, const Vec3i& voxel,
                    int current = -1, float hysteresis = 0.0f);

class ErrorDiffusionHalftoner {
public:
    ErrorDiffusionHalftoner(int resX, int resY);

    // Halftones one slice; call for z = 0, 1, 2, ... in order.
    // targets[y * resX + x] are the voxels' fractions, active[...] says
    // which voxels take part; chosen[...] receives the material index.
    void halftoneSlice(int z, const std::vector<MaterialFractions>& targets,
                       const std::vector<uint8_t>& active, std::vector<uint8_t>& chosen);

private:
    int resX_, resY_;
    std::vector<MaterialFractions> error_, nextError_;
};

// Halftones a frame's voxels (index x fastest, then y, then z) slice by
// slice by error diffusion: wanted(i, f) says whether voxel i takes part
// and sets the fractions it asks for; chosen(i, m) receives the material
// index of each voxel that does.
void halftoneFrame(const Vec3i& resolution, const std::function<bool(size_t, MaterialFractions&)>& wanted,
                   const std::function<void(size_t, int)>& chosen);

}  // namespace pl
