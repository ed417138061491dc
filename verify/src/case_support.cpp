// Shared pieces of the verification cases (see case_support.hpp).

#include "case_support.hpp"

#include <algorithm>
#include <cmath>

namespace isoforge::verify {

GridSpec cubic_grid(const Bounds& box, Index n) {
  const Vec3 size = box.size();
  const double longest = std::max({size.x, size.y, size.z});
  const double h = longest / static_cast<double>(n - 1);
  GridSpec g;
  g.spacing = {h, h, h};
  for (int a = 0; a < 3; ++a) {
    const auto cells = static_cast<Index>(std::ceil(size[a] / h - 1e-9));
    g.dims[static_cast<std::size_t>(a)] = cells + 1;
    g.origin[a] = box.center()[a] - 0.5 * static_cast<double>(cells) * h;
  }
  return g;
}

void record_closed_surface(CaseResult& r, const MeshReport& m) {
  r.equal("border edges (closed)", m.border_edges, std::size_t{0});
  r.equal("non-manifold edges", m.non_manifold_edges, std::size_t{0});
  r.equal("non-manifold vertices", m.non_manifold_vertices, std::size_t{0});
  r.equal("inconsistently oriented edges", m.inconsistent_edges, std::size_t{0});
  r.is_true("outward oriented, every component (exact)", m.outward);
  r.equal("degenerate faces (exact)", m.degenerate_faces, std::size_t{0});
  r.equal("duplicate points", m.duplicate_points, std::size_t{0});
  r.is_true("self-intersection test ran", m.self_intersection_checked);
  r.equal("self-intersecting face pairs (exact)", m.self_intersections, std::size_t{0});
}

void record_bordered_surface(CaseResult& r, const MeshReport& m, const BorderReport& b) {
  r.equal("non-manifold edges", m.non_manifold_edges, std::size_t{0});
  r.equal("non-manifold vertices", m.non_manifold_vertices, std::size_t{0});
  r.equal("inconsistently oriented edges", m.inconsistent_edges, std::size_t{0});
  r.equal("degenerate faces (exact)", m.degenerate_faces, std::size_t{0});
  r.equal("duplicate points", m.duplicate_points, std::size_t{0});
  r.is_true("self-intersection test ran", m.self_intersection_checked);
  r.equal("self-intersecting face pairs (exact)", m.self_intersections, std::size_t{0});
  r.equal("border edges off the volume boundary", b.off_boundary, std::size_t{0});
}

void note_mesh(CaseResult& r, const MeshReport& m, const std::string& prefix) {
  r.note(prefix + "vertices / triangles", fmt::format("{} / {}", m.vertices, m.faces));
  std::size_t g0 = 0, g1 = 0, g2 = 0, other = 0;
  for (const auto& c : m.components) {
    (c.genus == 0 ? g0 : c.genus == 1 ? g1 : c.genus == 2 ? g2 : other) += 1;
  }
  r.note(prefix + "components (genus 0 / 1 / 2 / more)",
         fmt::format("{} ({} / {} / {} / {})", m.components.size(), g0, g1, g2, other));
  if (other > 0 && m.components.size() <= 4) {
    std::string g;
    for (const auto& c : m.components) g += fmt::format("{}{}", g.empty() ? "" : ", ", c.genus);
    r.note(prefix + "genus of each component", g);
  }
}

}  // namespace isoforge::verify
