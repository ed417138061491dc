#pragma once
/// \file
/// Exact closest points and squared Euclidean distances from a point to the generating primitives
/// of implicit modeling — a point, a line segment, a triangle — in double precision. These are the
/// kernels of every distance field in isoforge (dense, sparse, scatter and gather strategies all
/// call exactly these functions, so their values agree bit for bit).
///
/// References implemented:
/// - D. Eberly, "Distance Between Point and Triangle in 3D" (Geometric Tools, 1999/2008): the
///   minimization of the quadratic |B + s E0 + t E1 - P|² over the triangle's parameter domain,
///   classified into seven regions of the (s, t) plane.
/// - C. Ericson, *Real-Time Collision Detection* (2005), 5.1.2: closest point on a segment.
///
/// Distances are computed from the closest point (|P - Q|²), not from the expanded quadratic
/// form, so they do not suffer its cancellation far from the primitive. Degenerate triangles
/// (collinear or repeated points, relative Gram determinant below 1e-14) are measured as the union
/// of their three edges; a zero-length segment as its point.

#include <algorithm>
#include <cstdint>

#include "isoforge/core/vec.hpp"

// The kernels run in the innermost loops of the distance fields: inline them even when large.
#if defined(__GNUC__)
#define ISOFORGE_KERNEL inline __attribute__((always_inline))
#else
#define ISOFORGE_KERNEL inline
#endif

namespace isoforge {

/// The part of a triangle (a, b, c) that holds the closest point.
enum class TriangleFeature : std::uint8_t {
  Face,     ///< the interior
  Edge01,   ///< the open edge a-b
  Edge12,   ///< the open edge b-c
  Edge20,   ///< the open edge c-a
  Vertex0,  ///< a
  Vertex1,  ///< b
  Vertex2,  ///< c
};

/// Closest point on a segment: `point` = a + t (b - a), t in [0, 1].
struct SegmentClosest {
  double dist2 = 0;  ///< squared distance
  double t = 0;      ///< parameter of the closest point
  Vec3 point;        ///< the closest point
};

/// Closest point on a triangle: `point` = a + s (b - a) + t (c - a), s, t >= 0, s + t <= 1.
struct TriangleClosest {
  double dist2 = 0;  ///< squared distance
  double s = 0, t = 0;
  Vec3 point;  ///< the closest point
  TriangleFeature feature = TriangleFeature::Face;
};

/// Closest point of the segment [a, b] to `p`.
[[nodiscard]] ISOFORGE_KERNEL SegmentClosest closest_on_segment(const Vec3& p, const Vec3& a,
                                                                const Vec3& b) {
  const Vec3 e = b - a;
  const double len2 = dot(e, e);
  double t = 0;
  if (len2 > 0) {
    // Written as the distance fields' vectorized row loops compute it: min/max, no branches.
    t = std::min(std::max(dot(p - a, e) * (1.0 / len2), 0.0), 1.0);
  }
  SegmentClosest r;
  r.t = t;
  r.point = a + e * t;
  r.dist2 = norm2(p - r.point);
  return r;
}

/// Squared distance from `p` to the segment [a, b].
[[nodiscard]] ISOFORGE_KERNEL double segment_distance2(const Vec3& p, const Vec3& a,
                                                       const Vec3& b) {
  return closest_on_segment(p, a, b).dist2;
}

namespace model_detail {

// The closest of the three edges of a degenerate triangle, expressed in (s, t).
inline TriangleClosest degenerate_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
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

}  // namespace model_detail

/// Closest point of the triangle (a, b, c) to `p` (Eberly's region classification).
[[nodiscard]] ISOFORGE_KERNEL TriangleClosest closest_on_triangle(const Vec3& p, const Vec3& a,
                                                                  const Vec3& b, const Vec3& c) {
  using F = TriangleFeature;
  const Vec3 e0 = b - a, e1 = c - a, d = a - p;
  const double a00 = dot(e0, e0), a01 = dot(e0, e1), a11 = dot(e1, e1);
  const double b0 = dot(d, e0), b1 = dot(d, e1);
  const double det = a00 * a11 - a01 * a01;
  if (!(det > 1e-14 * a00 * a11)) return model_detail::degenerate_triangle(p, a, b, c);
  double s = a01 * b1 - a11 * b0;
  double t = a01 * b0 - a00 * b1;
  F f = F::Face;
  // Written without lambdas: the kernel is inlined into hot loops and must not call out.
  // Minimum on the edge s = 0 (t in [0, 1]): from c back to a.
#define ISOFORGE_ON_EDGE20()          \
  s = 0;                              \
  if (b1 >= 0) {                      \
    t = 0, f = F::Vertex0;            \
  } else if (-b1 >= a11) {            \
    t = 1, f = F::Vertex2;            \
  } else {                            \
    t = -b1 / a11, f = F::Edge20;     \
  }
  // Minimum on the edge t = 0 (s in [0, 1]).
#define ISOFORGE_ON_EDGE01()          \
  t = 0;                              \
  if (b0 >= 0) {                      \
    s = 0, f = F::Vertex0;            \
  } else if (-b0 >= a00) {            \
    s = 1, f = F::Vertex1;            \
  } else {                            \
    s = -b0 / a00, f = F::Edge01;     \
  }
  if (s + t <= det) {
    if (s < 0) {
      if (t < 0 && b0 < 0) {  // region 4, minimum on t = 0
        ISOFORGE_ON_EDGE01()
      } else {  // region 3 (or 4 with the minimum on s = 0)
        ISOFORGE_ON_EDGE20()
      }
    } else if (t < 0) {  // region 5
      ISOFORGE_ON_EDGE01()
    } else {  // region 0: the interior
      s /= det;
      t /= det;
    }
  } else if (s < 0) {  // region 2
    const double tmp0 = a01 + b0, tmp1 = a11 + b1;
    if (tmp1 > tmp0) {  // the edge s + t = 1, parameterized by s
      const double numer = tmp1 - tmp0, denom = a00 - 2 * a01 + a11;
      if (numer >= denom) {
        s = 1, t = 0, f = F::Vertex1;
      } else {
        s = numer / denom, t = 1 - s, f = F::Edge12;
      }
    } else if (tmp1 <= 0) {
      s = 0, t = 1, f = F::Vertex2;
    } else {
      ISOFORGE_ON_EDGE20()
    }
  } else if (t < 0) {  // region 6
    const double tmp0 = a01 + b1, tmp1 = a00 + b0;
    if (tmp1 > tmp0) {  // the edge s + t = 1, parameterized by t from b
      const double numer = tmp1 - tmp0, denom = a00 - 2 * a01 + a11;
      if (numer >= denom) {
        t = 1, s = 0, f = F::Vertex2;
      } else {
        t = numer / denom, s = 1 - t, f = F::Edge12;
      }
    } else if (tmp1 <= 0) {
      s = 1, t = 0, f = F::Vertex1;
    } else {
      ISOFORGE_ON_EDGE01()
    }
  } else {  // region 1
    const double numer = a11 + b1 - a01 - b0;
    if (numer <= 0) {
      s = 0, t = 1, f = F::Vertex2;
    } else {
      const double denom = a00 - 2 * a01 + a11;
      if (numer >= denom) {
        s = 1, t = 0, f = F::Vertex1;
      } else {
        s = numer / denom, t = 1 - s, f = F::Edge12;
      }
    }
  }
#undef ISOFORGE_ON_EDGE20
#undef ISOFORGE_ON_EDGE01
  TriangleClosest r;
  r.s = s;
  r.t = t;
  r.point = a + e0 * s + e1 * t;
  r.dist2 = norm2(p - r.point);
  r.feature = f;
  return r;
}

/// Squared distance from `p` to the triangle (a, b, c).
[[nodiscard]] ISOFORGE_KERNEL double triangle_distance2(const Vec3& p, const Vec3& a, const Vec3& b,
                                                        const Vec3& c) {
  return closest_on_triangle(p, a, b, c).dist2;
}

}  // namespace isoforge
