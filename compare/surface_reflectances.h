// A render's surface voxels beside a reference's, as reflectance
// (radiance over the surroundings' radiance): the colours
// compare/surface_colour_error.h judges, and the two checks that need no
// colour space, the mean bias and how many differences the reported
// errors cover.
#pragma once

#include <cstdint>
#include <vector>

#include "core/film.h"
#include "core/rgb.h"
#include "core/sensors.h"
#include "core/vecmath.h"

namespace pl {

// One entry per surface voxel the sensor's image (the atlas) shows.
struct SurfaceReflectances {
    std::vector<Point3f> points_mm;  // the voxels' surface points
    std::vector<RGB> film, reference;
    std::vector<int64_t> imageIndex;  // where each voxel is in the image
    RGB meanBias{0, 0, 0};            // of film - reference
    // The share of voxel channels whose difference from the reference is
    // within twice the two standard errors combined (reported errors that
    // cover every source of error put about 95 % there).
    double withinTwoErrors = 0;
};

// referenceMean, referenceStandardError: laid out in the sensor's image
// (Sensor::pixelImageIndex); environment: the surroundings' radiance.
SurfaceReflectances surfaceReflectances(const Film& film, const SurfaceVoxelSensor& sensor,
                                        const std::vector<RGB>& referenceMean,
                                        const std::vector<RGB>& referenceStandardError, const RGB& environment);

}  // namespace pl
