#include "media/slab_transport.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

namespace pl {

namespace {

constexpr double kPi = 3.14159265358979323846;

// P_n(x) and P_{n-1}(x) by the three-term recurrence.
void legendre(int n, double x, double& pn, double& pnm1) {
    double p0 = 1.0, p1 = x;
    if (n == 0) {
        pn = 1.0;
        pnm1 = 0.0;
        return;
    }
    for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    pn = p1;
    pnm1 = p0;
}

// The zeros of f in (-1, 1), bracketed on a fine Chebyshev grid and refined
// by bisection to round-off; `count` of them are expected.
std::vector<double> zerosIn(const std::function<double(double)>& f, int count) {
    std::vector<double> zeros;
    const int samples = 64 * (count + 2);
    double a = -1.0, fa = f(a);
    // The grid stops one step short of +1 (a Radau polynomial vanishes there).
    for (int k = 1; k < samples; ++k) {
        const double b = -std::cos(kPi * k / samples), fb = f(b);
        if (fa == 0.0) zeros.push_back(a);
        else if (fa * fb < 0.0) {
            double lo = a, hi = b, flo = fa;
            for (int it = 0; it < 200 && hi - lo > 1e-17; ++it) {
                const double mid = 0.5 * (lo + hi), fm = f(mid);
                if ((fm < 0.0) == (flo < 0.0)) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            zeros.push_back(0.5 * (lo + hi));
        }
        a = b;
        fa = fb;
    }
    if (int(zeros.size()) != count) throw std::logic_error("quadrature: wrong number of polynomial zeros");
    return zeros;
}

// Quadrature of mu in (0, 1] for the slab: Gauss-Legendre on [0, mu_c],
// Gauss-Radau in t on [mu_c, 1] with mu = mu_c + (1 - mu_c) t^2; the last
// node is mu = 1.
struct DirectionQuadrature {
    std::vector<double> mu, weight;
};

DirectionQuadrature directions(double muCritical, int nodes) {
    DirectionQuadrature q;
    std::vector<double> x(static_cast<size_t>(nodes)), w(static_cast<size_t>(nodes));
    if (muCritical > 0.0) {
        gaussLegendre(nodes, x.data(), w.data());
        for (int i = 0; i < nodes; ++i) {
            q.mu.push_back(0.5 * muCritical * (x[size_t(i)] + 1.0));
            q.weight.push_back(0.5 * muCritical * w[size_t(i)]);
        }
    }
    gaussRadauRight(nodes, x.data(), w.data());
    for (int i = 0; i < nodes; ++i) {
        const double t = 0.5 * (x[size_t(i)] + 1.0), dt = 0.5 * w[size_t(i)];
        q.mu.push_back(muCritical + (1.0 - muCritical) * t * t);
        q.weight.push_back(2.0 * (1.0 - muCritical) * t * dt);
    }
    return q;
}

}  // namespace

void gaussLegendre(int n, double* nodes, double* weights) {
    std::vector<double> z = zerosIn(
        [n](double x) {
            double pn, pnm1;
            legendre(n, x, pn, pnm1);
            return pn;
        },
        n);
    for (int i = 0; i < n; ++i) {
        double pn, pnm1;
        legendre(n, z[size_t(i)], pn, pnm1);
        // w = 2 (1 - x^2) / (n P_{n-1}(x))^2 at a zero of P_n.
        nodes[i] = z[size_t(i)];
        weights[i] = 2.0 * (1.0 - z[size_t(i)] * z[size_t(i)]) / (double(n) * n * pnm1 * pnm1);
    }
}

void gaussRadauRight(int n, double* nodes, double* weights) {
    // Interior nodes: the zeros of P_{n-1} - P_n other than +1.
    std::vector<double> z;
    if (n > 1)
        z = zerosIn(
            [n](double x) {
                double pn, pnm1;
                legendre(n, x, pn, pnm1);
                return pnm1 - pn;
            },
            n - 1);
    for (int i = 0; i + 1 < n; ++i) {
        double pn, pnm1;
        legendre(n, z[size_t(i)], pn, pnm1);
        nodes[i] = z[size_t(i)];
        weights[i] = (1.0 + z[size_t(i)]) / (double(n) * n * pnm1 * pnm1);
    }
    nodes[n - 1] = 1.0;
    weights[n - 1] = 2.0 / (double(n) * n);
}

double fresnelFromInside(double mu, double ior) {
    mu = std::clamp(mu, 0.0, 1.0);
    const double eta = 1.0 / ior;  // n_t / n_i
    const double sin2T = (1.0 - mu * mu) / (eta * eta);
    if (sin2T >= 1.0) return 1.0;
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rParl = (eta * mu - cosT) / (eta * mu + cosT);
    const double rPerp = (mu - eta * cosT) / (mu + eta * cosT);
    return 0.5 * (rParl * rParl + rPerp * rPerp);
}

SlabEscape solveSlabEscape(const SlabMedium& medium, int nodes) {
    if (!(medium.albedo >= 0.0 && medium.albedo < 1.0) || !(std::abs(medium.g) < 1.0) || !(medium.ior >= 1.0) ||
        !(medium.opticalThickness > 0.0) || nodes < 2)
        throw std::invalid_argument("slab transport: albedo in [0, 1), |g| < 1, ior >= 1, thickness > 0");
    const double muCritical = medium.ior > 1.0 ? std::sqrt(1.0 - 1.0 / (medium.ior * medium.ior)) : 0.0;
    const DirectionQuadrature q = directions(muCritical, nodes);
    const int n = int(q.mu.size());
    using Eigen::MatrixXd;
    using Eigen::VectorXd;

    // Azimuthally averaged phase function between directions i and j, both
    // downward (same) or one up (opposite): sum (2l+1)/2 g^l P_l P_l.
    MatrixXd same = MatrixXd::Zero(n, n), opposite = MatrixXd::Zero(n, n);
    int terms = 1;
    while (terms < 2000 && std::pow(std::abs(medium.g), terms) > 1e-17) ++terms;
    std::vector<std::vector<double>> P(static_cast<size_t>(n), std::vector<double>(static_cast<size_t>(terms)));
    for (int i = 0; i < n; ++i) {
        double p0 = 1.0, p1 = q.mu[size_t(i)];
        for (int l = 0; l < terms; ++l) {
            P[size_t(i)][size_t(l)] = p0;
            const double p2 = ((2.0 * l + 3.0) * q.mu[size_t(i)] * p1 - (l + 1.0) * p0) / (l + 2.0);
            p0 = p1;
            p1 = p2;
        }
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double s = 0, o = 0, gl = 1;
            for (int l = 0; l < terms; ++l, gl *= medium.g) {
                const double term = 0.5 * (2.0 * l + 1.0) * gl * P[size_t(i)][size_t(l)] * P[size_t(j)][size_t(l)];
                s += term;
                o += (l % 2 ? -term : term);
            }
            same(i, j) = s;
            opposite(i, j) = o;
        }
    // Light scattered from direction j goes somewhere: renormalise each
    // source direction's discrete redistribution to 1.
    for (int j = 0; j < n; ++j) {
        double total = 0;
        for (int i = 0; i < n; ++i) total += q.weight[size_t(i)] * (same(i, j) + opposite(i, j));
        same.col(j) /= total;
        opposite.col(j) /= total;
    }

    // mu dU+/dtau = -U+ + a (S W U+ + O W U-), -mu dU-/dtau = -U- + a (O W U+ + S W U-):
    // dU+/dtau = -A U+ + B U-, dU-/dtau = A U- - B U+.
    const double a = medium.albedo;
    MatrixXd A(n, n), B(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            A(i, j) = ((i == j ? 1.0 : 0.0) - a * same(i, j) * q.weight[size_t(j)]) / q.mu[size_t(i)];
            B(i, j) = a * opposite(i, j) * q.weight[size_t(j)] / q.mu[size_t(i)];
        }
    // S = U+ + U- obeys S'' = (A + B)(A - B) S: modes X e^{-lambda tau},
    // with D = U+ - U- = (A - B) X / lambda.
    const MatrixXd sum = A + B, difference = A - B;
    Eigen::EigenSolver<MatrixXd> eigen(sum * difference);
    if (eigen.info() != Eigen::Success) throw std::runtime_error("slab transport: eigen decomposition failed");
    MatrixXd down(n, n), up(n, n);  // decaying mode k: U+ = down.col(k), U- = up.col(k) at tau = 0
    VectorXd lambda(n);
    for (int k = 0; k < n; ++k) {
        const double l2 = eigen.eigenvalues()[k].real();
        if (!(l2 > 0.0) || std::abs(eigen.eigenvalues()[k].imag()) > 1e-9 * l2)
            throw std::runtime_error("slab transport: eigenvalue not real and positive");
        lambda[k] = std::sqrt(l2);
        const VectorXd X = eigen.eigenvectors().col(k).real();
        const VectorXd D = difference * X / lambda[k];
        down.col(k) = 0.5 * (X + D);
        up.col(k) = 0.5 * (X - D);
    }

    // Boundaries: U+(0) = F U-(0) + beam, U-(T) = F U+(T). The beam of unit
    // flux is the radiance of the node mu = 1: flux = sum w mu U (per 2 pi).
    VectorXd fresnel(n), escape(n);
    for (int i = 0; i < n; ++i) {
        fresnel[i] = fresnelFromInside(q.mu[size_t(i)], medium.ior);
        escape[i] = q.weight[size_t(i)] * q.mu[size_t(i)] * (1.0 - fresnel[i]);
    }
    VectorXd beam = VectorXd::Zero(n);
    beam[n - 1] = 1.0 / (q.weight[size_t(n - 1)] * q.mu[size_t(n - 1)]);
    const MatrixXd downBC = down - fresnel.asDiagonal() * up;  // (P - F M)
    const MatrixXd upBC = up - fresnel.asDiagonal() * down;    // (M - F P)

    SlabEscape result;
    if (std::isinf(medium.opticalThickness)) {
        const VectorXd c = downBC.partialPivLu().solve(beam);
        result.top = escape.dot(up * c);
        return result;
    }
    // Decaying modes c (from the top) and growing ones d, written as
    // e^{-lambda (T - tau)} with U+ and U- swapped (the slab's mirror image).
    const VectorXd fade = (-lambda * medium.opticalThickness).array().exp();
    MatrixXd system(2 * n, 2 * n);
    system.topLeftCorner(n, n) = downBC;
    system.topRightCorner(n, n) = upBC * fade.asDiagonal();
    system.bottomLeftCorner(n, n) = upBC * fade.asDiagonal();
    system.bottomRightCorner(n, n) = downBC;
    VectorXd rhs = VectorXd::Zero(2 * n);
    rhs.head(n) = beam;
    const VectorXd cd = system.partialPivLu().solve(rhs);
    const VectorXd c = cd.head(n), d = cd.tail(n);
    // U-(0) = M c + P E d; U+(T) = P E c + M d.
    result.top = escape.dot(up * c + down * (fade.asDiagonal() * d));
    result.bottom = escape.dot(down * (fade.asDiagonal() * c) + up * d);
    return result;
}

SlabEscape slabEscape(const SlabMedium& medium) {
    SlabEscape previous = solveSlabEscape(medium, 12);
    for (int nodes = 24;; nodes *= 2) {
        SlabEscape next = solveSlabEscape(medium, nodes);
        next.error = std::abs((next.top + next.bottom) - (previous.top + previous.bottom));
        if (next.error < 1e-9 || nodes >= 96) return next;
        previous = next;
    }
}

}  // namespace pl
