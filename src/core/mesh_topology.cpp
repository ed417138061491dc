// Combinatorial surface analysis (mesh_topology.hpp): half-edges sorted by undirected edge,
// union-find over face corners (fans at each vertex) and over faces (components).

#include "isoforge/core/mesh_topology.hpp"

#include <algorithm>
#include <tuple>
#include <unordered_map>

#include "isoforge/core/cell.hpp"
#include "isoforge/core/union_find.hpp"

namespace isoforge {

namespace {

struct HalfEdge {
  Index lo, hi;  // undirected key
  Index from;
  std::size_t face;
  int corner_from, corner_to;
};

}  // namespace

std::vector<std::array<Index, 3>> triangulate_faces(const PolyData& mesh) {
  std::vector<std::array<Index, 3>> tris;
  tris.reserve(mesh.polys.connectivity().size() / 3 + mesh.strips.connectivity().size());
  for (std::size_t c = 0; c < mesh.polys.size(); ++c) {
    auto ids = mesh.polys.cell(c);
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) tris.push_back({ids[0], ids[k], ids[k + 1]});
  }
  for (std::size_t c = 0; c < mesh.strips.size(); ++c) {
    auto ids = mesh.strips.cell(c);
    for (std::size_t k = 0; k + 2 < ids.size(); ++k) tris.push_back(strip_triangle(ids, k));
  }
  return tris;
}

SurfaceTopology analyze_topology(const PolyData& mesh) {
  mesh.polys.validate(mesh.points.size(), "polys");
  mesh.strips.validate(mesh.points.size(), "strips");
  const auto tris = triangulate_faces(mesh);
  const std::size_t nf = tris.size();
  SurfaceTopology r;
  r.faces = nf;

  std::vector<HalfEdge> hes;
  hes.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = tris[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) ++r.repeated_vertex_faces;
    for (int k = 0; k < 3; ++k) {
      const Index a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      if (a == b) continue;
      hes.push_back({std::min(a, b), std::max(a, b), a, f, k, (k + 1) % 3});
    }
  }
  std::sort(hes.begin(), hes.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return std::tie(x.lo, x.hi, x.face, x.corner_from) < std::tie(y.lo, y.hi, y.face, y.corner_from);
  });

  UnionFind<> corners(3 * nf);
  UnionFind<> face_sets(nf);
  struct EdgeInfo {
    Index lo, hi;
    std::size_t count, first;
  };
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
      auto corner_at = [](const HalfEdge& h, Index v) {
        return 3 * h.face + static_cast<std::size_t>(h.from == v ? h.corner_from : h.corner_to);
      };
      corners.unite(corner_at(x, x.lo), corner_at(y, x.lo));
      corners.unite(corner_at(x, x.hi), corner_at(y, x.hi));
    }
    i = j;
  }
  r.edges = edges.size();

  // Vertices and their fans (sorted for determinism).
  std::vector<std::pair<Index, std::size_t>> vc;  // (vertex, corner)
  vc.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t k = 0; k < 3; ++k) vc.push_back({tris[f][k], 3 * f + k});
  std::sort(vc.begin(), vc.end());

  // Components.
  std::unordered_map<std::size_t, std::size_t> comp_of_root;
  r.face_component.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    auto [it, inserted] = comp_of_root.try_emplace(face_sets.find(f), comp_of_root.size());
    r.face_component[f] = it->second;
  }
  r.components.resize(comp_of_root.size());
  for (std::size_t f = 0; f < nf; ++f) ++r.components[r.face_component[f]].faces;

  std::vector<std::size_t> roots, comps;
  for (std::size_t i = 0; i < vc.size();) {
    std::size_t j = i;
    roots.clear();
    comps.clear();
    while (j < vc.size() && vc[j].first == vc[i].first) {
      roots.push_back(corners.find(vc[j].second));
      comps.push_back(r.face_component[vc[j].second / 3]);
      ++j;
    }
    ++r.vertices;
    std::sort(roots.begin(), roots.end());
    if (std::unique(roots.begin(), roots.end()) - roots.begin() > 1) ++r.non_manifold_vertices;
    std::sort(comps.begin(), comps.end());
    comps.erase(std::unique(comps.begin(), comps.end()), comps.end());
    for (std::size_t c : comps) ++r.components[c].vertices;
    i = j;
  }

  // Edges and border loops per component.
  std::unordered_map<Index, std::size_t> border_vertex;
  for (const auto& e : edges) {
    ++r.components[r.face_component[hes[e.first].face]].edges;
    if (e.count == 1) {
      border_vertex.try_emplace(e.lo, border_vertex.size());
      border_vertex.try_emplace(e.hi, border_vertex.size());
    }
  }
  UnionFind<> loops(border_vertex.size());
  for (const auto& e : edges) {
    if (e.count == 1) loops.unite(border_vertex[e.lo], border_vertex[e.hi]);
  }
  std::unordered_map<std::size_t, std::size_t> loop_comp;
  for (const auto& e : edges) {
    if (e.count == 1) loop_comp[loops.find(border_vertex[e.lo])] = r.face_component[hes[e.first].face];
  }
  for (const auto& [root, c] : loop_comp) ++r.components[c].border_loops;
  for (auto& c : r.components) {
    c.euler = static_cast<long>(c.vertices) - static_cast<long>(c.edges) + static_cast<long>(c.faces);
    c.closed = c.border_loops == 0;
    c.genus = (2 - c.euler - static_cast<long>(c.border_loops)) / 2;
  }
  return r;
}

}  // namespace isoforge
