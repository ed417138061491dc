// Mesh checks for the verification suite (see mesh_checks.hpp).
//
// Combinatorics (edges, fans, components, Euler characteristic) are computed here with integer
// arithmetic. Geometry uses CGAL 5.5: exact predicates (Epick: exact predicates, inexact
// constructions) for collinearity, Polygon Mesh Processing for self-intersections
// (box-intersection filtered, exact triangle-triangle predicates) and outward orientation.

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
#include <numeric>
#include <unordered_map>

namespace isoforge::verify {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

using Tri = std::array<Index, 3>;

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

std::vector<Tri> triangulate(const PolyData& mesh) {
  std::vector<Tri> tris;
  for (std::size_t c = 0; c < mesh.polys.size(); ++c) {
    auto ids = mesh.polys.cell(c);
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) tris.push_back({ids[0], ids[k], ids[k + 1]});
  }
  for (std::size_t c = 0; c < mesh.strips.size(); ++c) {
    auto ids = mesh.strips.cell(c);
    for (std::size_t k = 0; k + 2 < ids.size(); ++k) {
      if (k % 2 == 0) {
        tris.push_back({ids[k], ids[k + 1], ids[k + 2]});
      } else {
        tris.push_back({ids[k + 1], ids[k], ids[k + 2]});
      }
    }
  }
  return tris;
}

Point to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

// A directed half-edge of face f from a to b, keyed by its undirected edge.
struct HalfEdge {
  Index lo, hi;  // undirected key
  Index from;    // a
  std::size_t face;
  int corner_from, corner_to;
};

}  // namespace

MeshReport check_mesh(const PolyData& mesh, const MeshCheckOptions& options) {
  mesh.polys.validate(mesh.points.size(), "polys");
  mesh.strips.validate(mesh.points.size(), "strips");
  const std::vector<Tri> tris = triangulate(mesh);
  if (tris.empty()) throw Error("check_mesh: the mesh has no polygons");

  MeshReport r;
  r.faces = tris.size();
  const std::size_t nf = tris.size();

  // Points as stored (float or double) converted exactly to double.
  std::vector<Point> pts(mesh.points.size());
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = to_point(mesh.points[i]);

  // Degenerate faces (exact).
  std::vector<bool> degenerate(nf, false);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = tris[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
        CGAL::collinear(pts[static_cast<std::size_t>(t[0])], pts[static_cast<std::size_t>(t[1])],
                        pts[static_cast<std::size_t>(t[2])])) {
      degenerate[f] = true;
      ++r.degenerate_faces;
    }
  }

  // Half-edges grouped by undirected edge.
  std::vector<HalfEdge> hes;
  hes.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      Index a = tris[f][static_cast<std::size_t>(k)], b = tris[f][static_cast<std::size_t>((k + 1) % 3)];
      if (a == b) continue;
      hes.push_back({std::min(a, b), std::max(a, b), a, f, k, (k + 1) % 3});
    }
  }
  std::sort(hes.begin(), hes.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return std::tie(x.lo, x.hi, x.face) < std::tie(y.lo, y.hi, y.face);
  });

  UnionFind corners(3 * nf);  // corner (f, k) = 3f + k; fans = classes of corners at a vertex
  UnionFind face_sets(nf);
  struct EdgeInfo { Index lo, hi; std::size_t count; std::size_t first; };
  std::vector<EdgeInfo> edges;
  for (std::size_t i = 0; i < hes.size();) {
    std::size_t j = i;
    while (j < hes.size() && hes[j].lo == hes[i].lo && hes[j].hi == hes[i].hi) ++j;
    const std::size_t n = j - i;
    edges.push_back({hes[i].lo, hes[i].hi, n, i});
    for (std::size_t k = i + 1; k < j; ++k) face_sets.unite(hes[i].face, hes[k].face);
    if (n == 1) {
      ++r.border_edges;
    } else if (n > 2) {
      ++r.non_manifold_edges;
    } else {
      const HalfEdge& x = hes[i];
      const HalfEdge& y = hes[i + 1];
      if (x.from == y.from) ++r.inconsistent_edges;
      // Join the corners at each end of this manifold edge: same vertex, adjacent faces.
      auto corner_at = [](const HalfEdge& h, Index v) {
        return 3 * h.face + static_cast<std::size_t>(h.from == v ? h.corner_from : h.corner_to);
      };
      corners.unite(corner_at(x, x.lo), corner_at(y, x.lo));
      corners.unite(corner_at(x, x.hi), corner_at(y, x.hi));
    }
    i = j;
  }
  r.edges = edges.size();

  // Vertices: referenced points, fans per vertex.
  std::unordered_map<Index, std::vector<std::size_t>> vertex_corners;
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t k = 0; k < 3; ++k) vertex_corners[tris[f][k]].push_back(3 * f + k);
  r.vertices = vertex_corners.size();
  for (auto& [v, cs] : vertex_corners) {
    std::vector<std::size_t> roots;
    for (std::size_t c : cs) roots.push_back(corners.find(c));
    std::sort(roots.begin(), roots.end());
    if (std::unique(roots.begin(), roots.end()) - roots.begin() > 1) ++r.non_manifold_vertices;
  }

  // Duplicate points among referenced vertices (identical stored coordinates).
  {
    std::vector<std::pair<Vec3, Index>> coords;
    coords.reserve(vertex_corners.size());
    for (auto& [v, cs] : vertex_corners) coords.push_back({mesh.points[static_cast<std::size_t>(v)], v});
    std::sort(coords.begin(), coords.end(), [](const auto& a, const auto& b) {
      return std::tie(a.first.x, a.first.y, a.first.z) < std::tie(b.first.x, b.first.y, b.first.z);
    });
    for (std::size_t i = 1; i < coords.size(); ++i)
      if (coords[i].first == coords[i - 1].first) ++r.duplicate_points;
  }

  r.closed = r.border_edges == 0;
  r.manifold = r.non_manifold_edges == 0 && r.non_manifold_vertices == 0;
  r.oriented = r.inconsistent_edges == 0;

  // Area and signed volume (divergence theorem), in double.
  for (const auto& t : tris) {
    const Vec3 a = mesh.points[static_cast<std::size_t>(t[0])];
    const Vec3 b = mesh.points[static_cast<std::size_t>(t[1])];
    const Vec3 c = mesh.points[static_cast<std::size_t>(t[2])];
    r.area += 0.5 * norm(cross(b - a, c - a));
    r.volume += dot(a, cross(b, c)) / 6.0;
  }

  // Components: V - E + F and border loops per component.
  {
    std::unordered_map<std::size_t, std::size_t> comp_of_root;
    std::vector<std::size_t> comp(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      auto [it, inserted] = comp_of_root.try_emplace(face_sets.find(f), comp_of_root.size());
      comp[f] = it->second;
    }
    r.components.resize(comp_of_root.size());
    for (std::size_t f = 0; f < nf; ++f) ++r.components[comp[f]].faces;
    for (auto& [v, cs] : vertex_corners) {
      // A non-manifold vertex shared by two components counts in each.
      std::vector<std::size_t> cc;
      for (std::size_t c : cs) cc.push_back(comp[c / 3]);
      std::sort(cc.begin(), cc.end());
      cc.erase(std::unique(cc.begin(), cc.end()), cc.end());
      for (std::size_t c : cc) ++r.components[c].vertices;
    }
    // Border loops: union border edges sharing a vertex, per component.
    std::unordered_map<Index, std::size_t> border_vertex;
    std::vector<std::pair<Index, Index>> border;
    for (const auto& e : edges) {
      ++r.components[comp[hes[e.first].face]].edges;
      if (e.count == 1) border.push_back({e.lo, e.hi});
    }
    for (const auto& [a, b] : border) {
      border_vertex.try_emplace(a, border_vertex.size());
      border_vertex.try_emplace(b, border_vertex.size());
    }
    UnionFind loops(border_vertex.size());
    for (const auto& [a, b] : border) loops.unite(border_vertex[a], border_vertex[b]);
    std::unordered_map<std::size_t, std::size_t> loop_comp;
    for (const auto& e : edges) {
      if (e.count != 1) continue;
      loop_comp[loops.find(border_vertex[e.lo])] = comp[hes[e.first].face];
    }
    for (auto& [root, c] : loop_comp) ++r.components[c].border_loops;
    for (auto& c : r.components) {
      c.euler = static_cast<long>(c.vertices) - static_cast<long>(c.edges) + static_cast<long>(c.faces);
      c.closed = c.border_loops == 0;
      c.genus = (2 - c.euler - static_cast<long>(c.border_loops)) / 2;
    }
  }

  // Geometry with CGAL on the non-degenerate faces.
  if (options.self_intersections || (r.closed && r.manifold && r.oriented)) {
    std::vector<Point> soup_points = pts;
    std::vector<std::vector<std::size_t>> soup;
    soup.reserve(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      if (degenerate[f]) continue;
      soup.push_back({static_cast<std::size_t>(tris[f][0]), static_cast<std::size_t>(tris[f][1]),
                      static_cast<std::size_t>(tris[f][2])});
    }
    // Orienting the soup duplicates points at non-manifold vertices, which keeps the geometry
    // and lets CGAL build a halfedge mesh of any input.
    PMP::orient_polygon_soup(soup_points, soup);
    if (PMP::is_polygon_soup_a_polygon_mesh(soup)) {
      Mesh sm;
      PMP::polygon_soup_to_polygon_mesh(soup_points, soup, sm);
      if (options.self_intersections) {
        std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
        PMP::self_intersections(faces(sm), sm, std::back_inserter(pairs));
        r.self_intersections = pairs.size();
        r.self_intersection_checked = true;
      }
      if (r.closed && r.manifold && r.oriented && r.degenerate_faces == 0) {
        r.outward = PMP::is_outward_oriented(sm);
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
  if (r.closed && r.manifold && r.oriented) {
    s += fmt::format("outward oriented (exact): {}\n", r.outward ? "yes" : "no");
  }
  s += fmt::format("degenerate faces (exact): {}\n", r.degenerate_faces);
  s += fmt::format("duplicate points: {}\n", r.duplicate_points);
  if (r.self_intersection_checked) {
    s += fmt::format("self-intersecting face pairs (exact): {}\n", r.self_intersections);
  } else {
    s += "self-intersections: not checked (not representable as a polygon mesh)\n";
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
