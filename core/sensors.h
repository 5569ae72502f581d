// Sensors turn (pixel index, two uniform numbers) into primary rays.
//  - PerspectiveSensor / OrthographicSensor: preview cameras, box-filtered
//    pixels of a width x height image (row-major, top row first).
//  - SurfaceVoxelSensor: the optimisation sensor, one "pixel" per surface
//    voxel; its construction is documented in docs/surface-voxel-sensor.md.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/geometry.h"
#include "core/grid_frame.h"
#include "core/surface_patches.h"
#include "core/vecmath.h"

namespace pl {

// The kinds of sensor as a set of bits: what an estimator takes
// (integrators/integrator.h, IntegratorCapabilities::sensors).
using SensorKinds = uint8_t;
constexpr SensorKinds kCameraSensor = 1;              // perspective or orthographic
constexpr SensorKinds kSurfaceVoxelRaySensor = 2;     // surface voxels, ray footprint
constexpr SensorKinds kSurfaceVoxelPatchSensor = 4;   // surface voxels, patch footprint
constexpr SensorKinds kEverySensorKind = kCameraSensor | kSurfaceVoxelRaySensor | kSurfaceVoxelPatchSensor;

class Sensor {
public:
    virtual ~Sensor() = default;
    virtual size_t pixelCount() const = 0;
    virtual Ray generateRay(size_t pixel, float u0, float u1) const = 0;
    // The image the results are shown in: pixelImageIndex(p) is the
    // row-major index in a imageWidth() x imageHeight() image, or -1.
    virtual int imageWidth() const = 0;
    virtual int imageHeight() const = 0;
    virtual int64_t pixelImageIndex(size_t pixel) const { return int64_t(pixel); }
    // Rays that stand for the sensor's view whatever its resolution, for
    // decisions an estimator takes before rendering (printpt's control
    // census): surveyRayCount() of them, each standing for
    // surveyRayWeight() entries. Here every kSurveyStride-th pixel's
    // centre (the surface-voxel sensor, whose pixels are the object's).
    static constexpr uint32_t kSurveyStride = 8;
    virtual size_t surveyRayCount() const { return (pixelCount() + kSurveyStride - 1) / kSurveyStride; }
    virtual Ray surveyRay(size_t i) const { return generateRay(i * kSurveyStride, 0.5f, 0.5f); }
    virtual uint32_t surveyRayWeight() const { return kSurveyStride; }
};

struct CameraPose {
    Point3f position_mm{0, 0, 0};
    Point3f lookAt_mm{0, 0, 1};
    Vec3f up{0, 1, 0};
};

// A camera with a pose and a width x height image; subclasses project.
class CameraSensor : public Sensor {
public:
    CameraSensor(const CameraPose& pose, int width, int height);
    size_t pixelCount() const override { return size_t(width_) * height_; }
    int imageWidth() const override { return width_; }
    int imageHeight() const override { return height_; }
    Ray generateRay(size_t pixel, float u0, float u1) const override {
        float x, y;
        filmPosition(pixel, u0, u1, x, y);
        return rayThrough(x, y);
    }
    // The survey: a kSurveySide^2 grid over the film, whatever the image's
    // resolution; each ray stands for one entry of a view that size.
    static constexpr int kSurveySide = 256;
    size_t surveyRayCount() const override { return size_t(kSurveySide) * kSurveySide; }
    Ray surveyRay(size_t i) const override {
        const float x = (float(i % kSurveySide) + 0.5f) / kSurveySide * 2.0f - 1.0f;
        const float y = 1.0f - (float(i / kSurveySide) + 0.5f) / kSurveySide * 2.0f;
        return rayThrough(x, y);
    }
    uint32_t surveyRayWeight() const override { return 1; }

protected:
    // The ray through film position (x, y) in [-1, 1]^2, y up.
    virtual Ray rayThrough(float x, float y) const = 0;
    // Film position of a jittered pixel sample in [-1, 1]^2, y up.
    void filmPosition(size_t pixel, float u0, float u1, float& x, float& y) const {
        x = (float(pixel % width_) + u0) / width_ * 2.0f - 1.0f;
        y = 1.0f - (float(pixel / width_) + u1) / height_ * 2.0f;
    }
    Point3f origin_;
    Vec3f right_, up_, forward_;
    int width_, height_;
};

class PerspectiveSensor : public CameraSensor {
public:
    PerspectiveSensor(const CameraPose& pose, float fovY_deg, int width, int height);

private:
    Ray rayThrough(float x, float y) const override;
    float tanHalfFovY_;
};

class OrthographicSensor : public CameraSensor {
public:
    OrthographicSensor(const CameraPose& pose, float viewWidth_mm, int width, int height);

private:
    Ray rayThrough(float x, float y) const override;
    float viewWidth_mm_;
};

// One pixel per surface voxel: a non-void voxel with a face neighbour that is
// void (or outside the grid). Its surface point p is where the mesh is
// crossed, leaving the object, on the line through the voxel centre along an
// exposed face's direction (the nearest crossing over the exposed faces,
// searched one voxel either side of the centre); if no such crossing exists,
// the closest point of the mesh to the centre. The ray starts at p offset
// outwards by a small epsilon along the outward normal n of the triangle
// there and travels along -n: the value is the radiance leaving the surface
// at p along its normal. With the patch footprint, each sample takes a
// point of the voxel's patch instead (core/surface_patches.h) and the value
// is the patch's average. Full description: docs/surface-voxel-sensor.md.
class SurfaceVoxelSensor : public Sensor {
public:
    enum class Footprint { Ray, Patch };
    struct Pixel {
        Vec3i voxel;
        Point3f surfacePoint_mm;
        Vec3f normal;  // outward
    };

    // surfaceVoxels: from LabelGrid::surfaceVoxels().
    SurfaceVoxelSensor(const Geometry& geometry, const GridFrame& frame,
                       const std::vector<SurfaceVoxel>& surfaceVoxels, Footprint footprint = Footprint::Ray);
    size_t pixelCount() const override { return pixels_.size(); }
    Ray generateRay(size_t pixel, float u0, float u1) const override;
    int imageWidth() const override { return atlasWidth_; }
    int imageHeight() const override { return atlasHeight_; }
    int64_t pixelImageIndex(size_t pixel) const override { return atlasIndex_[pixel]; }

    const std::vector<Pixel>& pixels() const { return pixels_; }
    // The patches (patch footprint; none with the ray footprint).
    const SurfacePatches* patches() const { return patches_.get(); }
    float rayOffset_mm() const { return rayOffset_mm_; }

private:
    void buildAtlas(const GridFrame& frame);

    std::vector<Pixel> pixels_;
    std::unique_ptr<SurfacePatches> patches_;
    std::vector<int64_t> atlasIndex_;
    int atlasWidth_ = 0, atlasHeight_ = 0;
    float rayOffset_mm_;
};

}  // namespace pl
