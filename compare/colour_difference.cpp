#include "compare/colour_difference.h"

#include <cmath>

namespace pl {

namespace {
constexpr double kPiD = 3.14159265358979323846;
double degrees(double radians) { return radians * 180.0 / kPiD; }
double radians(double degrees) { return degrees * kPiD / 180.0; }

// sRGB primaries, D65 white (IEC 61966-2-1), white normalised to Y = 1.
constexpr double kXn = 0.95047, kYn = 1.0, kZn = 1.08883;
constexpr double kLabDelta = 6.0 / 29.0;
}  // namespace

Lab labFromLinearSrgb(const RGB& rgb) {
    const double r = rgb[0], g = rgb[1], b = rgb[2];
    const double X = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
    const double Y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
    const double Z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
    const double Xn = kXn, Yn = kYn, Zn = kZn;
    auto f = [](double t) {
        const double d = kLabDelta;
        return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
    };
    const double fx = f(X / Xn), fy = f(Y / Yn), fz = f(Z / Zn);
    return {float(116 * fy - 16), float(500 * (fx - fy)), float(200 * (fy - fz))};
}

RGB linearSrgbFromLab(const Lab& lab) {
    auto finv = [](double t) {
        const double d = kLabDelta;
        return t > d ? t * t * t : 3 * d * d * (t - 4.0 / 29.0);
    };
    const double fy = (lab.L + 16) / 116.0;
    const double X = kXn * finv(fy + lab.a / 500.0), Y = kYn * finv(fy), Z = kZn * finv(fy - lab.b / 200.0);
    return {float(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z), float(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
            float(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z)};
}

double hueDegrees(const Lab& lab) {
    const double h = degrees(std::atan2(double(lab.b), double(lab.a)));
    return h < 0 ? h + 360 : h;
}

double ciede2000(const Lab& x, const Lab& y) {
    const double L1 = x.L, a1 = x.a, b1 = x.b, L2 = y.L, a2 = y.a, b2 = y.b;
    const double C1 = std::hypot(a1, b1), C2 = std::hypot(a2, b2);
    const double Cbar7 = std::pow((C1 + C2) / 2, 7);
    const double G = 0.5 * (1 - std::sqrt(Cbar7 / (Cbar7 + std::pow(25.0, 7))));
    const double a1p = (1 + G) * a1, a2p = (1 + G) * a2;
    const double C1p = std::hypot(a1p, b1), C2p = std::hypot(a2p, b2);
    auto hue = [](double b, double ap) {
        if (b == 0 && ap == 0) return 0.0;
        double h = degrees(std::atan2(b, ap));
        return h < 0 ? h + 360 : h;
    };
    const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);
    const double dLp = L2 - L1, dCp = C2p - C1p;
    double dhp = 0;
    if (C1p * C2p != 0) {
        dhp = h2p - h1p;
        if (dhp > 180) dhp -= 360;
        else if (dhp < -180) dhp += 360;
    }
    const double dHp = 2 * std::sqrt(C1p * C2p) * std::sin(radians(dhp / 2));
    const double Lbarp = (L1 + L2) / 2, Cbarp = (C1p + C2p) / 2;
    double hbarp = h1p + h2p;
    if (C1p * C2p != 0) {
        if (std::abs(h1p - h2p) <= 180) hbarp /= 2;
        else hbarp = h1p + h2p < 360 ? (h1p + h2p + 360) / 2 : (h1p + h2p - 360) / 2;
    }
    const double T = 1 - 0.17 * std::cos(radians(hbarp - 30)) + 0.24 * std::cos(radians(2 * hbarp)) +
                     0.32 * std::cos(radians(3 * hbarp + 6)) - 0.20 * std::cos(radians(4 * hbarp - 63));
    const double dTheta = 30 * std::exp(-std::pow((hbarp - 275) / 25, 2));
    const double Cbarp7 = std::pow(Cbarp, 7);
    const double RC = 2 * std::sqrt(Cbarp7 / (Cbarp7 + std::pow(25.0, 7)));
    const double SL = 1 + 0.015 * (Lbarp - 50) * (Lbarp - 50) / std::sqrt(20 + (Lbarp - 50) * (Lbarp - 50));
    const double SC = 1 + 0.045 * Cbarp, SH = 1 + 0.015 * Cbarp * T;
    const double RT = -std::sin(radians(2 * dTheta)) * RC;
    const double l = dLp / SL, c = dCp / SC, h = dHp / SH;
    return std::sqrt(l * l + c * c + h * h + RT * c * h);
}

}  // namespace pl
