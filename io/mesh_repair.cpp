#include "io/mesh_repair.h"

#include <array>
#include <map>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include "core/input_error.h"

namespace pl {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;

constexpr size_t kLongestTriangulatedBorder = 100;

std::string MeshRepairSummary::text() const {
    return std::to_string(weldedVertices) + " vertices welded, " + std::to_string(degenerateTriangles) +
           " degenerate triangles dropped, " + std::to_string(reorientedTriangles) + " reoriented, " +
           std::to_string(stitchedEdges) + " edges stitched, " + std::to_string(holesFilled) + " holes filled with " +
           std::to_string(fillTriangles) + " triangles";
}

MeshAsset repairMesh(const MeshAsset& in, const std::string& file, MeshRepairSummary& summary) {
    const TriangleMesh& mesh = in.mesh;
    // Weld equal positions; keep the input's triangle order and which
    // input triangle each soup polygon is.
    std::map<std::array<float, 3>, size_t> welded;
    std::vector<Kernel::Point_3> points;
    std::vector<size_t> weldOf(mesh.positions_mm.size());
    for (size_t v = 0; v < mesh.positions_mm.size(); ++v) {
        const Point3f& p = mesh.positions_mm[v];
        auto [it, added] = welded.emplace(std::array<float, 3>{p.x, p.y, p.z}, points.size());
        if (added) points.emplace_back(p.x, p.y, p.z);
        weldOf[v] = it->second;
    }
    summary.weldedVertices = mesh.positions_mm.size() - points.size();
    std::vector<std::vector<size_t>> polygons;
    std::vector<uint32_t> sourceOf;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const size_t a = weldOf[mesh.indices[3 * t]], b = weldOf[mesh.indices[3 * t + 1]], c = weldOf[mesh.indices[3 * t + 2]];
        if (a == b || b == c || c == a || CGAL::collinear(points[a], points[b], points[c])) {
            summary.degenerateTriangles += 1;
            continue;
        }
        polygons.push_back({a, b, c});
        sourceOf.push_back(uint32_t(t));
    }
    if (polygons.empty()) throw InputError(file, "mesh repair: no triangle with an area");
    PMP::orient_polygon_soup(points, polygons);

    CgalMesh cgal;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, cgal);
    summary.stitchedEdges = PMP::stitch_borders(cgal);
    std::vector<CgalMesh::Halfedge_index> holes;
    PMP::extract_boundary_cycles(cgal, std::back_inserter(holes));
    for (CgalMesh::Halfedge_index h : holes) {
        summary.holesFilled += 1;
        // The triangulation's search is cubic in the border's length where
        // it falls back from Delaunay: long borders get the fan below.
        size_t border = 0;
        for (CgalMesh::Halfedge_index b : CGAL::halfedges_around_face(h, cgal)) border += b.is_valid();
        if (border > kLongestTriangulatedBorder) continue;
        std::vector<CgalMesh::Face_index> added;
        PMP::triangulate_hole(cgal, h, std::back_inserter(added));
        summary.fillTriangles += added.size();
    }
    // A hole the triangulation cannot fill (its border crosses itself) or
    // was not asked to: one face over it, split into a fan around its
    // centroid.
    std::vector<CgalMesh::Halfedge_index> unfilled;
    PMP::extract_boundary_cycles(cgal, std::back_inserter(unfilled));
    for (CgalMesh::Halfedge_index h : unfilled) {
        double x = 0, y = 0, z = 0;
        size_t n = 0;
        for (CgalMesh::Halfedge_index b : CGAL::halfedges_around_face(h, cgal)) {
            const Kernel::Point_3& p = cgal.point(cgal.target(b));
            x += p.x(), y += p.y(), z += p.z(), n += 1;
        }
        const size_t facesBefore = cgal.number_of_faces();
        CGAL::Euler::fill_hole(h, cgal);
        const CgalMesh::Halfedge_index spoke = CGAL::Euler::add_center_vertex(h, cgal);
        cgal.point(cgal.target(spoke)) = Kernel::Point_3(x / n, y / n, z / n);
        summary.fillTriangles += cgal.number_of_faces() - facesBefore;
    }
    if (!CGAL::is_closed(cgal)) {
        std::vector<CgalMesh::Halfedge_index> left;
        PMP::extract_boundary_cycles(cgal, std::back_inserter(left));
        throw InputError(file, "mesh repair: the surface could not be closed (" + std::to_string(left.size()) + " of " +
                                   std::to_string(holes.size()) + " holes left open)");
    }
    // Outwards, shell by shell: each connected component with a negative
    // enclosed volume is turned over. (CGAL's orient_to_bound_a_volume also
    // nests shells, so that a cavity faces inwards, but tests every pair:
    // minutes on models of many small parts. A cavity here faces outwards.)
    auto component = cgal.add_property_map<CgalMesh::Face_index, size_t>("f:component", 0).first;
    const size_t components = PMP::connected_components(cgal, component);
    std::vector<double> volume(components, 0.0);
    for (CgalMesh::Face_index f : cgal.faces()) {
        std::array<Kernel::Point_3, 3> p;
        int k = 0;
        for (CgalMesh::Vertex_index v : CGAL::vertices_around_face(cgal.halfedge(f), cgal)) p[size_t(k++)] = cgal.point(v);
        volume[component[f]] += CGAL::scalar_product(p[0] - CGAL::ORIGIN, CGAL::cross_product(p[1] - CGAL::ORIGIN, p[2] - CGAL::ORIGIN)) / 6.0;
    }
    std::vector<CgalMesh::Face_index> inverted;
    for (CgalMesh::Face_index f : cgal.faces())
        if (volume[component[f]] < 0) inverted.push_back(f);
    PMP::reverse_face_orientations(inverted, cgal);

    // Each triangle with its own vertices, colours from its input triangle
    // (the corner at the same position), or for a fill triangle from an
    // input triangle across one of its edges (its nearest corner).
    const SurfaceAppearance& look = in.appearance;
    MeshAsset out;
    out.appearance.materials = look.materials;
    out.appearance.textures = look.textures;
    auto sourceOfFace = [&](CgalMesh::Face_index f) -> int64_t {
        return size_t(f) < sourceOf.size() ? int64_t(sourceOf[size_t(f)]) : -1;
    };
    for (CgalMesh::Face_index f : cgal.faces()) {
        int64_t source = sourceOfFace(f);
        if (source < 0)
            for (CgalMesh::Halfedge_index h : CGAL::halfedges_around_face(cgal.halfedge(f), cgal)) {
                source = sourceOfFace(cgal.face(cgal.opposite(h)));
                if (source >= 0) break;
            }
        const uint32_t* corners = source >= 0 ? &mesh.indices[3 * size_t(source)] : nullptr;
        for (CgalMesh::Vertex_index v : CGAL::vertices_around_face(cgal.halfedge(f), cgal)) {
            const Kernel::Point_3& p = cgal.point(v);
            const Point3f q(float(p.x()), float(p.y()), float(p.z()));
            out.mesh.indices.push_back(uint32_t(out.mesh.positions_mm.size()));
            out.mesh.positions_mm.push_back(q);
            if (!corners) continue;
            uint32_t nearest = corners[0];
            float best = 1e30f;
            for (int k = 0; k < 3; ++k) {
                const Vec3f d = mesh.positions_mm[corners[k]] - q;
                if (dot(d, d) < best) best = dot(d, d), nearest = corners[k];
            }
            if (!look.uvs.empty()) out.appearance.uvs.push_back(look.uvs[nearest]);
            if (!look.vertexColors.empty()) out.appearance.vertexColors.push_back(look.vertexColors[nearest]);
        }
        // Reoriented: an input triangle that now faces the other way.
        if (size_t(f) < sourceOf.size()) {
            const Point3f* q = &out.mesh.positions_mm[out.mesh.positions_mm.size() - 3];
            const Vec3f now = cross(q[1] - q[0], q[2] - q[0]);
            const Vec3f was = cross(mesh.positions_mm[corners[1]] - mesh.positions_mm[corners[0]],
                                    mesh.positions_mm[corners[2]] - mesh.positions_mm[corners[0]]);
            summary.reorientedTriangles += dot(now, was) < 0.0f;
        }
        if (!corners) {  // a fill with no input neighbour: white
            if (!look.uvs.empty()) out.appearance.uvs.insert(out.appearance.uvs.end(), 3, {0, 0});
            if (!look.vertexColors.empty()) out.appearance.vertexColors.insert(out.appearance.vertexColors.end(), 3, RGB{1, 1, 1});
        }
        if (!look.triangleMaterial.empty())
            out.appearance.triangleMaterial.push_back(source >= 0 ? look.triangleMaterial[size_t(source)] : 0);
    }
    return out;
}

}  // namespace pl
