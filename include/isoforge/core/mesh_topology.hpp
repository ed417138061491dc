#pragma once
/// \file
/// Combinatorial analysis of a polygonal surface: edges, borders, manifoldness, orientation
/// consistency, connected components and their Euler characteristic and genus. Exact (integer)
/// work on the connectivity only; `verify/` adds the geometric checks with CGAL.

#include <array>
#include <cstddef>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// One connected component (faces joined through shared edges).
struct SurfaceComponent {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t border_loops = 0;  ///< closed chains of border edges
  long euler = 0;                ///< V − E + F
  long genus = 0;                ///< from V − E + F = 2 − 2g − b (for manifold components)
  bool closed = false;
};

struct SurfaceTopology {
  std::size_t vertices = 0;  ///< points used by at least one face
  std::size_t faces = 0;     ///< triangles after fan-triangulating polygons and strips
  std::size_t edges = 0;     ///< unique undirected edges
  std::size_t border_edges = 0;           ///< edges of exactly one face
  std::size_t non_manifold_edges = 0;     ///< edges of more than two faces
  std::size_t non_manifold_vertices = 0;  ///< vertices whose faces form more than one fan
  std::size_t inconsistent_edges = 0;     ///< two-face edges traversed the same way by both
  std::size_t repeated_vertex_faces = 0;  ///< faces using one point twice
  std::vector<SurfaceComponent> components;
  /// Component of each triangle (in fan-triangulation order: polys, then strips).
  std::vector<std::size_t> face_component;

  [[nodiscard]] bool closed() const { return border_edges == 0; }
  [[nodiscard]] bool manifold() const { return non_manifold_edges == 0 && non_manifold_vertices == 0; }
  [[nodiscard]] bool oriented() const { return inconsistent_edges == 0; }
};

/// Analyzes the polygons and strips of `mesh` (verts and lines are ignored). Polygons are fan
/// triangulated first. \throw Error if a cell refers to a point out of range.
[[nodiscard]] SurfaceTopology analyze_topology(const PolyData& mesh);

/// The polygons and strips of `mesh` as triangles (fan triangulation; strips alternate).
[[nodiscard]] std::vector<std::array<Index, 3>> triangulate_faces(const PolyData& mesh);

}  // namespace isoforge
