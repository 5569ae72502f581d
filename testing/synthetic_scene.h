// Scenes built in code rather than read from files: boxes and prisms of
// labelled voxels under a constant environment, for the tests and the
// numerical stability suite (printlight stability).
#pragma once

#include <functional>
#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

#include "core/geometry.h"
#include "scene/scene.h"
#include "media/label_grid.h"
#include "media/materials.h"

namespace pl::synthetic {

using ::pl::boxMesh;

// A sphere of `segments` around and segments / 2 from pole to pole,
// triangles counter-clockwise from outside, with its exact normals.
inline TriangleMesh sphereMesh(const Point3f& centre, float radius, int segments) {
    TriangleMesh m;
    const int rings = segments / 2;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const float theta = kPi * float(i) / float(rings), phi = 2.0f * kPi * float(j) / float(segments);
            const Vec3f n{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
            m.positions_mm.push_back(centre + n * radius);
            m.normals.push_back(n);
        }
    auto at = [&](int i, int j) { return uint32_t(i * segments + (j % segments)); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            if (i > 0) m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
            if (i + 1 < rings) m.indices.insert(m.indices.end(), {at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
        }
    return m;
}

// A prism along y over the triangle (0,0), (length,0), (length,height) in
// x-z: a wedge whose sharp edge (angle atan(height/length)) lies on the
// y axis at x = z = 0. Offset by `origin`.
inline TriangleMesh wedgeMesh(const Point3f& origin, float length, float height, float depth) {
    TriangleMesh m;
    const float xz[3][2] = {{0, 0}, {length, 0}, {length, height}};
    for (int side = 0; side < 2; ++side)
        for (const auto& p : xz) m.positions_mm.push_back({origin.x + p[0], origin.y + side * depth, origin.z + p[1]});
    // Vertices 0-2 at y = 0, 3-5 at y = depth; outward counter-clockwise.
    m.indices = {0, 1, 2, 3, 5, 4,  // end caps (-y, +y)
                 0, 3, 4, 0, 4, 1,  // bottom (-z)
                 1, 4, 5, 1, 5, 2,  // back (+x)
                 0, 2, 5, 0, 5, 3}; // slanted face
    return m;
}

inline Material material(RGB sigmaT, RGB albedo, RGB g = {0, 0, 0}) {
    Material m;
    m.sigmaT_perMm = sigmaT;
    m.albedo = albedo;
    m.g = g;
    m.defined = true;
    return m;
}

inline MaterialTable tableOf(std::initializer_list<std::pair<Label, Material>> entries) {
    MaterialTable t;
    for (const auto& [label, m] : entries) {
        t.byLabel[label] = m;
        t.byLabel[label].defined = true;
    }
    return t;
}

constexpr Label kVoid = kVoidLabel;

// Voxels (voxel_mm) from `cornerMin_mm` on, carrying labelOf(voxel index).
inline LabelGrid labelGrid(const Vec3i& resolution, const Vec3f& voxel_mm,
                           const std::function<Label(const Vec3i&)>& labelOf,
                           const Point3f& cornerMin_mm = {0, 0, 0}) {
    GridFrame f;
    f.resolution = resolution;
    f.voxelSize_mm = voxel_mm;
    f.cornerMin_mm = cornerMin_mm;
    std::vector<Label> labels(f.voxelCount());
    size_t i = 0;
    for (int z = 0; z < resolution.z; ++z)
        for (int y = 0; y < resolution.y; ++y)
            for (int x = 0; x < resolution.x; ++x) labels[i++] = labelOf({x, y, z});
    return LabelGrid::fromDense(f, labels, kVoid);
}

// Any mesh over a label grid (world coordinates), with the surface
// clearance built; rendered in the grid's local frame.
inline Scene sceneOf(TriangleMesh mesh, LabelGrid grid, MaterialTable table, float ior, RGB environment = {1, 1, 1}) {
    Scene s;
    s.worldOrigin_mm = toLocalFrame(mesh, grid);
    s.geometry = std::make_unique<Geometry>(std::move(mesh));
    s.medium = std::make_unique<LabelMedium>(std::move(grid), std::move(table));
    s.ior = ior;
    s.environment = environment;
    s.clearance = std::make_unique<SurfaceClearance>(*s.geometry, s.medium->frame());
    return s;
}

// The box filled exactly by the grid's voxels.
inline Scene boxScene(const Vec3i& resolution, const Vec3f& voxel_mm,
                      const std::function<Label(const Vec3i&)>& labelOf, MaterialTable table, float ior,
                      RGB environment = {1, 1, 1}, const Point3f& cornerMin_mm = {0, 0, 0}) {
    Point3f hi{cornerMin_mm.x + resolution.x * voxel_mm.x, cornerMin_mm.y + resolution.y * voxel_mm.y,
               cornerMin_mm.z + resolution.z * voxel_mm.z};
    return sceneOf(boxMesh(cornerMin_mm, hi), labelGrid(resolution, voxel_mm, labelOf, cornerMin_mm),
                   std::move(table), ior, environment);
}

}  // namespace pl::synthetic
