// The learned predictor's input for one surface point and one channel
// (Rittig et al. 2021 in spirit): what lies under the surface, coarse to
// fine along the inward normal.
//  - The column: the exact labels' coefficients at kColumnSamples depths,
//    kColumnStep_mm apart (the halftone's dots right under the point).
//  - Per level l of a property pyramid (cells of 0.1 x 2^l mm, up to
//    1.6 mm): at kDepths depths of (k + 1/2) cells, the cell on the normal
//    and the mean of kRing cells around it one cell away, each as (share
//    filled, scattering, absorption). The ring's mean makes it blind to
//    the turn about the normal, as reflectance under uniform light is.
// Coefficients are divided by kCoefficientScale_perMm.
#pragma once

#include <array>
#include <memory>

#include "media/label_medium.h"
#include "media/property_pyramid.h"

namespace pl {

class LabelDescriptor {
public:
    static constexpr int kColumnSamples = 6;
    static constexpr float kColumnStep_mm = 0.03f;
    static constexpr float kBaseCell_mm = 0.1f;
    static constexpr int kLevels = 5;
    static constexpr int kDepths = 3;
    static constexpr int kRing = 8;
    static constexpr float kCoefficientScale_perMm = 20.0f;
    static constexpr int kSize = 2 * kColumnSamples + kLevels * kDepths * 2 * 3;
    using Values = std::array<float, kSize>;
    // The pyramid is refused beyond this (a whole tray at 0.1 mm cells).
    static constexpr uint64_t kMostPyramidBytes = uint64_t(4) << 30;

    // Refuses (std::length_error) an object whose pyramid would exceed maxBytes.
    LabelDescriptor(const LabelMedium& medium, uint64_t maxBytes);

    // The descriptors of the three channels at surface point p_mm, with
    // outward unit normal n.
    void compute(const Point3f& p_mm, const Vec3f& n, LabelMedium::Tracker& sampler,
                 std::array<Values, 3>& out) const;

private:
    const LabelMedium& medium_;
    PropertyPyramid pyramid_;
};

}  // namespace pl
