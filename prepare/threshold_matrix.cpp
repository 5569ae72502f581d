#include "prepare/threshold_matrix.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "core/rng.h"

namespace pl {

namespace {

// A binary pattern on the tile (a torus) and its energy: every set voxel
// spreads a Gaussian of distance in mm, so the set voxel of most energy
// is the tightest cluster and the unset voxel of least the largest void.
class PatternEnergy {
public:
    PatternEnergy(const Vec3i& tile, const Vec3f& voxelSize_mm) : tile_(tile), set_(volume(tile), 0), energy_(volume(tile), 0.0) {
        // sigma: 1.5 times the mean voxel spacing (Ulichney's 1.5 pixels),
        // cut at 3 sigma and at half the tile (no voxel seen twice).
        const double spacing_mm = std::cbrt(double(voxelSize_mm.x) * voxelSize_mm.y * voxelSize_mm.z);
        const double sigma_mm = 1.5 * spacing_mm, cut_mm = 3 * sigma_mm;
        int reach[3];
        for (int a = 0; a < 3; ++a) reach[a] = std::min(int(cut_mm / voxelSize_mm[a]), (tile[a] - 1) / 2);
        for (int dz = -reach[2]; dz <= reach[2]; ++dz)
            for (int dy = -reach[1]; dy <= reach[1]; ++dy)
                for (int dx = -reach[0]; dx <= reach[0]; ++dx) {
                    const double x = dx * voxelSize_mm.x, y = dy * voxelSize_mm.y, z = dz * voxelSize_mm.z;
                    const double d2 = x * x + y * y + z * z;
                    if (d2 > cut_mm * cut_mm) continue;
                    offsets_.push_back({dx, dy, dz});
                    weights_.push_back(std::exp(-d2 / (2 * sigma_mm * sigma_mm)));
                }
    }
    static size_t volume(const Vec3i& t) { return size_t(t.x) * t.y * t.z; }
    size_t size() const { return set_.size(); }
    bool isSet(size_t i) const { return set_[i] != 0; }

    void toggle(size_t i) {
        const double sign = set_[i] ? -1.0 : 1.0;
        set_[i] ^= 1;
        const int x = int(i % tile_.x), y = int((i / tile_.x) % tile_.y), z = int(i / (size_t(tile_.x) * tile_.y));
        for (size_t k = 0; k < offsets_.size(); ++k) {
            const Vec3i& o = offsets_[k];
            const size_t j = (size_t(wrap(z + o.z, tile_.z)) * tile_.y + wrap(y + o.y, tile_.y)) * tile_.x +
                             wrap(x + o.x, tile_.x);
            energy_[j] += sign * weights_[k];
        }
    }
    // The set voxel of most energy (the first of equals).
    size_t tightestCluster() const { return extreme(1, [](double a, double b) { return a > b; }); }
    // The unset voxel of least energy (the first of equals).
    size_t largestVoid() const { return extreme(0, [](double a, double b) { return a < b; }); }

private:
    static int wrap(int v, int n) { return v < 0 ? v + n : (v >= n ? v - n : v); }
    template <class Better>
    size_t extreme(uint8_t state, Better better) const {
        size_t best = size_t(-1);
        for (size_t i = 0; i < set_.size(); ++i)
            if (set_[i] == state && (best == size_t(-1) || better(energy_[i], energy_[best]))) best = i;
        return best;
    }
    Vec3i tile_;
    std::vector<uint8_t> set_;
    std::vector<double> energy_;
    std::vector<Vec3i> offsets_;
    std::vector<double> weights_;
};

}  // namespace

ThresholdMatrix::ThresholdMatrix(const Vec3i& tile, const Vec3f& voxelSize_mm)
    : tile_(tile), threshold_(size_t(std::max(tile.x, 0)) * size_t(std::max(tile.y, 0)) * size_t(std::max(tile.z, 0))) {
    const size_t n = threshold_.size();
    if (n < 64) throw std::invalid_argument("a threshold matrix needs at least 64 voxels");
    std::vector<uint32_t> rank(n);
    // The initial pattern: a tenth of the voxels at random, then the
    // tightest cluster moved to the largest void until it moves back.
    PatternEnergy initial(tile, voxelSize_mm);
    Rng rng(0x9e3779b97f4a7c15ull, 7);
    size_t ones = 0;
    while (ones < n / 10) {
        const size_t i = size_t(rng.next32()) % n;
        if (!initial.isSet(i)) initial.toggle(i), ++ones;
    }
    for (size_t moves = 0; moves < 4 * n; ++moves) {
        const size_t cluster = initial.tightestCluster();
        initial.toggle(cluster);
        const size_t hole = initial.largestVoid();
        initial.toggle(hole);
        if (hole == cluster) break;
    }
    // Ranks below the initial count: its tightest clusters taken out, the
    // last first.
    PatternEnergy pattern = initial;
    for (size_t r = ones; r-- > 0;) {
        const size_t cluster = pattern.tightestCluster();
        pattern.toggle(cluster);
        rank[cluster] = uint32_t(r);
    }
    // The rest: the largest void filled next (with one filter for all
    // ranks, Ulichney's third phase is the same rule).
    pattern = std::move(initial);
    for (size_t r = ones; r < n; ++r) {
        const size_t hole = pattern.largestVoid();
        pattern.toggle(hole);
        rank[hole] = uint32_t(r);
    }
    for (size_t i = 0; i < n; ++i) threshold_[i] = (float(rank[i]) + 0.5f) / float(n);
}

Vec3i ThresholdMatrix::tileFor(const Vec3f& voxelSize_mm) {
    // About 16,000 voxels as near a cube in mm as powers of two give
    // (32 x 16 x 32 for the printer's 42 x 85 x 27 um: 1.35 x 1.36 x 0.86
    // mm), made in under a second.
    const double side_mm = std::cbrt(16384.0 * voxelSize_mm.x * voxelSize_mm.y * voxelSize_mm.z);
    Vec3i tile;
    for (int a = 0; a < 3; ++a) {
        const double n = std::clamp(side_mm / voxelSize_mm[a], 4.0, 128.0);
        tile[a] = 1 << int(std::lround(std::log2(n)));
    }
    return tile;
}

const ThresholdMatrix& ThresholdMatrix::forVoxel(const Vec3f& voxelSize_mm) {
    static std::mutex mutex;
    static std::map<std::tuple<float, float, float>, std::unique_ptr<ThresholdMatrix>> made;
    std::lock_guard<std::mutex> lock(mutex);
    auto& m = made[{voxelSize_mm.x, voxelSize_mm.y, voxelSize_mm.z}];
    if (!m) m = std::make_unique<ThresholdMatrix>(tileFor(voxelSize_mm), voxelSize_mm);
    return *m;
}

}  // namespace pl
