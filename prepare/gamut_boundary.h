// The printer's gamut as a solid in CIELAB's lightness, chroma and hue: per
// hue slice and band of lightness, the most chromatic colour of a fine
// grid of mixtures (Morovic and Luo's segment maxima, 2000), joined in
// order of lightness and closed by the neutral axis between the darkest
// and the lightest colour. What the perceptual intent compresses towards
// (prepare/rendering_intent.h); the inverse's nearest colour takes up
// what the descriptor misses.
#pragma once

#include <utility>
#include <vector>

#include "prepare/printer_gamut.h"

namespace pl {

class GamutBoundary {
public:
    // From the colours of the mixtures of gridMixtures(levels), in slices of
    // 360 / hueSlices degrees.
    explicit GamutBoundary(const PrinterGamut& gamut, int levels = 32, int hueSlices = 72);

    double darkestL() const { return darkestL_; }
    double lightestL() const { return lightestL_; }
    // The largest chroma at lightness L and hue hue_deg (0 outside the
    // lightness range), linear in hue between the slices' centres.
    double maxChroma(double L, double hue_deg) const;
    // The lightness of the hue's most chromatic colour (its cusp).
    double cuspLightness(double hue_deg) const;

private:
    using Slice = std::vector<std::pair<double, double>>;  // (L*, C*), L* rising
    static double chromaOn(const Slice& slice, double L);
    // The two slices around a hue and the weight of the second.
    void slicesAround(double hue_deg, int& first, int& second, double& weight) const;
    double darkestL_ = 0, lightestL_ = 100;
    std::vector<Slice> slices_;
};

}  // namespace pl
