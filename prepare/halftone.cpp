#include "prepare/halftone.h"

#include <algorithm>

#include "prepare/threshold_matrix.h"

namespace pl {

MaterialFractions fractionsForColor(const RGB& linear) {
    float c = 1 - std::clamp(linear[0], 0.0f, 1.0f);
    float m = 1 - std::clamp(linear[1], 0.0f, 1.0f);
    float y = 1 - std::clamp(linear[2], 0.0f, 1.0f);
    float k = std::min({c, m, y});
    MaterialFractions f{c - k, m - k, y - k, k, 0.0f};
    f[4] = std::max(0.0f, 1.0f - (f[0] + f[1] + f[2] + f[3]));
    return f;
}

namespace {
// Material indices (kPrintMaterialLabel's order) from the lightest.
constexpr int kLightestFirst[kPrintMaterials] = {4, 2, 0, 1, 3};
}  // namespace

int materialAtThreshold(const MaterialFractions& fractions, float threshold, int current, float hysteresis) {
    const int wanted = materialAtThreshold(fractions, threshold);
    if (wanted == current || current < 0 || current >= kPrintMaterials || !(hysteresis > 0)) return wanted;
    float total = 0;
    for (float f : fractions) total += std::max(f, 0.0f);
    if (!(total > 0)) return wanted;
    // The current material's share [lo, hi) of [0, 1), against the threshold's reach.
    float lo = 0;
    for (int m : kLightestFirst) {
        const float share = std::max(fractions[size_t(m)], 0.0f) / total;
        if (m == current)
            return share > 0 && lo < threshold + hysteresis && lo + share > threshold - hysteresis ? current : wanted;
        lo += share;
    }
    return wanted;
}

int materialAtThreshold(const MaterialFractions& fractions, float threshold) {
    float total = 0;
    for (float f : fractions) total += std::max(f, 0.0f);
    const float t = threshold * total;
    float below = 0;
    int last = kLightestFirst[0];
    for (int m : kLightestFirst) {
        const float f = std::max(fractions[size_t(m)], 0.0f);
        if (f <= 0) continue;
        below += f;
        last = m;
        if (t < below) return m;
    }
    return last;  // round-off at the top
}

int printMaterialOf(Label label) {
    for (int m = 0; m < kPrintMaterials; ++m)
        if (kPrintMaterialLabel[m] == label) return m;
    return -1;
}

int largestFraction(const MaterialFractions& fractions) {
    return int(std::max_element(fractions.begin(), fractions.end()) - fractions.begin());
}

int materialOfVoxel(const MaterialFractions& fractions, const ThresholdMatrix* thresholds, const Vec3i& voxel,
                    int current, float hysteresis) {
    return thresholds ? materialAtThreshold(fractions, thresholds->at(voxel), current, hysteresis)
                      : largestFraction(fractions);
}

ErrorDiffusionHalftoner::ErrorDiffusionHalftoner(int resX, int resY)
    : resX_(resX), resY_(resY),
      error_(size_t(resX) * resY, MaterialFractions{}),
      nextError_(size_t(resX) * resY, MaterialFractions{}) {}

void ErrorDiffusionHalftoner::halftoneSlice(int z, const std::vector<MaterialFractions>& targets,
                                            const std::vector<uint8_t>& active,
                                            std::vector<uint8_t>& chosen) {
    chosen.assign(size_t(resX_) * resY_, 0);
    for (int y = 0; y < resY_; ++y) {
        // Serpentine: alternate the x direction per row, and per slice.
        int dir = ((y + z) % 2 == 0) ? 1 : -1;
        int xStart = dir > 0 ? 0 : resX_ - 1;
        for (int i = 0; i < resX_; ++i) {
            int x = xStart + dir * i;
            size_t at = size_t(y) * resX_ + x;
            if (!active[at]) continue;
            // Pick the material with the largest wanted amount.
            MaterialFractions want;
            int best = 0;
            for (int m = 0; m < kPrintMaterials; ++m) {
                want[m] = targets[at][m] + error_[at][m];
                if (want[m] > want[best]) best = m;
            }
            chosen[at] = uint8_t(best);
            want[best] -= 1.0f;  // the residual to pass on

            // Unvisited neighbours that take part, with their weights.
            struct Tap { size_t at; float w; bool nextSlice; };
            Tap taps[5];
            int n = 0;
            float total = 0;
            auto add = [&](int nx, int ny, float w) {
                if (nx < 0 || nx >= resX_ || ny >= resY_) return;
                size_t a = size_t(ny) * resX_ + nx;
                if (!active[a]) return;
                taps[n++] = {a, w, false};
                total += w;
            };
            add(x + dir, y, 5);
            add(x - dir, y + 1, 3);
            add(x, y + 1, 2);
            add(x + dir, y + 1, 1);
            // The next slice is not known yet: assume it takes part.
            taps[n++] = {at, 5, true};
            total += 5;
            for (int t = 0; t < n; ++t) {
                MaterialFractions& e = taps[t].nextSlice ? nextError_[taps[t].at] : error_[taps[t].at];
                float w = taps[t].w / total;
                for (int m = 0; m < kPrintMaterials; ++m) e[m] += w * want[m];
            }
        }
    }
    // Error that reached an inactive voxel of the next slice is dropped there.
    std::swap(error_, nextError_);
    std::fill(nextError_.begin(), nextError_.end(), MaterialFractions{});
}

void halftoneFrame(const Vec3i& resolution, const std::function<bool(size_t, MaterialFractions&)>& wanted,
                   const std::function<void(size_t, int)>& chosen) {
    const size_t sliceSize = size_t(resolution.x) * size_t(resolution.y);
    ErrorDiffusionHalftoner halftoner(resolution.x, resolution.y);
    std::vector<MaterialFractions> targets(sliceSize);
    std::vector<uint8_t> active(sliceSize), material;
    for (int z = 0; z < resolution.z; ++z) {
        const size_t slice = size_t(z) * sliceSize;
        for (size_t i = 0; i < sliceSize; ++i) active[i] = wanted(slice + i, targets[i]);
        halftoner.halftoneSlice(z, targets, active, material);
        for (size_t i = 0; i < sliceSize; ++i)
            if (active[i]) chosen(slice + i, material[i]);
    }
}

}  // namespace pl
