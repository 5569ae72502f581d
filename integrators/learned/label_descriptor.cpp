#include "integrators/learned/label_descriptor.h"

#include <cmath>

namespace pl {

LabelDescriptor::LabelDescriptor(const LabelMedium& medium, uint64_t maxBytes)
    : medium_(medium), pyramid_(medium, kBaseCell_mm, kLevels, maxBytes) {}

void LabelDescriptor::compute(const Point3f& p_mm, const Vec3f& n, LabelMedium::Tracker& sampler,
                              std::array<Values, 3>& out) const {
    constexpr float kScale = 1.0f / kCoefficientScale_perMm;
    int at = 0;
    const Label voidLabel = medium_.grid().voidLabel();
    for (int k = 0; k < kColumnSamples; ++k) {
        const Point3f q = p_mm - n * ((float(k) + 0.5f) * kColumnStep_mm);
        const Label label = sampler.labelAt(medium_.voxelAt(q));
        for (int c = 0; c < 3; ++c) {
            const ChannelLut& lut = medium_.lut(c);
            const float sigmaT = label == voidLabel ? 0.0f : lut.sigmaT_perMm[label];
            out[size_t(c)][size_t(at)] = kScale * sigmaT * lut.albedo[label];
            out[size_t(c)][size_t(at) + 1] = kScale * sigmaT * (1 - lut.albedo[label]);
        }
        at += 2;
    }
    const Frame frame(n);
    std::array<Vec3f, kRing> ring;
    for (int j = 0; j < kRing; ++j) {
        const float phi = 2 * kPi * float(j) / kRing;
        ring[size_t(j)] = frame.s * std::cos(phi) + frame.t * std::sin(phi);
    }
    for (int l = 0; l < kLevels; ++l) {
        const float cell_mm = pyramid_.cellSize_mm(l);
        for (int k = 0; k < kDepths; ++k) {
            const Point3f centre = p_mm - n * ((float(k) + 0.5f) * cell_mm);
            const CellProperties onNormal = pyramid_.at(l, centre);
            CellProperties around;
            for (const Vec3f& d : ring) {
                const CellProperties cell = pyramid_.at(l, centre + d * cell_mm);
                around.filled += cell.filled / kRing;
                for (int c = 0; c < 3; ++c) {
                    around.sigmaS_perMm[c] += cell.sigmaS_perMm[c] / kRing;
                    around.sigmaA_perMm[c] += cell.sigmaA_perMm[c] / kRing;
                }
            }
            const CellProperties* const cells[2] = {&onNormal, &around};
            for (const CellProperties* cell : cells) {
                for (int c = 0; c < 3; ++c) {
                    out[size_t(c)][size_t(at)] = cell->filled;
                    out[size_t(c)][size_t(at) + 1] = kScale * cell->sigmaS_perMm[c];
                    out[size_t(c)][size_t(at) + 2] = kScale * cell->sigmaA_perMm[c];
                }
                at += 3;
            }
        }
    }
}

}  // namespace pl
