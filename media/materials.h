// Material lookup table: per label and RGB channel an extinction coefficient
// sigma_t (1/mm), a single-scattering albedo and a Henyey-Greenstein g.
#pragma once

#include <array>
#include <cmath>
#include <string>

#include "core/rgb.h"
#include "media/label_grid.h"

namespace pl {

struct Material {
    std::string name;
    RGB sigmaT_perMm{0, 0, 0};
    RGB albedo{0, 0, 0};
    RGB g{0, 0, 0};
    bool defined = false;
};

// The label convention of the research code (Rittig et al. 2021), which
// prepare writes, the bundled data use and a label grid's void defaults to:
// 0 cyan, 1 magenta, 2 yellow, 3 black, 4 white, 5 air (void), 6 clear.
enum ResearchLabel : Label {
    kCyanLabel = 0,
    kMagentaLabel = 1,
    kYellowLabel = 2,
    kBlackLabel = 3,
    kWhiteLabel = 4,
    kVoidLabel = 5,
    kClearLabel = 6,
};
inline const char* researchLabelName(int label) {
    static const char* names[] = {"cyan", "magenta", "yellow", "black", "white", "air (void)", "clear"};
    return label >= 0 && label < 7 ? names[label] : "";
}

struct MaterialTable {
    std::array<Material, 256> byLabel;
    // Whether voxels may hold label l: it has a material, or it is the void
    // label (vacuum unless defined).
    bool covers(Label l, Label voidLabel) const { return l == voidLabel || byLabel[l].defined; }
};

// The per-channel view the trackers read in their inner loops.
struct ChannelLut {
    std::array<float, 256> sigmaT_perMm{};
    std::array<float, 256> albedo{};
    std::array<float, 256> g{};
    std::array<float, 256> logSigmaT{};  // log(sigma_t), -inf where 0 (hero-channel pdf ratios)

    // The void label is vacuum unless the table defines it.
    static ChannelLut build(const MaterialTable& table, Label voidLabel, int channel) {
        ChannelLut lut;
        for (int l = 0; l < 256; ++l) {
            const Material& m = table.byLabel[l];
            if (!m.defined) continue;
            lut.sigmaT_perMm[l] = m.sigmaT_perMm[channel];
            lut.albedo[l] = m.albedo[channel];
            lut.g[l] = m.g[channel];
        }
        if (!table.byLabel[voidLabel].defined) lut.sigmaT_perMm[voidLabel] = 0.0f;
        for (int l = 0; l < 256; ++l) lut.logSigmaT[l] = std::log(lut.sigmaT_perMm[l]);
        return lut;
    }
};

}  // namespace pl
