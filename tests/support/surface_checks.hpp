#pragma once
// Shared test helpers for surfaces and grids: closed-manifold expectations, signed volume,
// cubic sampling grids.

#include <gtest/gtest.h>

#include <string>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge::test {

/// Expects a closed, 2-manifold, consistently oriented surface whose every point is used (one
/// point per crossed edge, no strays) and no face repeats a point.
inline void expect_closed_manifold(const PolyData& pd, const std::string& what) {
  const SurfaceTopology t = analyze_topology(pd);
  EXPECT_EQ(t.border_edges, 0u) << what;
  EXPECT_EQ(t.non_manifold_edges, 0u) << what;
  EXPECT_EQ(t.non_manifold_vertices, 0u) << what;
  EXPECT_EQ(t.inconsistent_edges, 0u) << what;
  EXPECT_EQ(t.repeated_vertex_faces, 0u) << what;
  EXPECT_EQ(t.vertices, pd.points.size()) << what;
}

/// Signed volume enclosed by the triangles of `pd` (divergence theorem; positive when outward).
inline double signed_volume(const PolyData& pd) {
  double v = 0;
  for (const auto& t : triangulate_faces(pd)) {
    v += dot(pd.points[static_cast<std::size_t>(t[0])],
             cross(pd.points[static_cast<std::size_t>(t[1])], pd.points[static_cast<std::size_t>(t[2])])) /
         6;
  }
  return v;
}

/// n^3 samples with corners at (lo, lo, lo) and (hi, hi, hi).
inline GridSpec cube_grid(double lo, double hi, Index n) {
  Bounds b;
  b.extend({lo, lo, lo});
  b.extend({hi, hi, hi});
  return GridSpec::from_bounds(b, {n, n, n});
}

}  // namespace isoforge::test
