#pragma once
/// \file
/// Exact closest points and squared distances from a point to a segment and a triangle, in
/// double precision: the kernels of every distance field, locator and cell query in isoforge
/// (one copy, so all of them agree bit for bit). Distances are |p − closest point|², never the
/// expanded quadratic form. Methods: docs/algorithms/closest_point.md.

#include <algorithm>
#include <cstdint>

#include "isoforge/core/vec.hpp"

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
[[nodiscard, gnu::always_inline]] inline SegmentClosest closest_on_segment(const Vec3& p,
                                                                           const Vec3& a,
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
[[nodiscard, gnu::always_inline]] inline double segment_distance2(const Vec3& p, const Vec3& a,
                                                                  const Vec3& b) {
  return closest_on_segment(p, a, b).dist2;
}

/// Closest point of the union of the three edges of triangle (a, b, c) to `p`, expressed in the
/// triangle's (s, t): what `closest_on_triangle` returns for degenerate (collinear or repeated
/// point) triangles.
[[nodiscard]] TriangleClosest closest_on_triangle_edges(const Vec3& p, const Vec3& a, const Vec3& b,
                                                        const Vec3& c);

/// Closest point of the triangle (a, b, c) to `p` (Eberly's region classification).
[[nodiscard, gnu::always_inline]] inline TriangleClosest closest_on_triangle(const Vec3& p,
                                                                             const Vec3& a,
                                                                             const Vec3& b,
                                                                             const Vec3& c) {
  using F = TriangleFeature;
  const Vec3 e0 = b - a, e1 = c - a, d = a - p;
  const double a00 = dot(e0, e0), a01 = dot(e0, e1), a11 = dot(e1, e1);
  const double b0 = dot(d, e0), b1 = dot(d, e1);
  const double det = a00 * a11 - a01 * a01;
  if (!(det > 1e-14 * a00 * a11)) return closest_on_triangle_edges(p, a, b, c);
  double s = a01 * b1 - a11 * b0;
  double t = a01 * b0 - a00 * b1;
  F f = F::Face;
  // The minimum on the edge s = 0 (t in [0, 1], from a to c) and on the edge t = 0 (s in [0, 1]).
  // Forced inline: the kernel runs inside the distance fields' innermost loops.
  const auto on_edge20 = [&]() __attribute__((always_inline)) {
    s = 0;
    if (b1 >= 0) {
      t = 0, f = F::Vertex0;
    } else if (-b1 >= a11) {
      t = 1, f = F::Vertex2;
    } else {
      t = -b1 / a11, f = F::Edge20;
    }
  };
  const auto on_edge01 = [&]() __attribute__((always_inline)) {
    t = 0;
    if (b0 >= 0) {
      s = 0, f = F::Vertex0;
    } else if (-b0 >= a00) {
      s = 1, f = F::Vertex1;
    } else {
      s = -b0 / a00, f = F::Edge01;
    }
  };
  if (s + t <= det) {
    if (s < 0) {
      if (t < 0 && b0 < 0) {  // region 4, minimum on t = 0
        on_edge01();
      } else {  // region 3 (or 4 with the minimum on s = 0)
        on_edge20();
      }
    } else if (t < 0) {  // region 5
      on_edge01();
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
      on_edge20();
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
      on_edge01();
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
  TriangleClosest r;
  r.s = s;
  r.t = t;
  r.point = a + e0 * s + e1 * t;
  r.dist2 = norm2(p - r.point);
  r.feature = f;
  return r;
}

/// Squared distance from `p` to the triangle (a, b, c).
[[nodiscard, gnu::always_inline]] inline double triangle_distance2(const Vec3& p, const Vec3& a,
                                                                   const Vec3& b, const Vec3& c) {
  return closest_on_triangle(p, a, b, c).dist2;
}

}  // namespace isoforge
