// Photons as points (bre's, pp3d's and combined's): stored where a photon's walk meets
// a real collision, with its power after the albedo, and filed by the cell
// of a grid whose side is the iteration's kernel radius.
#pragma once

#include <cstdint>
#include <vector>

#include "core/path_stats.h"
#include "core/vecmath.h"
#include "integrators/photons/cell_grid.h"
#include "integrators/photons/photon_parts.h"
#include "media/label_medium.h"

namespace pl {

class PhotonMap {
public:
    struct Photon {
        Point3f p;
        Vec3f dIn;     // propagation direction before the scattering
        float power;   // after the albedo
        Label label;   // where it scattered (its phase function)
    };
    PhotonMap(std::vector<Photon> photons, float radius_mm);
    float radius_mm() const { return radius_mm_; }
    size_t size() const { return photons_.size(); }
    // Calls f(photon) for every photon within one cell of a cell that
    // ray.at([0, tMax_mm]) crosses, each once, in a fixed order.
    template <class F>
    void forEachNear(const Ray& ray, float tMax_mm, F&& f) const {
        thread_local std::vector<uint64_t> keys;
        grid_.cellsNear(ray, tMax_mm, keys);
        grid_.forEachItem(keys, [&](size_t position, uint32_t) { f(photons_[position]); });
    }
    // Calls f(photon) for every photon in the 27 cells around p's, each
    // once, in a fixed order: every photon within the radius of p.
    template <class F>
    void forEachNearPoint(const Point3f& p, F&& f) const {
        thread_local std::vector<uint64_t> keys;
        grid_.cellsAround(p, keys);
        grid_.forEachItem(keys, [&](size_t position, uint32_t) { f(photons_[position]); });
    }

private:
    std::vector<Photon> photons_;  // in the grid's order
    float radius_mm_;
    CellGrid grid_;
};

// Bytes a photon takes while its iteration's map is built (the photon in
// its part and in the map, its grid entry and its place in the grid).
constexpr uint64_t kPhotonBytes = 2 * sizeof(PhotonMap::Photon) + 16 + 4;

// The photons of sample `sample` in a channel, stored at every real
// collision, filed at radius_mm.
PhotonMap tracePhotonPoints(const PhotonSource& source, int channel, uint32_t sample, float radius_mm,
                            PathStats& stats);

}  // namespace pl
