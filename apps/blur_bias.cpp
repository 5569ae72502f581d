// blur-bias PREDICTION.vdb LABELS.vdb: the bias a photon-point estimator
// would carry on a surface-voxel prediction, measured on a render of it
// (docs/performance.md, "Photon points: the bias of blurring across
// voxels"). A photon kernel of radius r (a disc on the surface, in voxel
// widths) averaged over a patch expects the patch's radiance blurred with
// the disc: sum_j w_j L_j over the voxel's in-plane neighbours j. Per r it
// prints, over surface voxels and channels:
//  - the mean squared relative bias (sum_j w_j L_j - L) / L, noise
//    removed: the render's own error variance of that difference is
//    subtracted, so a value at or below 0 means "below what the render
//    resolves". L in the denominator is the mean radiance of the voxel's
//    label (the voxel's own value is as noisy as the difference). The
//    subtraction takes the voxels' errors as independent: true of the path
//    tracers' renders, not of lighttrace's (neighbours share particles);
//  - the same with every voxel's radiance replaced by the mean radiance of
//    its label (no noise: how much the halftone's own contrast blurs).
// Voxels are taken as flat faces: the plane is across the first axis on
// which a neighbour is void. Cubes are exact; curved models approximate.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/rng.h"
#include "core/vecmath.h"
#include "io/grid_io.h"
#include "media/label_grid.h"

namespace {

using namespace pl;

constexpr int kReach = 3;  // neighbours up to 3 voxels away in each in-plane axis
constexpr int kSide = 2 * kReach + 1;

// w[(du + kReach) * kSide + dv + kReach]: the share of a disc of radius r
// around a point uniform in the unit square [0,1]^2 that lands in the
// square offset by (du, dv). Monte Carlo, fixed seed.
std::vector<double> discWeights(double radius) {
    std::vector<double> w(kSide * kSide, 0.0);
    Rng rng(1, 0);
    const int n = 2000000;
    for (int i = 0; i < n; ++i) {
        const double cx = rng.uniform(), cy = rng.uniform();
        const double angle = 2 * kPi * rng.uniform(), rho = radius * std::sqrt(rng.uniform());
        const int du = int(std::floor(cx + rho * std::cos(angle))), dv = int(std::floor(cy + rho * std::sin(angle)));
        if (std::abs(du) <= kReach && std::abs(dv) <= kReach) w[(du + kReach) * kSide + dv + kReach] += 1.0 / n;
    }
    return w;
}

openvdb::Vec3SGrid::Ptr readVec3Grid(const char* path, const char* name) {
    openvdb::io::File file(path);
    file.open();
    auto grid = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid(name));
    file.close();
    if (!grid) throw std::runtime_error(std::string(path) + ": no Vec3f grid '" + name + "'");
    return grid;
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc != 3) {
        std::fprintf(stderr, "usage: blur-bias PREDICTION.vdb LABELS.vdb\n");
        return 2;
    }
    openvdb::initialize();
    const auto radiance = readVec3Grid(argv[1], "radiance"), stderrs = readVec3Grid(argv[1], "stderr");
    const LabelGrid labels = loadLabelGrid(argv[2], std::nullopt);
    // The prediction's voxels are at the label grid's own indices.
    auto labelAt = [&](const openvdb::Coord& k) { return int(labels.label({k.x(), k.y(), k.z()})); };
    auto L = radiance->getConstAccessor();
    auto S = stderrs->getConstAccessor();

    std::map<int, std::array<double, 4>> labelMean;  // R, G, B, count
    for (auto it = radiance->cbeginValueOn(); it; ++it) {
        auto& m = labelMean[labelAt(it.getCoord())];
        for (int c = 0; c < 3; ++c) m[c] += (*it)[c];
        m[3] += 1;
    }
    for (auto& [label, m] : labelMean) {
        for (int c = 0; c < 3; ++c) m[c] /= m[3];
        std::printf("label %d: %.0f surface voxels, mean radiance %.4f %.4f %.4f\n", label, m[3], m[0], m[1], m[2]);
    }
    std::printf("radius (voxels) | kernel area / voxel face | mean squared relative bias, noise removed | label-mean "
                "model: median / 75th percentile relative bias\n");
    for (double radius : {0.25, 0.5, 0.75, 1.0, 1.5, 2.0}) {
        const std::vector<double> w = discWeights(radius);
        double sumSquared = 0, count = 0;
        std::vector<double> modelBias;
        for (auto it = radiance->cbeginValueOn(); it; ++it) {
            const openvdb::Coord k = it.getCoord();
            int axis = -1;
            for (int a = 0; a < 3 && axis < 0; ++a) {
                openvdb::Coord up = k, down = k;
                up[a] += 1;
                down[a] -= 1;
                if (labelAt(up) == labels.voidLabel() || labelAt(down) == labels.voidLabel()) axis = a;
            }
            if (axis < 0) continue;
            // The blur over the neighbours that are surface voxels, renormalised.
            struct Neighbour { double w; openvdb::Coord k; };
            std::vector<Neighbour> neighbours;
            double wSum = 0;
            for (int du = -kReach; du <= kReach; ++du)
                for (int dv = -kReach; dv <= kReach; ++dv) {
                    openvdb::Coord q = k;
                    q[(axis + 1) % 3] += du;
                    q[(axis + 2) % 3] += dv;
                    const double wq = w[(du + kReach) * kSide + dv + kReach];
                    if (wq > 0 && L.isValueOn(q)) {
                        neighbours.push_back({wq, q});
                        wSum += wq;
                    }
                }
            std::array<double, 3> blurred{}, variance{}, modelBlurred{};
            for (const Neighbour& n : neighbours) {
                const double wn = n.w / wSum;
                const double wDiff = n.k == k ? wn - 1.0 : wn;  // weight in (blur - own value)
                const auto Ln = L.getValue(n.k), Sn = S.getValue(n.k);
                for (int c = 0; c < 3; ++c) {
                    blurred[c] += wn * Ln[c];
                    variance[c] += wDiff * wDiff * Sn[c] * Sn[c];
                    modelBlurred[c] += wn * labelMean[labelAt(n.k)][c];
                }
            }
            const auto own = L.getValue(k);
            const auto& mean = labelMean[labelAt(k)];
            for (int c = 0; c < 3; ++c) {
                if (!(mean[c] > 0)) continue;
                const double bias = blurred[c] - own[c];
                sumSquared += (bias * bias - variance[c]) / (mean[c] * mean[c]);
                count += 1;
                modelBias.push_back(std::abs(modelBlurred[c] - mean[c]) / mean[c]);
            }
        }
        if (modelBias.empty()) throw std::runtime_error("no surface voxel with an exposed face to blur over");
        std::sort(modelBias.begin(), modelBias.end());
        std::printf("%.2f | %.2f | %+.2e (rms %.1f %%) | %.1f %% / %.1f %%\n", radius, kPi * radius * radius,
                    sumSquared / count, 100 * std::sqrt(std::max(0.0, sumSquared / count)),
                    100 * modelBias[modelBias.size() / 2], 100 * modelBias[modelBias.size() * 3 / 4]);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "blur-bias: %s\n", e.what());
    return 1;
}
