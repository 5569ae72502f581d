#include "core/sensors.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace pl {

namespace {
constexpr float kEdgeNudge_mm = 1e-3f;  // 1 um, far below a voxel

}  // namespace

CameraSensor::CameraSensor(const CameraPose& pose, int width, int height)
    : origin_(pose.position_mm), width_(width), height_(height) {
    forward_ = normalize(pose.lookAt_mm - pose.position_mm);
    right_ = normalize(cross(forward_, pose.up));
    up_ = cross(right_, forward_);
}

PerspectiveSensor::PerspectiveSensor(const CameraPose& pose, float fovY_deg, int width,
                                     int height)
    : CameraSensor(pose, width, height), tanHalfFovY_(std::tan(0.5f * fovY_deg * kPi / 180.0f)) {}

Ray PerspectiveSensor::rayThrough(float x, float y) const {
    float aspect = float(width_) / float(height_);
    Vec3f d = forward_ + right_ * (x * tanHalfFovY_ * aspect) + up_ * (y * tanHalfFovY_);
    return {origin_, normalize(d)};
}

OrthographicSensor::OrthographicSensor(const CameraPose& pose, float viewWidth_mm, int width,
                                       int height)
    : CameraSensor(pose, width, height), viewWidth_mm_(viewWidth_mm) {}

Ray OrthographicSensor::rayThrough(float x, float y) const {
    float viewHeight_mm = viewWidth_mm_ * float(height_) / float(width_);
    return {origin_ + right_ * (0.5f * x * viewWidth_mm_) + up_ * (0.5f * y * viewHeight_mm), forward_};
}

SurfaceVoxelSensor::SurfaceVoxelSensor(const Geometry& geometry, const GridFrame& frame,
                                       const std::vector<SurfaceVoxel>& surfaceVoxels, Footprint footprint)
    : rayOffset_mm_(geometry.rayEpsilon_mm()) {
    pixels_.resize(surfaceVoxels.size());
    const Vec3f& s = frame.voxelSize_mm;
    float searchRadius_mm = 4.0f * std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
    std::vector<uint8_t> missing(surfaceVoxels.size(), 0);
    tbb::parallel_for(size_t(0), surfaceVoxels.size(), [&](size_t i) {
        const SurfaceVoxel& sv = surfaceVoxels[i];
        Point3f c = frame.voxelCenter_mm(sv.voxel);

        // Nearest exit crossing along the exposed faces' directions.
        std::optional<SurfaceHit> best;
        float bestDist = 1e30f;
        for (int k = 0; k < 6; ++k) {
            if (!(sv.exposedFaces & (1u << k))) continue;
            const Vec3i& e = kFaceDirections[k];
            Vec3f dir(float(e.x), float(e.y), float(e.z));
            float h = std::abs(dot(dir, s));  // voxel extent along this axis
            auto hit = geometry.intersect({c - dir * h, dir}, 2.0f * h);
            if (!hit || dot(dir, hit->ng) <= 0) continue;  // must leave the object
            float dist = length(hit->p - c);
            if (dist < bestDist) {
                bestDist = dist;
                best = hit;
            }
        }
        Point3f p;
        Vec3f n;
        uint32_t prim;
        if (best) {
            p = best->p;
            n = best->ng;
            prim = best->prim;
        } else {
            auto cp = geometry.closestPoint(c, searchRadius_mm);
            if (!cp) {
                missing[i] = 1;
                return;
            }
            p = cp->p;
            n = cp->ng;
            prim = cp->prim;
        }
        // Points on edges or corners are nudged a little into their
        // triangle, so the inward ray does not run inside a neighbouring
        // face's plane where intersection is ill-conditioned.
        Vec3f toCentroid = geometry.triangleCentroid(prim) - p;
        float dist = length(toCentroid);
        if (dist > 0) p = p + toCentroid * (std::min(kEdgeNudge_mm, 0.5f * dist) / dist);
        pixels_[i] = {sv.voxel, p, n};
    });
    for (size_t i = 0; i < missing.size(); ++i)
        if (missing[i]) {
            const Vec3i& v = surfaceVoxels[i].voxel;
            throw std::runtime_error(
                "surface voxel (" + std::to_string(v.x) + "," + std::to_string(v.y) + "," +
                std::to_string(v.z) + ") is more than " + std::to_string(searchRadius_mm) +
                " mm from the mesh: mesh and label grid do not match");
        }
    buildAtlas(frame);
    if (footprint == Footprint::Patch) {
        std::vector<Vec3i> voxels(pixels_.size());
        for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = pixels_[i].voxel;
        patches_ = std::make_unique<SurfacePatches>(geometry.mesh(), frame, voxels);
    }
}

Ray SurfaceVoxelSensor::generateRay(size_t pixel, float u0, float u1) const {
    if (patches_)
        if (auto x = patches_->sample(pixel, u0, u1)) return {x->p + x->normal * rayOffset_mm_, -x->normal};
    const Pixel& px = pixels_[pixel];
    return {px.surfacePoint_mm + px.normal * rayOffset_mm_, -px.normal};
}

// Atlas for viewing: voxels are grouped by the dominant axis and sign of
// their normal (+x,+y,+z on the top row, -x,-y,-z below) and each group is
// projected along its axis onto the other two voxel axes. Where several
// voxels project to one atlas pixel the outermost one is shown; the .vdb
// output holds every voxel.
void SurfaceVoxelSensor::buildAtlas(const GridFrame& frame) {
    const Vec3i& r = frame.resolution;
    int tileW[3], tileH[3];
    for (int a = 0; a < 3; ++a) {
        tileW[a] = r[(a + 1) % 3];
        tileH[a] = r[(a + 2) % 3];
    }
    int tileX[3] = {0, tileW[0], tileW[0] + tileW[1]};
    int rowH = std::max({tileH[0], tileH[1], tileH[2]});
    atlasWidth_ = tileW[0] + tileW[1] + tileW[2];
    atlasHeight_ = 2 * rowH;

    atlasIndex_.assign(pixels_.size(), -1);
    std::vector<int64_t> owner(size_t(atlasWidth_) * atlasHeight_, -1);
    std::vector<int> depth(owner.size(), 0);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const Vec3f& n = pixels_[i].normal;
        int a = std::abs(n.x) >= std::abs(n.y) ? (std::abs(n.x) >= std::abs(n.z) ? 0 : 2)
                                               : (std::abs(n.y) >= std::abs(n.z) ? 1 : 2);
        bool positive = n[a] > 0;
        const Vec3i& v = pixels_[i].voxel;
        int u = v[(a + 1) % 3] - frame.indexMin[(a + 1) % 3];
        int w = v[(a + 2) % 3] - frame.indexMin[(a + 2) % 3];
        int x = tileX[a] + u;
        int y = (positive ? 0 : rowH) + (tileH[a] - 1 - w);
        size_t idx = size_t(y) * atlasWidth_ + x;
        int outward = positive ? v[a] : -v[a];
        if (owner[idx] < 0 || outward > depth[idx]) {
            if (owner[idx] >= 0) atlasIndex_[owner[idx]] = -1;
            owner[idx] = int64_t(i);
            depth[idx] = outward;
            atlasIndex_[i] = int64_t(idx);
        }
    }
}

}  // namespace pl
