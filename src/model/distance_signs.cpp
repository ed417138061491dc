// Signs of distance fields: angle-weighted pseudonormals of closed triangle meshes
// (distance_signs.hpp).

#include "distance_signs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "isoforge/core/mesh_topology.hpp"

namespace isoforge::model_detail {

Pseudonormals build_pseudonormals(const PolyData& in, const PrimitiveSet& P, bool require_closed) {
  if (!P.points().empty() || !P.segments().empty()) {
    throw Error("distance: signed distance needs a closed triangle mesh, but the input has " +
                std::to_string(in.verts.size()) + " vertex and " + std::to_string(in.lines.size()) +
                " line cells");
  }
  const SurfaceTopology topo = analyze_topology(in);
  if (require_closed) {
    if (!topo.manifold()) {
      throw Error("distance: signed distance needs a manifold mesh, but it has " +
                  std::to_string(topo.non_manifold_edges) + " non-manifold edges and " +
                  std::to_string(topo.non_manifold_vertices) + " non-manifold vertices");
    }
    if (!topo.oriented()) {
      throw Error("distance: signed distance needs a consistently oriented mesh, but " +
                  std::to_string(topo.inconsistent_edges) +
                  " edges are traversed the same way by both their faces (inconsistent "
                  "orientation)");
    }
    if (!topo.closed()) {
      throw Error("distance: signed distance needs a closed mesh, but it is open (" +
                  std::to_string(topo.border_edges) + " border edges)");
    }
  }
  const std::size_t nt = P.triangles().size();
  Pseudonormals pn;
  pn.face.resize(nt);
  // Orientation per component: flip components that enclose a negative volume.
  std::vector<double> volume(topo.components.size(), 0.0);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = P.triangles()[t];
    const Vec3 a = P.vertices()[v[0]], b = P.vertices()[v[1]], c = P.vertices()[v[2]];
    volume[topo.face_component[t]] += dot(a, cross(b, c));
    const Vec3 n = cross(b - a, c - a);
    const double len = norm(n);
    pn.face[t] = len > 0 ? n / len : Vec3{};
  }
  for (std::size_t t = 0; t < nt; ++t) {
    const std::size_t comp = topo.face_component[t];
    if (volume[comp] < 0 && topo.components[comp].closed) pn.face[t] = -pn.face[t];
  }
  pn.vertex.assign(P.vertices().size(), Vec3{});
  struct EdgeUse {
    u32 lo, hi;
    u32 slot;  // 3 * triangle + local edge
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = P.triangles()[t];
    for (int k = 0; k < 3; ++k) {
      const u32 i = v[static_cast<std::size_t>(k)], j = v[static_cast<std::size_t>((k + 1) % 3)],
                l = v[static_cast<std::size_t>((k + 2) % 3)];
      // Angle at vertex i between edges to j and l.
      const Vec3 e1 = P.vertices()[j] - P.vertices()[i], e2 = P.vertices()[l] - P.vertices()[i];
      const double n1 = norm(e1), n2 = norm(e2);
      if (n1 > 0 && n2 > 0) {
        const double cosang = std::clamp(dot(e1, e2) / (n1 * n2), -1.0, 1.0);
        pn.vertex[i] += pn.face[t] * std::acos(cosang);
      }
      uses.push_back(
          {std::min(i, j), std::max(i, j), static_cast<u32>(3 * t + static_cast<std::size_t>(k))});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return a.lo != b.lo ? a.lo < b.lo : (a.hi != b.hi ? a.hi < b.hi : a.slot < b.slot);
  });
  pn.tri_edges.resize(nt);
  for (std::size_t s = 0; s < uses.size();) {
    std::size_t e = s;
    Vec3 sum{};
    while (e < uses.size() && uses[e].lo == uses[s].lo && uses[e].hi == uses[s].hi) {
      sum += pn.face[uses[e].slot / 3];
      ++e;
    }
    const u32 edge_id = static_cast<u32>(pn.edge.size());
    pn.edge.push_back(sum);
    for (std::size_t k = s; k < e; ++k) pn.tri_edges[uses[k].slot / 3][uses[k].slot % 3] = edge_id;
    s = e;
  }
  return pn;
}

}  // namespace isoforge::model_detail
