// Everything a render reads: the object's boundary (Embree), the label
// medium inside it, the constant environment, and the boundary's IOR.
#pragma once

#include <memory>

#include "core/geometry.h"
#include "core/rgb.h"
#include "core/surface_clearance.h"
#include "media/label_medium.h"

namespace pl {

struct Scene {
    std::unique_ptr<Geometry> geometry;
    std::unique_ptr<LabelMedium> medium;
    RGB environment{1, 1, 1};  // constant radiance of the surroundings
    float ior = 1.5f;          // object / air
    // Optional: lets printpt skip boundary queries deep inside (null: never skip).
    std::unique_ptr<SurfaceClearance> clearance;
};

}  // namespace pl
