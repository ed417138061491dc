#pragma once
// Mesh checks of the verification suite. Combinatorial checks are exact integer work; geometric
// ones (degenerate faces, self-intersections, orientation) use CGAL's exact predicates on the
// stored float coordinates, so a verdict never disagrees with the data.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/mesh_topology.hpp"

namespace isoforge::verify {

using ComponentReport = SurfaceComponent;

struct MeshReport {
  std::size_t vertices = 0;  ///< points referenced by at least one face
  std::size_t faces = 0;     ///< triangles after fan-triangulating polygons and strips
  std::size_t edges = 0;     ///< unique undirected edges
  std::size_t border_edges = 0;
  std::size_t non_manifold_edges = 0;     ///< edges shared by more than two faces
  std::size_t non_manifold_vertices = 0;  ///< vertices whose faces form more than one fan
  std::size_t inconsistent_edges = 0;     ///< manifold edges both faces traverse the same way
  std::size_t degenerate_faces = 0;       ///< repeated ids or collinear corners (exact)
  std::size_t duplicate_points = 0;       ///< distinct ids with identical coordinates
  /// Pairs of faces that intersect beyond the corner or edge they share (exact; manifold or not).
  std::size_t self_intersections = 0;
  bool self_intersection_checked = false;  ///< the test ran (MeshCheckOptions::self_intersections)
  bool closed = false;                     ///< no border edges
  bool manifold = false;                   ///< no non-manifold edges or vertices
  bool oriented = false;                   ///< no inconsistent edges
  /// Closed, manifold, oriented, no degenerate faces, and every component faces away from the
  /// volume it bounds (exact: CGAL's is_outward_oriented per component and exact nesting; a
  /// component inside another one bounds a cavity and must face inward).
  bool outward = false;
  std::size_t inward_components = 0;  ///< components facing the wrong way (when tested)
  double area = 0;
  double volume = 0;  ///< signed, from the divergence theorem (meaningful when closed)
  std::vector<ComponentReport> components;

  /// Closed, manifold, consistently oriented, no degenerate faces and no self-intersections.
  [[nodiscard]] bool valid_closed_surface() const {
    return closed && manifold && oriented && degenerate_faces == 0 && self_intersection_checked &&
           self_intersections == 0;
  }
};

struct MeshCheckOptions {
  bool self_intersections = true;  ///< run the exact self-intersection test (the slow part)
};

/// Checks the polygons and triangle strips of `mesh` (verts and lines are ignored).
/// \throw Error if the mesh is invalid as data (ids out of range) or has no faces.
[[nodiscard]] MeshReport check_mesh(const PolyData& mesh, const MeshCheckOptions& options = {});

/// Multi-line human-readable summary of a report.
[[nodiscard]] std::string format_report(const MeshReport& r);

/// The names `failed_requirements` accepts: closed, manifold, oriented, no-self-intersections.
[[nodiscard]] const std::vector<std::string>& mesh_requirement_names();

/// The requirements among `names` that `r` fails, each with what failed, e.g.
/// "closed (3 border edges)"; empty when all pass. "no-self-intersections" fails when the test
/// did not run. \throw Error naming an unknown requirement.
[[nodiscard]] std::vector<std::string> failed_requirements(const MeshReport& r,
                                                           const std::vector<std::string>& names);

/// CGAL's exact orientation of four points (sign of det[b − a, c − a, d − a]: +1, 0, −1), the
/// oracle of the library's own predicates (core/predicates.hpp) in the verification tests.
[[nodiscard]] int exact_orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// CGAL's exact closed-triangle intersection test (triangles must not be degenerate).
[[nodiscard]] bool exact_triangles_intersect(const std::array<Vec3, 3>& p,
                                             const std::array<Vec3, 3>& q);

}  // namespace isoforge::verify
