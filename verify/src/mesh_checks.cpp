// Mesh checks for the verification suite (see mesh_checks.hpp).
//
// Combinatorics (edges, fans, components, Euler characteristic) come from the library's
// analyze_topology (exact integer work). Geometry uses CGAL 5.5 with the Epick kernel (exact
// predicates, inexact constructions; only predicates are used): collinearity for degenerate
// faces, Polygon Mesh Processing self_intersections (box-intersection filter, exact
// triangle-triangle predicates) and volume_connected_components (is_outward_oriented per
// component plus exact nesting) for outward orientation.

#include "mesh_checks.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <functional>
#include <tuple>

namespace isoforge::verify {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

Point to_point(const Vec3& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

MeshReport check_mesh(const PolyData& mesh, const MeshCheckOptions& options) {
  const SurfaceTopology topo = analyze_topology(mesh);
  const auto tris = triangulate_faces(mesh);
  if (tris.empty()) throw Error("check_mesh: the mesh has no polygons");
  const std::size_t nf = tris.size();

  MeshReport r;
  r.faces = topo.faces;
  r.vertices = topo.vertices;
  r.edges = topo.edges;
  r.border_edges = topo.border_edges;
  r.non_manifold_edges = topo.non_manifold_edges;
  r.non_manifold_vertices = topo.non_manifold_vertices;
  r.inconsistent_edges = topo.inconsistent_edges;
  r.components = topo.components;
  r.closed = topo.closed();
  r.manifold = topo.manifold();
  r.oriented = topo.oriented();
  r.self_intersection_requested = options.self_intersections;

  // Points as stored (float or double) converted exactly to double.
  std::vector<Point> pts(mesh.points.size());
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = to_point(mesh.points[i]);

  // Degenerate faces (exact).
  std::vector<bool> degenerate(nf, false);
  std::vector<bool> used(mesh.points.size(), false);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = tris[f];
    for (Index id : t) used[static_cast<std::size_t>(id)] = true;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
        CGAL::collinear(pts[static_cast<std::size_t>(t[0])], pts[static_cast<std::size_t>(t[1])],
                        pts[static_cast<std::size_t>(t[2])])) {
      degenerate[f] = true;
      ++r.degenerate_faces;
    }
  }

  // Duplicate points among used points (identical stored coordinates).
  {
    std::vector<Vec3> coords;
    for (std::size_t i = 0; i < used.size(); ++i) {
      if (used[i]) coords.push_back(mesh.points[i]);
    }
    std::sort(coords.begin(), coords.end(), [](const Vec3& a, const Vec3& b) {
      return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    });
    for (std::size_t i = 1; i < coords.size(); ++i) {
      if (coords[i] == coords[i - 1]) ++r.duplicate_points;
    }
  }

  // Area and signed volume (divergence theorem), in double.
  for (const auto& t : tris) {
    const Vec3 a = mesh.points[static_cast<std::size_t>(t[0])];
    const Vec3 b = mesh.points[static_cast<std::size_t>(t[1])];
    const Vec3 c = mesh.points[static_cast<std::size_t>(t[2])];
    r.area += 0.5 * norm(cross(b - a, c - a));
    r.volume += dot(a, cross(b, c)) / 6.0;
  }

  // Geometry with CGAL on the non-degenerate faces.
  const bool orientable = r.closed && r.manifold && r.oriented && r.degenerate_faces == 0;
  if (options.self_intersections || orientable) {
    std::vector<Point> soup_points = pts;
    std::vector<std::vector<std::size_t>> soup;
    soup.reserve(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      if (degenerate[f]) continue;
      soup.push_back({static_cast<std::size_t>(tris[f][0]), static_cast<std::size_t>(tris[f][1]),
                      static_cast<std::size_t>(tris[f][2])});
    }
    // A valid surface becomes a halfedge mesh as it is, keeping every face's orientation. Any
    // other soup is oriented first, which duplicates points at non-manifold vertices and edges
    // (keeping the geometry), so self-intersections can be tested on any input.
    const bool as_is = PMP::is_polygon_soup_a_polygon_mesh(soup);
    if (!as_is) PMP::orient_polygon_soup(soup_points, soup);
    if (PMP::is_polygon_soup_a_polygon_mesh(soup)) {
      Mesh sm;
      PMP::polygon_soup_to_polygon_mesh(soup_points, soup, sm);
      if (options.self_intersections) {
        std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
        PMP::self_intersections(faces(sm), sm, std::back_inserter(pairs));
        r.self_intersections = pairs.size();
        r.self_intersection_checked = true;
      }
      if (orientable && as_is) {
        // Outward, exactly: for every surface component, CGAL's is_outward_oriented (the
        // orientation of the faces at its lexicographically extreme vertex, decided by exact
        // orientation predicates), compared with its nesting level (side_of_triangle_mesh, exact
        // ray/triangle predicates): components at even levels bound a volume from outside and
        // must face outward, those at odd levels bound a cavity and must face inward.
        auto volume_id = sm.add_property_map<Mesh::Face_index, std::size_t>("f:volume", 0).first;
        std::vector<std::size_t> nesting;
        std::vector<bool> outward;
        PMP::volume_connected_components(sm, volume_id,
                                         CGAL::parameters::nesting_levels(std::ref(nesting))
                                             .is_cc_outward_oriented(std::ref(outward))
                                             .do_orientation_tests(true));
        r.inward_components = 0;
        for (std::size_t c = 0; c < outward.size() && c < nesting.size(); ++c) {
          if (outward[c] != (nesting[c] % 2 == 0)) ++r.inward_components;
        }
        r.outward = !outward.empty() && r.inward_components == 0;
      }
    }
  }
  return r;
}

std::string format_report(const MeshReport& r) {
  std::string s;
  s += fmt::format("vertices {}  faces {} (triangles)  edges {}\n", r.vertices, r.faces, r.edges);
  s += fmt::format("closed: {} ({} border edges)\n", r.closed ? "yes" : "no", r.border_edges);
  s += fmt::format("manifold: {} ({} non-manifold edges, {} non-manifold vertices)\n",
                   r.manifold ? "yes" : "no", r.non_manifold_edges, r.non_manifold_vertices);
  s += fmt::format("consistently oriented: {} ({} inconsistent edges)\n", r.oriented ? "yes" : "no",
                   r.inconsistent_edges);
  if (r.closed && r.manifold && r.oriented && r.degenerate_faces == 0) {
    s += fmt::format("outward oriented (exact): {} ({} components facing the wrong way)\n",
                     r.outward ? "yes" : "no", r.inward_components);
  }
  s += fmt::format("degenerate faces (exact): {}\n", r.degenerate_faces);
  s += fmt::format("duplicate points: {}\n", r.duplicate_points);
  if (r.self_intersection_checked) {
    s += fmt::format("self-intersecting face pairs (exact): {}\n", r.self_intersections);
  } else if (r.self_intersection_requested) {
    s += "self-intersections: not checked (the faces do not form a polygon mesh)\n";
  } else {
    s += "self-intersections: not checked (skipped)\n";
  }
  s += fmt::format("area {:.9g}  signed volume {:.9g}\n", r.area, r.volume);
  s += fmt::format("components: {}\n", r.components.size());
  const std::size_t shown = std::min<std::size_t>(r.components.size(), 20);
  for (std::size_t i = 0; i < shown; ++i) {
    const auto& c = r.components[i];
    s += fmt::format("  #{}: V {} E {} F {}  chi {}  border loops {}  genus {}\n", i, c.vertices,
                     c.edges, c.faces, c.euler, c.border_loops, c.genus);
  }
  if (shown < r.components.size()) s += fmt::format("  ... {} more\n", r.components.size() - shown);
  return s;
}

}  // namespace isoforge::verify
