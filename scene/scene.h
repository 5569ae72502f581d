// Everything a render reads: the object's boundary (Embree), the label
// medium inside it, the constant environment, and the boundary's IOR.
#pragma once

#include <memory>
#include <optional>

#include "core/geometry.h"
#include "core/rgb.h"
#include "core/surface_clearance.h"
#include "media/label_medium.h"
#include "scene/homogeneous_core.h"

namespace pl {

struct Scene {
    std::unique_ptr<Geometry> geometry;
    std::unique_ptr<LabelMedium> medium;
    RGB environment{1, 1, 1};  // constant radiance of the surroundings
    float ior = 1.5f;          // object / air
    // Optional: lets printpt skip boundary queries deep inside (null: never skip).
    std::unique_ptr<SurfaceClearance> clearance;
    // Geometry, grid and sensors live in a local frame whose origin is the
    // grid's corner (see toLocalFrame); this is its world position.
    Vec3f worldOrigin_mm{0, 0, 0};
    // What the homogeneous-core approximation changed, when it is on.
    std::optional<HomogeneousCore> homogeneousCore;

    // The grid's placement in the world (for outputs).
    GridFrame worldFrame() const {
        GridFrame f = medium->frame();
        f.cornerMin_mm = f.cornerMin_mm + worldOrigin_mm;
        return f;
    }
};

// Moves mesh and grid so that the grid's corner is the origin and returns
// the world position of that origin. Far from the world origin floats are
// coarse (6e-5 mm at 1 m), and ray offsets scale with the coordinates: at
// 1 m they would skip a tenth of a mean free path at every boundary.
inline Vec3f toLocalFrame(TriangleMesh& mesh, LabelGrid& grid) {
    Vec3f origin = grid.frame().cornerMin_mm;
    for (Point3f& p : mesh.positions_mm) p = p - origin;
    grid.placeCornerAt({0, 0, 0});
    return origin;
}

// What the chosen estimators need beyond mesh, labels and materials.
struct SceneNeeds {
    bool surfaceFields = false;  // sdf/normal grids of a prepared .vdb (e.g. printpt's NEE)
    bool clearance = false;      // the surface clearance (e.g. printpt's query skipping and ball walks)
    SceneNeeds& operator|=(const SceneNeeds& o) {
        surfaceFields = surfaceFields || o.surfaceFields;
        clearance = clearance || o.clearance;
        return *this;
    }
};

}  // namespace pl
