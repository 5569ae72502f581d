#include "prepare/gamut_boundary.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pl {

namespace {

// Per bin of lightness the most chromatic point, in order of lightness,
// the neutral axis's ends added: the slice's boundary, between them
// linear (segment maxima: a fine grid leaves it a little inside the true
// boundary, never far outside).
std::vector<std::pair<double, double>> segmentMaxima(std::vector<std::pair<double, double>> points, double darkest,
                                                     double lightest, double bandL) {
    std::sort(points.begin(), points.end());
    std::vector<std::pair<double, double>> maxima{{darkest, 0.0}};
    for (size_t k = 0; k < points.size();) {
        const double bandEnd = darkest + bandL * (std::floor((points[k].first - darkest) / bandL) + 1);
        std::pair<double, double> best = points[k];
        for (; k < points.size() && points[k].first < bandEnd; ++k)
            if (points[k].second > best.second) best = points[k];
        if (best.first > maxima.back().first) maxima.push_back(best);
    }
    if (lightest > maxima.back().first) maxima.push_back({lightest, 0.0});
    return maxima;
}

}  // namespace

GamutBoundary::GamutBoundary(const PrinterGamut& gamut, int levels, int hueSlices) {
    if (levels < 1 || hueSlices < 1) throw std::invalid_argument("GamutBoundary: at least one level and one hue slice");
    std::vector<Lab> colours;
    for (const MaterialFractions& m : PrinterGamut::gridMixtures(levels)) colours.push_back(gamut.colour(m));
    darkestL_ = lightestL_ = colours.front().L;
    for (const Lab& c : colours) {
        darkestL_ = std::min(darkestL_, double(c.L));
        lightestL_ = std::max(lightestL_, double(c.L));
    }
    std::vector<Slice> points(static_cast<size_t>(hueSlices));
    const double width = 360.0 / hueSlices;
    for (const Lab& c : colours) {
        const int slice = std::min(hueSlices - 1, int(hueDegrees(c) / width));
        points[size_t(slice)].push_back({c.L, std::hypot(double(c.a), double(c.b))});
    }
    slices_.reserve(size_t(hueSlices));
    constexpr double kBandL = 2.0;  // of lightness, in L* units
    std::vector<bool> empty(points.size());
    for (size_t k = 0; k < points.size(); ++k) {
        empty[k] = points[k].empty();
        slices_.push_back(segmentMaxima(std::move(points[k]), darkestL_, lightestL_, kBandL));
    }
    // A hue no grid colour falls in takes its nearest neighbour's slice
    // (not a chroma of 0, which would send every colour of it to grey).
    const int n = hueSlices;
    std::vector<Slice> filled = slices_;
    for (int k = 0; k < n; ++k) {
        if (!empty[size_t(k)]) continue;
        for (int d = 1; d <= n / 2; ++d) {
            const int before = (k - d + n) % n, after = (k + d) % n;
            if (!empty[size_t(before)]) filled[size_t(k)] = slices_[size_t(before)];
            else if (!empty[size_t(after)]) filled[size_t(k)] = slices_[size_t(after)];
            else continue;
            break;
        }
    }
    slices_ = std::move(filled);
}

double GamutBoundary::chromaOn(const Slice& slice, double L) {
    if (L < slice.front().first || L > slice.back().first) return 0;
    const auto above = std::lower_bound(slice.begin(), slice.end(), std::make_pair(L, -1.0));
    if (above == slice.begin()) return above->second;
    const auto below = above - 1;
    const double span = above->first - below->first;
    const double t = span > 0 ? (L - below->first) / span : 0;
    return below->second + t * (above->second - below->second);
}

void GamutBoundary::slicesAround(double hue_deg, int& first, int& second, double& weight) const {
    const int n = int(slices_.size());
    const double width = 360.0 / n;
    // Centres at (k + 1/2) width.
    const double x = std::fmod(std::fmod(hue_deg, 360.0) + 360.0, 360.0) / width - 0.5;
    const int k = int(std::floor(x));
    weight = x - k;
    first = (k + n) % n;
    second = (k + 1) % n;
}

double GamutBoundary::maxChroma(double L, double hue_deg) const {
    int a = 0, b = 0;
    double w = 0;
    slicesAround(hue_deg, a, b, w);
    return (1 - w) * chromaOn(slices_[size_t(a)], L) + w * chromaOn(slices_[size_t(b)], L);
}

double GamutBoundary::cuspLightness(double hue_deg) const {
    int a = 0, b = 0;
    double w = 0;
    slicesAround(hue_deg, a, b, w);
    auto cusp = [](const Slice& slice) {
        return std::max_element(slice.begin(), slice.end(), [](const auto& x, const auto& y) { return x.second < y.second; })
            ->first;
    };
    return (1 - w) * cusp(slices_[size_t(a)]) + w * cusp(slices_[size_t(b)]);
}

}  // namespace pl
