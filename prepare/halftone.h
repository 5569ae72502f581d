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
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

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
// slice: wanted(i, f) says whether voxel i takes part and sets the
// fractions it asks for; chosen(i, m) receives the material index of each
// voxel that does.
void halftoneFrame(const Vec3i& resolution, const std::function<bool(size_t, MaterialFractions&)>& wanted,
                   const std::function<void(size_t, int)>& chosen);

}  // namespace pl
