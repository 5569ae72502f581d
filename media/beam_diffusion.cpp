#include "media/beam_diffusion.h"

#include <algorithm>
#include <cmath>

namespace pl {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Depth samples along the beam (pbrt-v3 takes 100, regularly spaced in
// the exponential's cumulative distribution).
constexpr int kBeamSamples = 100;

double hgPhase(double cosTheta, double g) {
    const double denominator = 1.0 + g * g - 2.0 * g * cosTheta;
    return (1.0 - g * g) / (4.0 * kPi * denominator * std::sqrt(denominator));
}

// Integral of f over [a, 1] where f has a square-root kink at a (Fresnel
// at the critical angle): mu = a + (1 - a) t^2, Gauss-Legendre in t.
template <class F>
double integrateAboveKink(double a, F f) {
    constexpr int n = 64;
    double nodes[n], weights[n];
    gaussLegendre(n, nodes, weights);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double t = 0.5 * (nodes[i] + 1.0);
        sum += 0.5 * weights[i] * f(a + (1.0 - a) * t * t) * 2.0 * (1.0 - a) * t;
    }
    return sum;
}

double criticalCosine(double ior) { return ior > 1.0 ? std::sqrt(1.0 - 1.0 / (ior * ior)) : 0.0; }

}  // namespace

double fresnelMomentInside(int n, double ior) {
    const double muC = criticalCosine(ior);
    // Below the critical cosine F = 1.
    return std::pow(muC, n + 1) / (n + 1) +
           integrateAboveKink(muC, [&](double mu) { return fresnelFromInside(mu, ior) * std::pow(mu, n); });
}

BeamDiffusion::BeamDiffusion(const SlabMedium& medium, double sigmaT_perMm)
    : albedo_(medium.albedo), g_(medium.g), ior_(medium.ior), sigmaT_perMm_(sigmaT_perMm) {
    const double sigmaS = albedo_ * sigmaT_perMm_, sigmaA = sigmaT_perMm_ - sigmaS;
    const double sigmaSReduced = (1.0 - g_) * sigmaS;
    sigmaTReduced_perMm_ = sigmaA + sigmaSReduced;
    albedoReduced_ = sigmaSReduced / sigmaTReduced_perMm_;
    D_mm_ = (2.0 * sigmaA + sigmaSReduced) / (3.0 * sigmaTReduced_perMm_ * sigmaTReduced_perMm_);  // Grosjean
    sigmaTr_perMm_ = std::sqrt(sigmaA / D_mm_);
    const double c1 = fresnelMomentInside(1, ior_), c2 = fresnelMomentInside(2, ior_);
    zb_mm_ = 2.0 * D_mm_ * (1.0 + 3.0 * c2) / (1.0 - 2.0 * c1);
    cPhi_ = 0.25 * (1.0 - 2.0 * c1);
    cE_ = 0.5 * (1.0 - 3.0 * c2);
}

double BeamDiffusion::dipole_perMm2(double r_mm, double zr_mm) const {
    const double zv_mm = -zr_mm - 2.0 * zb_mm_;
    const double dr = std::sqrt(r_mm * r_mm + zr_mm * zr_mm), dv = std::sqrt(r_mm * r_mm + zv_mm * zv_mm);
    const double er = std::exp(-sigmaTr_perMm_ * dr), ev = std::exp(-sigmaTr_perMm_ * dv);
    const double fluence = (er / dr - ev / dv) / (4.0 * kPi * D_mm_);
    const double flux = (zr_mm * (1.0 + sigmaTr_perMm_ * dr) * er / (dr * dr * dr) -
                         zv_mm * (1.0 + sigmaTr_perMm_ * dv) * ev / (dv * dv * dv)) /
                        (4.0 * kPi);
    return cPhi_ * fluence + cE_ * flux;
}

double BeamDiffusion::multipleScattering_perMm2(double r_mm, bool nearSurfaceCorrection) const {
    // First scatters along the beam, density sigma_s' exp(-sigma_t' z),
    // sampled from exp(-sigma_t' z) (weight alpha'); each source emits
    // alpha' of what it scatters (the improved diffusion source).
    double sum = 0;
    for (int i = 0; i < kBeamSamples; ++i) {
        const double z = -std::log(1.0 - (i + 0.5) / kBeamSamples) / sigmaTReduced_perMm_;
        double term = dipole_perMm2(r_mm, z);
        if (nearSurfaceCorrection)
            term *= 1.0 - std::exp(-2.0 * sigmaTReduced_perMm_ * (std::sqrt(r_mm * r_mm + z * z) + z));
        sum += term;
    }
    return albedoReduced_ * albedoReduced_ * sum / kBeamSamples;
}

double BeamDiffusion::singleScattering_perMm2(double r_mm) const {
    // Depths from which the exit point is seen inside the critical cone,
    // sampled from exp(-sigma_t (t - tCrit)).
    const double tCrit = r_mm * std::sqrt(std::max(0.0, ior_ * ior_ - 1.0));
    double sum = 0;
    for (int i = 0; i < kBeamSamples; ++i) {
        const double t = tCrit - std::log(1.0 - (i + 0.5) / kBeamSamples) / sigmaT_perMm_;
        const double d = std::sqrt(r_mm * r_mm + t * t), mu = t / d;
        sum += std::exp(-sigmaT_perMm_ * (d + tCrit)) / (d * d) * hgPhase(-mu, g_) * (1.0 - fresnelFromInside(mu, ior_)) * mu;
    }
    return albedo_ * sum / kBeamSamples;
}

double BeamDiffusion::singleScatteringTotal() const {
    return 2.0 * kPi * albedo_ * integrateAboveKink(criticalCosine(ior_), [&](double mu) {
               return hgPhase(-mu, g_) * (1.0 - fresnelFromInside(mu, ior_)) * mu / (1.0 + mu);
           });
}

double BeamDiffusion::multipleScatteringTotalWithoutCorrection() const {
    // Over the plane, a dipole at depth zr leaves C_phi (e^{-s zr} -
    // e^{-s |zv|}) / (2 D s) + C_E (e^{-s zr} + e^{-s |zv|}) / 2, s = sigma_tr;
    // integrated over the sources' exponential depths.
    const double s = sigmaTr_perMm_, k = sigmaTReduced_perMm_;
    const double depth = k / (k + s), image = std::exp(-2.0 * s * zb_mm_);
    return albedoReduced_ * albedoReduced_ * depth *
           (cPhi_ * (1.0 - image) / (2.0 * D_mm_ * s) + cE_ * (1.0 + image) / 2.0);
}

BeamDiffusionTable::BeamDiffusionTable(double g, double ior) {
    constexpr int kAlbedos = 100, kRadii = 64;
    for (int i = 0; i < kAlbedos; ++i)
        albedos_.push_back((1.0 - std::exp(-8.0 * i / (kAlbedos - 1))) / (1.0 - std::exp(-8.0)));
    radii_.push_back(0.0);
    radii_.push_back(2.5e-3);
    while (radii_.size() < kRadii) radii_.push_back(radii_.back() * 1.2);
    ringValues_.assign(albedos_.size() * radii_.size(), 0.0);
    totals_.assign(albedos_.size(), 0.0);
    for (size_t a = 0; a < albedos_.size(); ++a) {
        if (!(albedos_[a] < 1.0)) albedos_[a] = 1.0 - 1e-6;  // no diffusion without absorption (half-space)
        const BeamDiffusion d({albedos_[a], g, ior}, 1.0);
        for (size_t i = 1; i < radii_.size(); ++i) {
            const double r = radii_[i];
            ringValues_[a * radii_.size() + i] =
                2.0 * kPi * r * (d.singleScattering_perMm2(r) + d.multipleScattering_perMm2(r));
        }
        // The total over the radii, each step taken as an exponential (the
        // ring value is finite at 0).
        ringValues_[a * radii_.size()] = ringValues_[a * radii_.size() + 1];
        for (size_t i = 1; i < radii_.size(); ++i) {
            const double v0 = ringValues_[a * radii_.size() + i - 1], v1 = ringValues_[a * radii_.size() + i];
            const double step = radii_[i] - radii_[i - 1];
            totals_[a] += v0 > 0 && v1 > 0 && v0 != v1 ? (v1 - v0) * step / std::log(v1 / v0) : 0.5 * (v0 + v1) * step;
        }
    }
}

std::pair<size_t, double> BeamDiffusionTable::bracket(const std::vector<double>& knots, double x) {
    if (!(x > knots.front())) return {0, 0.0};
    if (!(x < knots.back())) return {knots.size() - 2, 1.0};
    const size_t above = size_t(std::upper_bound(knots.begin(), knots.end(), x) - knots.begin());
    return {above - 1, (x - knots[above - 1]) / (knots[above] - knots[above - 1])};
}

double BeamDiffusionTable::profile_perMm2(double albedo, double sigmaT_perMm, double r_mm) const {
    const double r = r_mm * sigmaT_perMm;  // optical units
    if (!(r < radii_.back()) || !(r > 0.0)) return 0.0;
    const auto [a, wa] = bracket(albedos_, albedo);
    const auto [i, wr] = bracket(radii_, r);
    // Along r as an exponential (single scattering falls by e^-2 per mean
    // free path: linear steps of 1.2x would read it 20 % high), across
    // albedos linearly.
    auto alongRadius = [&](size_t ai) {
        const double v0 = ringValues_[ai * radii_.size() + i], v1 = ringValues_[ai * radii_.size() + i + 1];
        return v0 > 0 && v1 > 0 ? v0 * std::pow(v1 / v0, wr) : (1 - wr) * v0 + wr * v1;
    };
    const double ring = (1 - wa) * alongRadius(a) + wa * alongRadius(a + 1);
    // Back from the ring value in optical units to mm^-2.
    return sigmaT_perMm * sigmaT_perMm * ring / (2.0 * kPi * r);
}

double BeamDiffusionTable::total(double albedo) const {
    const auto [a, wa] = bracket(albedos_, albedo);
    return (1 - wa) * totals_[a] + wa * totals_[a + 1];
}

}  // namespace pl
