// Deterministic radiative transfer in a homogeneous plane-parallel slab
// (or half-space) under smooth Fresnel boundaries: the light that a
// collimated beam, just inside the top face and travelling along its
// inward normal, brings out through each face. This is the exact mean of
// printpt's half-space control walk and the reference of the slab tests.
//
// Method: discrete ordinates for the azimuthally averaged radiance (the
// only Fourier mode a normally incident beam excites), solved in closed
// form per layer by the eigenvectors of the two-stream-coupled system
// (Chandrasekhar; Stamnes et al. 1988), with the beam as the radiance of a
// quadrature node at mu = 1 (as Prahl's adding-doubling puts it on a Radau
// node). The direction cosines are split at the critical angle, where the
// Fresnel factor has a square-root kink: Gauss-Legendre below it, a
// Gauss-Radau rule in t with mu = mu_c + (1 - mu_c) t^2 above it (smooth in
// t). The Henyey-Greenstein phase function enters through its Legendre
// series, renormalised so that the discrete scattering conserves energy.
// docs/formats.md ("What the standard errors include") says how its error
// is reported.
#pragma once

#include <limits>

namespace pl {

struct SlabMedium {
    double albedo = 0.9;  // single-scattering albedo, in [0, 1)
    double g = 0.0;       // Henyey-Greenstein anisotropy, |g| < 1
    double ior = 1.5;     // index of the medium over the outside's, >= 1
    // Optical thickness (sigma_t x thickness); infinity: a half-space.
    double opticalThickness = std::numeric_limits<double>::infinity();
};

// Fractions of the beam's flux that leave through the top face and through
// the bottom face (after Fresnel transmission).
struct SlabEscape {
    double top = 0, bottom = 0;
    // A bound on the discretisation error of top + bottom: the change from
    // the previous quadrature order (absolute).
    double error = 0;
};

// One solve with `nodes` directions on each side of the critical angle.
SlabEscape solveSlabEscape(const SlabMedium& medium, int nodes);
// Solves at increasing orders until two agree to 1e-9 (or the largest
// order is reached); the result of the last, with the change as its error.
SlabEscape slabEscape(const SlabMedium& medium);

// Unpolarised Fresnel reflectance (double precision) for light inside a
// medium of relative index ior, at internal cosine mu; 1 beyond the
// critical angle.
double fresnelFromInside(double mu, double ior);

// Quadrature on [-1, 1]: Gauss-Legendre (exact to degree 2n - 1) and
// Gauss-Radau with a node at +1 (exact to degree 2n - 2), nodes ascending.
void gaussLegendre(int n, double* nodes, double* weights);
void gaussRadauRight(int n, double* nodes, double* weights);

}  // namespace pl
