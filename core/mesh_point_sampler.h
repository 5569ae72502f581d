// Points uniform by area over a mesh (particles and photons entering from
// the environment): a triangle by its area, then a point uniform on it.
#pragma once

#include <algorithm>
#include <vector>

#include "core/geometry.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace pl {

class MeshPointSampler {
public:
    explicit MeshPointSampler(const Geometry& geometry) : geometry_(geometry) {
        const TriangleMesh& mesh = geometry.mesh();
        areaCdf_mm2_.reserve(mesh.triangleCount());
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            area_mm2_ += mesh.triangleArea_mm2(t);
            areaCdf_mm2_.push_back(area_mm2_);
        }
    }
    double area_mm2() const { return area_mm2_; }
    // Takes three uniform numbers: the triangle's, then the point's two.
    SurfaceHit sample(Rng& rng) const {
        const double pick = double(rng.uniform()) * area_mm2_;
        const size_t below = size_t(std::upper_bound(areaCdf_mm2_.begin(), areaCdf_mm2_.end(), pick) - areaCdf_mm2_.begin());
        const uint32_t prim = uint32_t(std::min(below, areaCdf_mm2_.size() - 1));
        const float u0 = rng.uniform(), u1 = rng.uniform();
        const TriangleSample b = sampleUniformTriangle(u0, u1);
        return geometry_.pointOn(prim, b.b1, b.b2);
    }

private:
    const Geometry& geometry_;
    std::vector<double> areaCdf_mm2_;
    double area_mm2_ = 0;
};

}  // namespace pl
