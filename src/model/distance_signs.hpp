#pragma once
// Private: signs of distance fields to closed triangle meshes — the angle-weighted pseudonormals
// of J. A. Bærentzen and H. Aanæs, "Signed distance computation using the angle weighted
// pseudonormal", IEEE TVCG 11(3), 2005: the sign of (p − q)·n, q the closest point and n the
// pseudonormal of the face, edge or vertex holding it.

#include <array>
#include <cstdint>
#include <vector>

#include "isoforge/core/closest_point.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/spatial/primitives.hpp"

namespace isoforge::model_detail {

using u32 = std::uint32_t;

struct Pseudonormals {
  std::vector<Vec3> face, vertex, edge;
  std::vector<std::array<u32, 3>> tri_edges;  // edges 01, 12, 20 of each triangle

  [[nodiscard]] double sign(const PrimitiveSet& P, u32 id, const Vec3& x) const {
    const u32 t = id - P.triangle_begin();
    const auto& v = P.triangles()[t];
    const TriangleClosest c =
        closest_on_triangle(x, P.vertices()[v[0]], P.vertices()[v[1]], P.vertices()[v[2]]);
    const Vec3* n = nullptr;
    switch (c.feature) {
      case TriangleFeature::Face:
        n = &face[t];
        break;
      case TriangleFeature::Edge01:
        n = &edge[tri_edges[t][0]];
        break;
      case TriangleFeature::Edge12:
        n = &edge[tri_edges[t][1]];
        break;
      case TriangleFeature::Edge20:
        n = &edge[tri_edges[t][2]];
        break;
      case TriangleFeature::Vertex0:
        n = &vertex[v[0]];
        break;
      case TriangleFeature::Vertex1:
        n = &vertex[v[1]];
        break;
      case TriangleFeature::Vertex2:
        n = &vertex[v[2]];
        break;
    }
    return dot(x - c.point, *n) < 0 ? -1.0 : 1.0;
  }
};

/// The pseudonormals of the triangles of `P` (made from `in`), with inward-oriented closed
/// components flipped. \throw Error if `P` has points or segments, or (with `require_closed`)
/// the mesh is not closed, manifold and consistently oriented, naming the problem.
[[nodiscard]] Pseudonormals build_pseudonormals(const PolyData& in, const PrimitiveSet& P,
                                                bool require_closed);

}  // namespace isoforge::model_detail
