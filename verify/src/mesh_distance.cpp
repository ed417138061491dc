// Closest-point distances to a triangle mesh with CGAL 5.5's AABB tree (see mesh_distance.hpp).
// The tree holds the triangles by value; distance queries use the tree's internal kd-tree of
// sample points (accelerate_distance_queries) to start the branch-and-bound search, which is
// built once up front so that concurrent queries (TBB) only read the tree.

#include "mesh_distance.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "isoforge/core/mesh_topology.hpp"

namespace isoforge::verify {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;

Point to_point(const Vec3& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

struct MeshDistance::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

MeshDistance::MeshDistance(const PolyData& mesh) : impl_(std::make_unique<Impl>()) {
  mesh.polys.validate(mesh.points.size(), "polys");
  mesh.strips.validate(mesh.points.size(), "strips");
  const auto tris = triangulate_faces(mesh);
  impl_->triangles.reserve(tris.size());
  for (const auto& t : tris) {
    const Point a = to_point(mesh.points[static_cast<std::size_t>(t[0])]);
    const Point b = to_point(mesh.points[static_cast<std::size_t>(t[1])]);
    const Point c = to_point(mesh.points[static_cast<std::size_t>(t[2])]);
    if (CGAL::collinear(a, b, c)) continue;
    impl_->triangles.emplace_back(a, b, c);
  }
  if (impl_->triangles.empty())
    throw Error("MeshDistance: the mesh has no non-degenerate triangle");
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

MeshDistance::~MeshDistance() = default;

std::size_t MeshDistance::triangles() const {
  return impl_->triangles.size();
}

std::vector<double> MeshDistance::distances(std::span<const Vec3> points) const {
  std::vector<double> d(points.size());
  const Tree& tree = impl_->tree;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        d[i] = std::sqrt(tree.squared_distance(to_point(points[i])));
                      }
                    });
  return d;
}

}  // namespace isoforge::verify
