#include "prepare/rendering_intent.h"

#include <algorithm>
#include <cmath>

namespace pl {

namespace {
constexpr double kKnee = 0.9;  // SGCK's: chroma within 90 % of the way to the boundary stays

// SGCK's weight of the lightness compression: 1 on the neutral axis, falling
// with chroma.
double lightnessWeight(double C) {
    const double c3 = C * C * C;
    return 1 - std::sqrt(c3 / (c3 + 5e5));
}

// The largest t in [0, most] for which inside(t) holds, by bisection
// (inside(0) holds; the solids are star-shaped about the focal point).
template <typename Inside>
double reach(Inside inside, double most) {
    if (inside(most)) return most;
    double lo = 0, hi = most;
    for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (lo + hi);
        (inside(mid) ? lo : hi) = mid;
    }
    return lo;
}
}  // namespace

Lab PerceptualIntent::operator()(const Lab& source) const {
    const double darkest = boundary_.darkestL(), lightest = boundary_.lightestL();
    const double scale = (lightest - darkest) / 100.0;  // sRGB's black and white at L* 0 and 100
    const double C = std::hypot(double(source.a), double(source.b));
    const double p = lightnessWeight(C);
    const double L = (1 - p) * source.L + p * (darkest + scale * source.L);
    if (C < 1e-6) return {float(L), source.a, source.b};
    const double hue_deg = hueDegrees(source), hue = hue_deg * double(kPi) / 180.0;
    const double cosHue = std::cos(hue), sinHue = std::sin(hue);
    // The ray from the hue's cusp lightness on the neutral axis through the
    // colour, in the (L*, C*) plane of its hue.
    const double focus = boundary_.cuspLightness(hue_deg);
    const double dL = L - focus, distance = std::hypot(dL, C);
    const double uL = dL / distance, uC = C / distance;
    const auto inGamut = [&](double t) {
        const double l = focus + t * uL;
        return l >= darkest && l <= lightest && t * uC <= boundary_.maxChroma(l, hue_deg);
    };
    // sRGB after the lightness compression: undo it and test the colour.
    const auto inSource = [&](double t) {
        const double c = t * uC, q = lightnessWeight(c);
        const double l = (focus + t * uL - q * darkest) / ((1 - q) + q * scale);
        if (l < 0 || l > 100) return false;
        const RGB rgb = linearSrgbFromLab({float(l), float(c * cosHue), float(c * sinHue)});
        return std::all_of(rgb.begin(), rgb.end(), [](float v) { return v >= -1e-4f && v <= 1 + 1e-4f; });
    };
    const double toGamut = reach(inGamut, 300.0);
    const double toSource = std::max(reach(inSource, 300.0), distance);
    // Beyond the knee, the rest of the way to sRGB's boundary into the
    // rest of the way to the gamut's; where sRGB ends first, nothing moves
    // (SGCK never pushes a colour outwards).
    double mapped = distance;
    const double knee = kKnee * toGamut;
    if (distance > knee && toSource > toGamut)
        mapped = knee + (distance - knee) * (toGamut - knee) / (toSource - knee);
    const double l = focus + mapped * uL, c = mapped * uC;
    return {float(l), float(c * cosHue), float(c * sinHue)};
}

}  // namespace pl
