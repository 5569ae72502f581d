// Where a kernel of radius r around a point stays inside the object (pp3d,
// pb2d and combined gather only there): no boundary within r and the
// surface lift.
#pragma once

#include <cmath>
#include <vector>

#include "scene/scene.h"

namespace pl {

// How far from the boundary a kernel of radius radius_mm may gather.
inline float clearReach_mm(const Scene& scene, float radius_mm) {
    return radius_mm + scene.geometry->surfaceLift_mm();
}

// Whether no boundary lies within reach_mm of x: the block's clearance, or
// else the nearest surface point.
inline bool isClear(const Scene& scene, const Point3f& x, float reach_mm) {
    return (scene.clearance && scene.clearance->at(x) >= reach_mm) || !scene.geometry->closestPoint(x, reach_mm);
}

// isClear at the points of one flight, mostly from a few distances to the
// boundary along it: a point within step / 2 of a sampled point p is clear
// where p's distance is at least reach + step / 2, and not where it is
// below reach - step / 2 (a distance changes no faster than the position);
// in between it is asked. isClear's answers (but at distances equal to the
// reach), with a query per step rather than per point.
class ClearAlong {
public:
    ClearAlong(const Scene& scene, const Ray& flight, float reach_mm, float step_mm)
        : scene_(scene), flight_(flight), reach_mm_(reach_mm), step_mm_(step_mm) {}

    // At flight.at(t_mm), t_mm >= 0.
    bool at(float t_mm) {
        if (!(t_mm >= 0.0f)) return false;
        const Point3f x = flight_.at(t_mm);
        if (scene_.clearance && scene_.clearance->at(x) >= reach_mm_) return true;
        const size_t j = size_t(std::lround(t_mm / step_mm_));
        if (j >= distances_mm_.size()) distances_mm_.resize(j + 1, -1.0f);
        if (distances_mm_[j] < 0.0f) {
            // Looked for up to reach + step: beyond, all that matters is that it is far.
            const float far_mm = reach_mm_ + step_mm_;
            const auto nearest = scene_.geometry->closestPoint(flight_.at(float(j) * step_mm_), far_mm);
            distances_mm_[j] = nearest ? nearest->distance_mm : far_mm;
        }
        const float d = distances_mm_[j], half = 0.5f * step_mm_;
        if (d >= reach_mm_ + half) return true;
        if (d < reach_mm_ - half) return false;
        return isClear(scene_, x, reach_mm_);
    }

private:
    const Scene& scene_;
    Ray flight_;
    float reach_mm_, step_mm_;
    std::vector<float> distances_mm_;  // at j x step along the flight; < 0: not yet asked
};

}  // namespace pl
