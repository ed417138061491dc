// Exact closest points on segments and triangles (core/closest_point.hpp).
//
// Methods implemented: D. Eberly, "Distance Between Point and Triangle in 3D" (Geometric Tools,
// 1999/2008), the minimization of |B + s E0 + t E1 − P|² over the triangle's parameter domain,
// classified into seven regions of the (s, t) plane; C. Ericson, *Real-Time Collision Detection*
// (2005), 5.1.2, the closest point on a segment.

#include "isoforge/core/closest_point.hpp"

namespace isoforge {

TriangleClosest closest_on_triangle_edges(const Vec3& p, const Vec3& a, const Vec3& b,
                                          const Vec3& c) {
  using F = TriangleFeature;
  const SegmentClosest e01 = closest_on_segment(p, a, b);
  const SegmentClosest e12 = closest_on_segment(p, b, c);
  const SegmentClosest e20 = closest_on_segment(p, c, a);
  const auto pick = [](double u, F at0, F inner, F at1) {
    return u == 0 ? at0 : (u == 1 ? at1 : inner);
  };
  TriangleClosest r;
  if (e01.dist2 <= e12.dist2 && e01.dist2 <= e20.dist2) {
    r.s = e01.t, r.t = 0, r.point = e01.point, r.dist2 = e01.dist2;
    r.feature = pick(e01.t, F::Vertex0, F::Edge01, F::Vertex1);
  } else if (e12.dist2 <= e20.dist2) {
    r.s = 1 - e12.t, r.t = e12.t, r.point = e12.point, r.dist2 = e12.dist2;
    r.feature = pick(e12.t, F::Vertex1, F::Edge12, F::Vertex2);
  } else {
    r.s = 0, r.t = 1 - e20.t, r.point = e20.point, r.dist2 = e20.dist2;
    r.feature = pick(e20.t, F::Vertex2, F::Edge20, F::Vertex0);
  }
  return r;
}

}  // namespace isoforge
