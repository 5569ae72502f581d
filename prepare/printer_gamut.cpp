#include "prepare/printer_gamut.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pl {

namespace {

// Mixtures on the grid, by cumulative coordinates B0 <= B1 <= B2 <= B3 in
// [0, levels] (B_j: levels x the fractions of materials 0..j).
template <typename Visit>
void forEachVertex(int levels, Visit visit) {
    for (int b0 = 0; b0 <= levels; ++b0)
        for (int b1 = b0; b1 <= levels; ++b1)
            for (int b2 = b1; b2 <= levels; ++b2)
                for (int b3 = b2; b3 <= levels; ++b3) visit(std::array<int, 4>{b0, b1, b2, b3});
}

size_t vertexKey(const std::array<int, 4>& b, int levels) {
    const size_t n = size_t(levels) + 1;
    return ((size_t(b[0]) * n + size_t(b[1])) * n + size_t(b[2])) * n + size_t(b[3]);
}

// The nearest point of the mixing simplex (Euclidean projection).
MaterialFractions projectOntoSimplex(const MaterialFractions& v) {
    MaterialFractions u = v;
    std::sort(u.begin(), u.end(), std::greater<float>());
    double sum = 0, theta = 0;
    for (int j = 0; j < kPrintMaterials; ++j) {
        sum += u[size_t(j)];
        const double t = (sum - 1.0) / (j + 1);
        if (u[size_t(j)] - t > 0) theta = t;
    }
    MaterialFractions x;
    for (int i = 0; i < kPrintMaterials; ++i) x[size_t(i)] = float(std::max(0.0, double(v[size_t(i)]) - theta));
    return x;
}

double squaredDistance(const Lab& x, const Lab& y) {
    const double dL = x.L - y.L, da = x.a - y.a, db = x.b - y.b;
    return dL * dL + da * da + db * db;
}

}  // namespace

std::vector<MaterialFractions> PrinterGamut::gridMixtures(int levels) {
    if (levels < 1) throw std::invalid_argument("PrinterGamut: at least one level");
    std::vector<MaterialFractions> mixtures;
    const float n = float(levels);
    forEachVertex(levels, [&](const std::array<int, 4>& b) {
        mixtures.push_back({float(b[0]) / n, float(b[1] - b[0]) / n, float(b[2] - b[1]) / n, float(b[3] - b[2]) / n,
                            float(levels - b[3]) / n});
    });
    return mixtures;
}

PrinterGamut::PrinterGamut(int levels, std::vector<RGB> reflectance, std::vector<RGB> standardError)
    : levels_(levels), reflectance_(std::move(reflectance)), standardError_(std::move(standardError)) {
    const size_t count = gridMixtures(levels).size();
    if (reflectance_.size() != count || standardError_.size() != count)
        throw std::invalid_argument("PrinterGamut: one reflectance and error per grid mixture");
    absorptionOverScattering_.resize(count);
    for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < 3; ++c) {
            const double R = std::clamp(double(reflectance_[i][size_t(c)]), 1e-6, 1.0);
            absorptionOverScattering_[i][size_t(c)] = float((1 - R) * (1 - R) / (2 * R));
        }
    const size_t n = size_t(levels) + 1;
    gridIndexOfVertex_.assign(n * n * n * n, -1);
    int32_t next = 0;
    forEachVertex(levels, [&](const std::array<int, 4>& b) { gridIndexOfVertex_[vertexKey(b, levels)] = next++; });
    // The dense table the inverse starts from: four times finer than the grid.
    const int denseLevels = std::max(4 * levels, 16);
    denseMixtures_ = gridMixtures(denseLevels);
    denseColours_.reserve(denseMixtures_.size());
    for (const MaterialFractions& m : denseMixtures_) denseColours_.push_back(colour(m));
}


RGB PrinterGamut::reflectance(const MaterialFractions& mixture) const {
    // Cumulative coordinates, scaled to the grid; the simplex of the Kuhn
    // triangulation holding them: base vertex, then one coordinate up at a
    // time in the order of the fractional parts (largest first; on ties the
    // later coordinate first, so every vertex stays ordered).
    const int n = levels_;
    std::array<double, 4> s{};
    double sum = 0;
    for (int j = 0; j < 4; ++j) {
        sum += std::max(0.0f, mixture[size_t(j)]);
        s[size_t(j)] = std::clamp(sum * n, j > 0 ? s[size_t(j) - 1] : 0.0, double(n));
    }
    std::array<int, 4> base{};
    std::array<double, 4> frac{};
    for (int j = 0; j < 4; ++j) {
        base[size_t(j)] = std::min(int(std::floor(s[size_t(j)])), n - 1);
        frac[size_t(j)] = s[size_t(j)] - base[size_t(j)];
    }
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return frac[size_t(a)] != frac[size_t(b)] ? frac[size_t(a)] > frac[size_t(b)] : a > b;
    });
    double d[3] = {0, 0, 0};
    std::array<int, 4> v = base;
    auto add = [&](double w) {
        if (w <= 0) return;
        const int32_t g = gridIndexOfVertex_[vertexKey(v, n)];
        for (int c = 0; c < 3; ++c) d[c] += w * absorptionOverScattering_[size_t(g)][size_t(c)];
    };
    add(1.0 - frac[size_t(order[0])]);
    for (int k = 0; k < 4; ++k) {
        ++v[size_t(order[size_t(k)])];
        add(frac[size_t(order[size_t(k)])] - (k < 3 ? frac[size_t(order[size_t(k) + 1])] : 0.0));
    }
    // Kubelka-Munk's reflectance of an opaque layer with that K/S.
    RGB r;
    for (int c = 0; c < 3; ++c) r[size_t(c)] = float(1 + d[c] - std::sqrt(d[c] * d[c] + 2 * d[c]));
    return r;
}

PrinterGamut::Match PrinterGamut::closest(const Lab& target) const {
    // From the few nearest mixtures of the dense table: the descent can
    // stall on a face of the simplex that a neighbouring start avoids.
    constexpr size_t kStarts = 4;
    std::vector<std::pair<double, size_t>> nearest;
    for (size_t i = 0; i < denseColours_.size(); ++i) {
        const double d = squaredDistance(denseColours_[i], target);
        if (nearest.size() < kStarts || d < nearest.back().first) {
            if (nearest.size() == kStarts) nearest.pop_back();
            nearest.insert(std::upper_bound(nearest.begin(), nearest.end(), std::make_pair(d, i)), {d, i});
        }
    }
    Match best = closest(target, denseMixtures_[nearest[0].second]);
    for (size_t k = 1; k < nearest.size() && best.deltaEab > 0.01; ++k) {
        const Match m = closest(target, denseMixtures_[nearest[k].second]);
        if (m.deltaEab < best.deltaEab) best = m;
    }
    return best;
}

PrinterGamut::Match PrinterGamut::closest(const Lab& target, const MaterialFractions& start, int maxSteps) const {
    // Projected Levenberg-Marquardt on the simplex. Moves trade each
    // material against the most abundant one (which always has room).
    MaterialFractions m = projectOntoSimplex(start);
    Lab c = colour(m);
    double cost = squaredDistance(c, target);
    double lambda = 1e-3;
    constexpr double h = 1e-3;
    // Until within 0.01 Delta E*ab, or a step shortens the squared distance
    // by under 0.01 % (outside the gamut: on its surface).
    for (int iteration = 0; iteration < maxSteps && cost > 1e-4; ++iteration) {
        const int pivot = int(std::max_element(m.begin(), m.end()) - m.begin());
        int free[4], k = 0;
        for (int i = 0; i < kPrintMaterials; ++i)
            if (i != pivot) free[k++] = i;
        double J[3][4];
        const double r[3] = {c.L - target.L, c.a - target.a, c.b - target.b};
        for (int j = 0; j < 4; ++j) {
            MaterialFractions q = m;
            q[size_t(free[j])] += float(h);
            q[size_t(pivot)] -= float(h);
            const Lab cq = colour(q);
            J[0][j] = (cq.L - c.L) / h, J[1][j] = (cq.a - c.a) / h, J[2][j] = (cq.b - c.b) / h;
        }
        double A[4][4], g[4];
        for (int i = 0; i < 4; ++i) {
            g[i] = 0;
            for (int e = 0; e < 3; ++e) g[i] += J[e][i] * r[e];
            for (int j = 0; j < 4; ++j) {
                A[i][j] = 0;
                for (int e = 0; e < 3; ++e) A[i][j] += J[e][i] * J[e][j];
            }
        }
        bool improved = false;
        for (int attempt = 0; attempt < 8; ++attempt) {
            // Solve (A + lambda (diag A + eps)) delta = -g by Gaussian elimination.
            double M[4][5];
            for (int i = 0; i < 4; ++i) {
                for (int j = 0; j < 4; ++j) M[i][j] = A[i][j] + (i == j ? lambda * (A[i][i] + 1e-3) : 0.0);
                M[i][4] = -g[i];
            }
            for (int col = 0; col < 4; ++col) {
                int piv = col;
                for (int row = col + 1; row < 4; ++row)
                    if (std::abs(M[row][col]) > std::abs(M[piv][col])) piv = row;
                std::swap(M[col], M[piv]);
                for (int row = col + 1; row < 4; ++row) {
                    const double f = M[row][col] / M[col][col];
                    for (int j = col; j < 5; ++j) M[row][j] -= f * M[col][j];
                }
            }
            double delta[4];
            for (int i = 3; i >= 0; --i) {
                double x = M[i][4];
                for (int j = i + 1; j < 4; ++j) x -= M[i][j] * delta[j];
                delta[i] = x / M[i][i];
            }
            MaterialFractions q = m;
            for (int j = 0; j < 4; ++j) {
                q[size_t(free[j])] += float(delta[j]);
                q[size_t(pivot)] -= float(delta[j]);
            }
            q = projectOntoSimplex(q);
            const Lab cq = colour(q);
            const double costQ = squaredDistance(cq, target);
            if (costQ < cost) {
                improved = cost - costQ > 1e-4 * cost;
                m = q, c = cq, cost = costQ;
                lambda = std::max(lambda / 3, 1e-7);
                break;
            }
            lambda *= 4;
        }
        if (!improved) break;
    }
    return {m, reflectance(m), c, std::sqrt(cost)};
}

MaterialFractions GamutMixing::operator()(const RGB& linear) {
    const Lab lab = labFromLinearSrgb(linear);
    // Tenths of L, a and b: the key packs them (offset to be positive) and
    // the colour searched for is made of them.
    const long L = std::lround(10.0f * lab.L), a = std::lround(10.0f * lab.a), b = std::lround(10.0f * lab.b);
    const auto field = [](long tenths) { return uint64_t(tenths + 0x80000) & 0xfffff; };
    const uint64_t key = (field(L) << 40) | (field(a) << 20) | field(b);
    if (auto found = known_.find(key); found != known_.end()) return found->second;
    const Lab rounded{float(L) / 10.0f, float(a) / 10.0f, float(b) / 10.0f};
    return known_[key] = gamut_.closest(compress_ ? compress_(rounded) : rounded).mixture;
}

}  // namespace pl
