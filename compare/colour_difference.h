// Colour difference as people see it: linear sRGB (D65) to CIE L*a*b* and
// the CIEDE2000 difference (Sharma, Wu and Dalal 2005), the measure the
// appearance-optimisation literature reports.
#pragma once

#include "core/rgb.h"

namespace pl {

struct Lab {
    float L, a, b;
};

// Linear sRGB (reflectance, white = 1) to L*a*b* under D65.
Lab labFromLinearSrgb(const RGB& rgb);
// And back (not clamped: a colour outside sRGB has components outside [0, 1]).
RGB linearSrgbFromLab(const Lab& lab);

// CIELAB's hue angle h_ab in degrees, [0, 360).
double hueDegrees(const Lab& lab);

// CIEDE2000 with kL = kC = kH = 1.
double ciede2000(const Lab& x, const Lab& y);

}  // namespace pl
