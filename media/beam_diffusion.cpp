#include "media/beam_diffusion.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

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
    struct Rule {
        double nodes[n], weights[n];
        Rule() { gaussLegendre(n, nodes, weights); }
    };
    static const Rule rule;
    const double* nodes = rule.nodes;
    const double* weights = rule.weights;
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

namespace {
constexpr int kTableAlbedos = 100, kTableRadii = 64;
constexpr double kFirstRadius = 2.5e-3, kRadiusStep = 1.2;
// Albedo knot i is (1 - e^{-8 i / 99}) / (1 - e^{-8}).
constexpr double kAlbedoSpread = 8.0;
}  // namespace

BeamDiffusionTable::BeamDiffusionTable(double g, double ior, Parts parts) {
    for (int i = 0; i < kTableAlbedos; ++i)
        albedos_.push_back((1.0 - std::exp(-kAlbedoSpread * i / (kTableAlbedos - 1))) / (1.0 - std::exp(-kAlbedoSpread)));
    radii_.push_back(0.0);
    radii_.push_back(kFirstRadius);
    while (radii_.size() < kTableRadii) radii_.push_back(radii_.back() * kRadiusStep);
    ringValues_.assign(albedos_.size() * radii_.size(), 0.0);
    totals_.assign(albedos_.size(), 0.0);
    for (size_t a = 0; a < albedos_.size(); ++a) {
        // No diffusion without absorption (half-space): the last knot is just below 1.
        const SlabMedium medium{std::min(albedos_[a], 1.0 - 1e-6), g, ior};
        const BeamDiffusion d(medium, 1.0);
        for (size_t i = 1; i < radii_.size(); ++i) {
            const double r = radii_[i];
            const double single = parts == Parts::SingleAndMultiple ? d.singleScattering_perMm2(r) : 0.0;
            ringValues_[a * radii_.size() + i] = 2.0 * kPi * r * (single + d.multipleScattering_perMm2(r));
        }
        // The total over the radii, each step taken as an exponential (the
        // ring value is finite at 0).
        ringValues_[a * radii_.size()] = ringValues_[a * radii_.size() + 1];
        withinRadius_.push_back(0.0);
        for (size_t i = 1; i < radii_.size(); ++i) {
            const double v0 = ringValues_[a * radii_.size() + i - 1], v1 = ringValues_[a * radii_.size() + i];
            const double step = radii_[i] - radii_[i - 1];
            totals_[a] += v0 > 0 && v1 > 0 && v0 != v1 ? (v1 - v0) * step / std::log(v1 / v0) : 0.5 * (v0 + v1) * step;
            withinRadius_.push_back(totals_[a]);
        }
        if (parts == Parts::MultipleMatchedToHalfSpace && albedos_[a] > 0 && totals_[a] > 0) {
            const double wanted = slabEscape(medium).top - d.singleScatteringTotal();
            const double scale = std::max(0.0, wanted) / totals_[a];
            for (size_t i = 0; i < radii_.size(); ++i) {
                ringValues_[a * radii_.size() + i] *= scale;
                withinRadius_[a * radii_.size() + i] *= scale;
            }
            totals_[a] *= scale;
        }
    }
    for (double v : ringValues_) logRingValues_.push_back(v > 0 ? float(std::log(v)) : -HUGE_VALF);
    // The Laplacian in the plane of a radial f is f'' + f' / r = (1 / r^2)
    // d^2 f / du^2 with u = ln r: second differences over the knots, which
    // are regular in u (0 at the first and last).
    laplacians_.assign(ringValues_.size(), 0.0);
    const double du = std::log(kRadiusStep);
    for (size_t a = 0; a < albedos_.size(); ++a)
        for (size_t i = 2; i + 1 < radii_.size(); ++i) {
            auto f = [&](size_t k) { return ringValues_[a * radii_.size() + k] / (2.0 * kPi * radii_[k]); };
            laplacians_[a * radii_.size() + i] = (f(i + 1) - 2.0 * f(i) + f(i - 1)) / (du * du * radii_[i] * radii_[i]);
        }
}

std::pair<int, float> BeamDiffusionTable::albedoKnot(double albedo) const {
    // Single precision: the lookups are the predictor's inner loop.
    static const float kAlbedoScale = float(1.0 - std::exp(-kAlbedoSpread));
    if (!(albedo > 0.0)) return {0, 0.0f};
    const float x = -float(kTableAlbedos - 1) / float(kAlbedoSpread) * std::log(1.0f - float(albedo) * kAlbedoScale);
    if (!(x < kTableAlbedos - 1)) return {kTableAlbedos - 2, 1.0f};
    const int i = int(x);
    return {i, x - float(i)};
}

std::pair<int, float> BeamDiffusionTable::radiusKnot(double r) const {
    static const float kInverseLogStep = float(1.0 / std::log(kRadiusStep));
    if (r < kFirstRadius) return {0, float(r / kFirstRadius)};
    // The knot below from the logarithm; the weight linear in r.
    const int i = std::min(int(1.0f + std::log(float(r / kFirstRadius)) * kInverseLogStep), kTableRadii - 2);
    return {i, float((r - radii_[size_t(i)]) / (radii_[size_t(i) + 1] - radii_[size_t(i)]))};
}

double BeamDiffusionTable::ringAt(size_t k, float wr) const {
    // Along r as an exponential (single scattering falls by e^-2 per mean
    // free path: linear steps of 1.2x would read it 20 % high).
    const float l0 = logRingValues_[k], l1 = logRingValues_[k + 1];
    if (l0 > -HUGE_VALF && l1 > -HUGE_VALF) return double(std::exp(l0 + wr * (l1 - l0)));
    return (1 - wr) * ringValues_[k] + wr * ringValues_[k + 1];
}

double BeamDiffusionTable::profile_perMm2(double albedo, double sigmaT_perMm, double r_mm) const {
    const double r = r_mm * sigmaT_perMm;  // optical units
    if (!(r < radii_.back()) || !(r > 0.0)) return 0.0;
    const auto [a, wa] = albedoKnot(albedo);
    const auto [i, wr] = radiusKnot(r);
    // Across albedos linearly.
    const size_t k = size_t(a) * kTableRadii + size_t(i);
    const double ring = (1 - wa) * ringAt(k, wr) + wa * ringAt(k + kTableRadii, wr);
    // Back from the ring value in optical units to mm^-2.
    return sigmaT_perMm * sigmaT_perMm * ring / (2.0 * kPi * r);
}

double BeamDiffusionTable::spreadProfile_perMm2(double albedo, double sigmaT_perMm, double r_mm,
                                                double spread_mm2) const {
    const double r = r_mm * sigmaT_perMm;  // optical units
    if (!(r < radii_.back()) || !(r > 0.0)) return 0.0;
    const auto [a, wa] = albedoKnot(albedo);
    const auto [i, wr] = radiusKnot(r);
    const size_t k = size_t(a) * kTableRadii + size_t(i);
    auto lerp = [wr = wr](const std::vector<double>& v, size_t at) { return (1 - wr) * v[at] + wr * v[at + 1]; };
    double value = (1 - wa) * ringAt(k, wr) + wa * ringAt(k + kTableRadii, wr);
    double laplacian = (1 - wa) * lerp(laplacians_, k) + wa * lerp(laplacians_, k + kTableRadii);
    // Back to mm: R_mm(r) = sigma^2 R(sigma r), its Laplacian takes sigma^4.
    const double s2 = sigmaT_perMm * sigmaT_perMm;
    value *= s2 / (2.0 * kPi * r);
    laplacian *= s2 * s2;
    // Second order only: bounded where the spread is not small against r.
    return std::clamp(value + 0.25 * spread_mm2 * laplacian, 0.5 * value, 2.0 * value);
}

double BeamDiffusionTable::withinRadius(double albedo, double sigmaT_perMm, double r_mm) const {
    const double r = r_mm * sigmaT_perMm;
    if (!(r > 0.0)) return 0.0;
    if (!(r < radii_.back())) return total(albedo);
    const auto [a, wa] = albedoKnot(albedo);
    const auto [i, wr] = radiusKnot(r);
    auto alongRadius = [&, i = i, wr = wr](int ai) {
        const size_t k = size_t(ai) * kTableRadii + size_t(i);
        return (1 - wr) * withinRadius_[k] + wr * withinRadius_[k + 1];
    };
    return (1 - wa) * alongRadius(a) + wa * alongRadius(a + 1);
}

double BeamDiffusionTable::total(double albedo) const {
    const auto [a, wa] = albedoKnot(albedo);
    return (1 - wa) * totals_[size_t(a)] + wa * totals_[size_t(a) + 1];
}

namespace {
constexpr int kDepthSteps = 3000;  // over [0, kMaxOpticalDepth]: steps of 0.01
}

SingleScatteringDepthTable::SingleScatteringDepthTable(double g, double ior) {
    // cumulative(tau) = 2 pi int p(-mu) (1 - F(mu)) mu / (1 + mu) (1 - e^{-tau (1 + mu) / mu}) dmu
    // over the cosines that leave: the depth integral of e^{-tau} (in)
    // e^{-tau / mu} (out) in closed form.
    const double muC = criticalCosine(ior);
    for (int k = 0; k <= kDepthSteps; ++k) {
        const double tau = kMaxOpticalDepth * k / kDepthSteps;
        values_.push_back(2.0 * kPi * integrateAboveKink(muC, [&](double mu) {
                              return hgPhase(-mu, g) * (1.0 - fresnelFromInside(mu, ior)) * mu / (1.0 + mu) *
                                     (1.0 - std::exp(-tau * (1.0 + mu) / mu));
                          }));
    }
}

double SingleScatteringDepthTable::cumulative(double tau) const {
    const double x = tau / kMaxOpticalDepth * kDepthSteps;
    if (!(x < kDepthSteps)) return values_.back();
    if (!(x > 0.0)) return 0.0;
    const int i = int(x);
    const double w = x - i;
    return (1 - w) * values_[size_t(i)] + w * values_[size_t(i) + 1];
}

}  // namespace pl
