// Mesh checks for the verification suite (see mesh_checks.hpp).
//
// Combinatorics (edges, fans, components, Euler characteristic) come from the library's
// analyze_topology (exact integer work). Geometry uses CGAL 5.5 with the Epick kernel (exact
// predicates, inexact constructions; only predicates are used): collinearity for degenerate
// faces, box_self_intersection_d plus exact triangle predicates for self-intersections, and Polygon
// Mesh Processing's volume_connected_components (is_outward_oriented per component plus exact
// nesting) for outward orientation.
//
// Self-intersections are tested on the triangles as given, manifold or not, with the rules of
// PMP::self_intersections (which needs a halfedge mesh, so it cannot take a non-manifold one
// as it is): faces sharing an edge intersect only if they are coplanar and overlap (their third
// corners on the same side of the edge); faces sharing one corner only if the edge opposite that
// corner in one of them meets the other; other faces if they meet at all.

#include "mesh_checks.hpp"

#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>
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

using Tri = std::array<std::size_t, 3>;

// Whether triangles a and b intersect beyond the corners and edge they share (exact).
bool faces_intersect(const std::vector<Point>& pts, const Tri& a, const Tri& b) {
  const auto P = [&](std::size_t id) -> const Point& { return pts[id]; };
  int shared = 0;
  int ia = 0, ib = 0;  // a shared corner's position in a and in b (the first one found)
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (a[static_cast<std::size_t>(i)] == b[static_cast<std::size_t>(j)]) {
        if (shared++ == 0) {
          ia = i;
          ib = j;
        }
      }
    }
  }
  const auto at = [](const Tri& t, int i) { return t[static_cast<std::size_t>(i % 3)]; };
  if (shared == 3) return true;  // the same three corners: the faces coincide
  if (shared == 2) {
    // The corners of a and b off the shared edge (u, v).
    std::size_t ra = 0, rb = 0;
    for (std::size_t id : a)
      if (id != b[0] && id != b[1] && id != b[2]) ra = id;
    for (std::size_t id : b)
      if (id != a[0] && id != a[1] && id != a[2]) rb = id;
    const std::size_t u = at(a, ia), v = (at(a, ia + 1) != ra) ? at(a, ia + 1) : at(a, ia + 2);
    // Non-coplanar faces meet only along the line of the edge, i.e. on the edge itself.
    return CGAL::coplanar(P(u), P(v), P(ra), P(rb)) &&
           CGAL::coplanar_orientation(P(u), P(v), P(ra), P(rb)) == CGAL::POSITIVE;
  }
  if (shared == 1) {
    // Their intersection is convex and contains the shared corner; if it holds another point,
    // it leaves one of the faces through the edge opposite the shared corner.
    const Kernel::Triangle_3 ta(P(a[0]), P(a[1]), P(a[2])), tb(P(b[0]), P(b[1]), P(b[2]));
    const Kernel::Segment_3 sa(P(at(a, ia + 1)), P(at(a, ia + 2)));
    const Kernel::Segment_3 sb(P(at(b, ib + 1)), P(at(b, ib + 2)));
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(Kernel::Triangle_3(P(a[0]), P(a[1]), P(a[2])),
                            Kernel::Triangle_3(P(b[0]), P(b[1]), P(b[2])));
}

// Pairs of triangles that intersect beyond what they share; candidates are the pairs whose
// bounding boxes (exact for double coordinates, closed) meet.
std::size_t count_self_intersections(const std::vector<Point>& pts, const std::vector<Tri>& tris) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t,
                                                        CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
  std::vector<Box> boxes;
  boxes.reserve(tris.size());
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const auto& t = tris[f];
    boxes.emplace_back(pts[t[0]].bbox() + pts[t[1]].bbox() + pts[t[2]].bbox(), f);
  }
  std::vector<const Box*> ptrs;
  ptrs.reserve(boxes.size());
  for (const Box& b : boxes) ptrs.push_back(&b);
  std::size_t count = 0;
  CGAL::box_self_intersection_d(ptrs.begin(), ptrs.end(), [&](const Box* a, const Box* b) {
    if (faces_intersect(pts, tris[a->info()], tris[b->info()])) ++count;
  });
  return count;
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

  // Self-intersections (exact) among the non-degenerate faces, manifold or not.
  std::vector<Tri> faces_ok;
  faces_ok.reserve(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    if (degenerate[f]) continue;
    faces_ok.push_back({static_cast<std::size_t>(tris[f][0]), static_cast<std::size_t>(tris[f][1]),
                        static_cast<std::size_t>(tris[f][2])});
  }
  if (options.self_intersections) {
    r.self_intersections = count_self_intersections(pts, faces_ok);
    r.self_intersection_checked = true;
  }

  // Outward orientation of a valid closed surface, on a CGAL halfedge mesh that keeps every
  // face's orientation.
  const bool orientable = r.closed && r.manifold && r.oriented && r.degenerate_faces == 0;
  if (orientable) {
    std::vector<std::vector<std::size_t>> soup;
    soup.reserve(faces_ok.size());
    for (const Tri& t : faces_ok) soup.push_back({t[0], t[1], t[2]});
    if (PMP::is_polygon_soup_a_polygon_mesh(soup)) {
      Mesh sm;
      PMP::polygon_soup_to_polygon_mesh(pts, soup, sm);
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
  return r;
}

int exact_orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return static_cast<int>(CGAL::orientation(to_point(a), to_point(b), to_point(c), to_point(d)));
}

bool exact_triangles_intersect(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& q) {
  return CGAL::do_intersect(Kernel::Triangle_3(to_point(p[0]), to_point(p[1]), to_point(p[2])),
                            Kernel::Triangle_3(to_point(q[0]), to_point(q[1]), to_point(q[2])));
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

const std::vector<std::string>& mesh_requirement_names() {
  static const std::vector<std::string> names{"closed", "manifold", "oriented",
                                              "no-self-intersections"};
  return names;
}

std::vector<std::string> failed_requirements(const MeshReport& r,
                                             const std::vector<std::string>& names) {
  std::vector<std::string> failed;
  for (const std::string& n : names) {
    if (n == "closed") {
      if (!r.closed) failed.push_back(fmt::format("closed ({} border edges)", r.border_edges));
    } else if (n == "manifold") {
      if (!r.manifold) {
        failed.push_back(fmt::format("manifold ({} non-manifold edges, {} non-manifold vertices)",
                                     r.non_manifold_edges, r.non_manifold_vertices));
      }
    } else if (n == "oriented") {
      if (!r.oriented) {
        failed.push_back(fmt::format("oriented ({} inconsistent edges)", r.inconsistent_edges));
      }
    } else if (n == "no-self-intersections") {
      if (!r.self_intersection_checked) {
        failed.push_back("no-self-intersections (not checked)");
      } else if (r.self_intersections > 0) {
        failed.push_back(fmt::format("no-self-intersections ({} intersecting face pairs)",
                                     r.self_intersections));
      }
    } else {
      throw Error("--require: unknown check '" + n +
                  "' (known: closed, manifold, oriented, no-self-intersections)");
    }
  }
  return failed;
}

}  // namespace isoforge::verify
