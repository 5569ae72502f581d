// Photon beam diffusion (Habel, Christensen and Jarosz 2013; the recipe of
// pbrt-v3's BeamDiffusionMS/SS, summarised with its equations in
// docs/diffusion.md): the light that a beam entering a homogeneous
// half-space along its inward normal brings out of the surface, per unit
// area at distance r from where it entered, per unit of the beam's power
// inside. Multiple scattering is the diffusion of dipoles placed along
// the beam (Grosjean's diffusion coefficient, the Kienle-Patterson
// boundary); single scattering is exact. The fast predictor's profile:
// its bias against the exact half-space (slab_transport.h)
// is measured in tests/test_beam_diffusion.cpp.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "media/slab_transport.h"

namespace pl {

// C_n = integral over [0, 1] of F(mu) mu^n dmu, F the Fresnel reflectance
// of light inside a medium of relative index ior at internal cosine mu.
double fresnelMomentInside(int n, double ior);

class BeamDiffusion {
public:
    // medium: albedo in [0, 1) (without absorption nothing bounds the
    // half-space's diffusion), g and ior (its optical thickness is
    // ignored: a half-space); sigmaT_perMm scales the profile to mm.
    BeamDiffusion(const SlabMedium& medium, double sigmaT_perMm);

    // Multiple scattering at distance r_mm, per mm^2. nearSurfaceCorrection:
    // Habel's factor for dipoles near the surface, 1 - exp(-2 sigma_t'
    // (d_r + z)); without it the integral has a closed form.
    double multipleScattering_perMm2(double r_mm, bool nearSurfaceCorrection = true) const;
    // Single scattering at distance r_mm, per mm^2 (grows as 1 / r at 0).
    double singleScattering_perMm2(double r_mm) const;

    // Over the whole plane: single scattering (exactly, a 1-D integral
    // over exit cosines) and multiple scattering without the near-surface
    // correction (closed form).
    double singleScatteringTotal() const;
    double multipleScatteringTotalWithoutCorrection() const;

    // The length over which diffusion spreads light, 1 / sigma_tr (mm;
    // infinite without absorption).
    double diffusionLength_mm() const { return 1.0 / sigmaTr_perMm_; }

private:
    // Exitance at r of one dipole whose real source is at depth zr.
    double dipole_perMm2(double r_mm, double zr_mm) const;

    double albedo_, g_, ior_;
    double sigmaT_perMm_, sigmaTReduced_perMm_, albedoReduced_;
    double D_mm_, sigmaTr_perMm_, zb_mm_;
    double cPhi_, cE_;
};

// The profile tabulated in optical units (sigma_t = 1) over albedos and
// radii, as pbrt-v3 does, for fast lookups: 2 pi r R(r) at 100 albedos
// (denser near 1) and 64 radii (0, then from 2.5e-3 mean free paths in
// steps of 1.2x), interpolated linearly across albedos and exponentially
// along r; one table per (g, ior). R is R_ss + R_ms, or, for a predictor
// that takes single scattering elsewhere, R_ms scaled per albedo so that
// with exact single scattering its total is the exact half-space's
// (slab_transport.h): PBD's shape, the right amount.
class BeamDiffusionTable {
public:
    enum class Parts { SingleAndMultiple, MultipleMatchedToHalfSpace };
    BeamDiffusionTable(double g, double ior, Parts parts = Parts::SingleAndMultiple);
    // The profile at r_mm in a medium of that albedo and extinction, per
    // mm^2 (0 beyond the table's last radius).
    double profile_perMm2(double albedo, double sigmaT_perMm, double r_mm) const;
    // The profile over the plane (the light a unit beam brings out).
    double total(double albedo) const;
    // The profile over the disc of radius r_mm around the beam.
    double withinRadius(double albedo, double sigmaT_perMm, double r_mm) const;
    // The profile's mean over sources spread about a point r_mm away with
    // a mean squared distance of spread_mm2 from it, in a plane: its value
    // plus spread / 4 times its Laplacian in the plane (second order; the
    // profile is convex, its value alone would read a spread source low).
    double spreadProfile_perMm2(double albedo, double sigmaT_perMm, double r_mm, double spread_mm2) const;

private:
    // Where an albedo or an optical radius falls among the knots: the
    // index below and the weight of the one above (in closed form: the
    // knots are regular in a transform of the value).
    std::pair<int, float> albedoKnot(double albedo) const;
    std::pair<int, float> radiusKnot(double r) const;
    // The ring value at table entry k (an albedo's row, a radius) towards
    // k + 1, wr of the way.
    double ringAt(std::size_t k, float wr) const;
    std::vector<double> albedos_, radii_;
    std::vector<double> ringValues_;  // 2 pi r R(r) per (albedo, radius), optical units
    std::vector<float> logRingValues_;
    std::vector<double> laplacians_;  // of R in the plane, per (albedo, radius), optical units
    std::vector<double> withinRadius_;  // the integral from 0 to each radius, per (albedo, radius)
    std::vector<double> totals_;        // per albedo
};

// Exact single scattering in a layered column (the diffusion predictor's
// single scattering, docs/diffusion.md): light entering along the inward
// normal, scattered once at optical depth tau (same depth along every
// way out: the layers are taken as laterally uniform) and leaving through
// the top after Fresnel. cumulative(tau) is the light single scattering
// brings out from the depths [0, tau] of a medium of albedo 1, per unit
// light inside; a layer of albedo a between tau0 and tau1 brings
// a (cumulative(tau1) - cumulative(tau0)). One table per (g, ior).
class SingleScatteringDepthTable {
public:
    SingleScatteringDepthTable(double g, double ior);
    double cumulative(double tau) const;
    // cumulative at infinite depth.
    double total() const { return values_.back(); }
    static constexpr double kMaxOpticalDepth = 30.0;  // beyond it e^-tau is below 1e-13

private:
    std::vector<double> values_;  // at regular depths over [0, kMaxOpticalDepth]
};

}  // namespace pl
