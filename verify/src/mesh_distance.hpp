#pragma once
// Closest-point distances from points to a triangle mesh: CGAL's AABB tree (AABB_tree over
// AABB_triangle_primitive, with the kd-tree that accelerates distance queries), the second and
// last translation unit of verify/ that includes CGAL (see mesh_distance.cpp).

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge::verify {

/// The non-degenerate triangles of a mesh (polygons fan-triangulated, strips split) in an AABB
/// tree. Queries are exact searches: the nearest triangle is found by the tree's branch and
/// bound, the distance to it is computed in double (CGAL's Epick kernel), so the error is a
/// few ulps of the coordinates. Collinear triangles (exact test) are left out: their points lie
/// on edges of the triangles around them in a valid surface.
class MeshDistance {
 public:
  /// \throw Error if the mesh has no non-degenerate triangle or ids are out of range.
  explicit MeshDistance(const PolyData& mesh);
  ~MeshDistance();
  MeshDistance(const MeshDistance&) = delete;
  MeshDistance& operator=(const MeshDistance&) = delete;

  [[nodiscard]] std::size_t triangles() const;
  /// Distance from each point to the mesh (multi-threaded, deterministic).
  [[nodiscard]] std::vector<double> distances(std::span<const Vec3> points) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isoforge::verify
