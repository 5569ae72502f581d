#include "integrators/photons/photon_map.h"

#include <algorithm>

namespace pl {

namespace {
Point3f lowestCorner(const std::vector<PhotonMap::Photon>& photons) {
    Point3f lo{1e30f, 1e30f, 1e30f};
    for (const PhotonMap::Photon& ph : photons)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], ph.p[a]);
    return photons.empty() ? Point3f{0, 0, 0} : lo;
}
}  // namespace

PhotonMap::PhotonMap(std::vector<Photon> photons, float radius_mm)
    : radius_mm_(radius_mm), grid_(radius_mm, lowestCorner(photons)) {
    std::vector<std::pair<uint64_t, uint32_t>> entries(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) entries[i] = {grid_.keyOf(grid_.cellOf(photons[i].p)), uint32_t(i)};
    grid_.fill(std::move(entries));
    // Stored in the grid's order: a cell's photons lie together.
    photons_.resize(grid_.entries());
    for (size_t i = 0; i < photons_.size(); ++i) photons_[i] = photons[grid_.itemAt(i)];
}

PhotonMap tracePhotonPoints(const PhotonSource& source, int channel, uint32_t sample, float radius_mm,
                            PathStats& stats) {
    const double power = source.powerEach(channel);
    std::vector<PhotonMap::Photon> photons = source.trace<PhotonMap::Photon>(
        channel, sample, stats, [](std::vector<PhotonMap::Photon>&, const Ray&, float, const SingleChannelPath&) {},
        [&](std::vector<PhotonMap::Photon>& stored, const Point3f& y, const Vec3f& dIn, Label label,
            const SingleChannelPath& p) { stored.push_back({y, dIn, float(power * double(p.beta)), label}); });
    return PhotonMap(std::move(photons), radius_mm);
}

}  // namespace pl
