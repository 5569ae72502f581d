// How targets the printer cannot show become colours it can, as ICC
// workflows name them:
//  - colorimetric: each colour to the printable colour nearest it (minimum
//    Delta E clipping, CIE 156:2004's MinDE): colours inside the gamut stay
//    as they are, those outside collapse onto its surface (a bright yellow
//    becomes the darker yellow the resins give, its gradations flattened);
//  - perceptual: the whole of sRGB compressed into the gamut keeping hue
//    and the order of lightness and chroma, after CIE 156:2004's SGCK (in
//    CIELAB, where SGCK works in CIECAM97s, and with its lightness
//    compression linear where SGCK's is sigmoidal): lightness scaled from
//    sRGB's black and white to the printer's, the more the less chromatic
//    the colour; then chroma towards the hue's cusp lightness on the
//    neutral axis, left alone within 90 % of the way to the gamut's
//    boundary and the rest of the way to sRGB's boundary pressed into the
//    last 10 %. Colours inside the gamut move too (every colour keeps its
//    place relative to the others), and the nearest printable colour
//    takes up what the boundary descriptor misses.
#pragma once

#include <array>

#include "core/enum_names.h"
#include "prepare/gamut_boundary.h"

namespace pl {

enum class RenderingIntent { Colorimetric, Perceptual };
inline constexpr std::array<EnumName<RenderingIntent>, 2> kRenderingIntentNames{
    {{RenderingIntent::Colorimetric, "colorimetric"}, {RenderingIntent::Perceptual, "perceptual"}}};

class PerceptualIntent {
public:
    explicit PerceptualIntent(const PrinterGamut& gamut) : boundary_(gamut) {}
    // An sRGB colour (CIELAB) to the colour it is compressed to.
    Lab operator()(const Lab& source) const;

private:
    GamutBoundary boundary_;
};

}  // namespace pl
