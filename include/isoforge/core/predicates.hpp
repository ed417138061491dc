#pragma once
/// \file
/// Exact geometric predicates on double coordinates: orientation in 2D and 3D, closed triangle
/// intersection and the self-intersection test of two faces of one mesh. Each answer is the sign
/// of the exact real-number result on the given doubles (a floating-point filter decides the
/// easy cases, expansion arithmetic the rest), so no two tests can contradict each other.
/// Exact as long as no intermediate product over- or underflows: coordinate magnitudes and
/// nonzero coordinate differences within [1e-90, 1e90] (always true for float32 data).
/// Methods: docs/algorithms/predicates.md.

#include <array>

#include "isoforge/core/cell_array.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge {

/// A point in the plane.
using Vec2 = std::array<double, 2>;

/// Sign of the signed area of (a, b, c): +1 if a, b, c turn counterclockwise (the x axis turned
/// towards the y axis), −1 if clockwise, 0 if collinear (exact).
[[nodiscard]] int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

/// Sign of det[b − a, c − a, d − a] = dot(cross(b − a, c − a), d − a): +1 if d lies on the side
/// of the plane through a, b, c towards which the right-hand normal cross(b − a, c − a) points
/// (a, b, c counterclockwise seen from d), −1 on the other side, 0 if the four points are
/// coplanar (exact). For a = (0,0,0), b = (1,0,0), c = (0,1,0), d = (0,0,1) it is +1.
[[nodiscard]] int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Whether the closed triangles p and q have a common point (exact). Degenerate triangles
/// (repeated or collinear corners) are the segments or points they cover.
[[nodiscard]] bool triangles_intersect(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& q);

/// Whether two faces of one mesh intersect beyond what they legitimately share (exact); equal
/// ids mean a shared vertex (and equal coordinates). No shared id: any common point counts. One
/// shared vertex: a common point other than that vertex's position counts. A shared edge: the
/// faces count only if they overlap — coplanar with the opposite corners on the same side of the
/// edge (degenerate faces: if they have a common point off the edge). Three shared ids (a
/// duplicate face): true. For non-degenerate faces this is the rule of verify/'s CGAL check.
[[nodiscard]] bool faces_intersect(const std::array<Vec3, 3>& p, const std::array<Index, 3>& pid,
                                   const std::array<Vec3, 3>& q, const std::array<Index, 3>& qid);

/// Whether the corners of the triangle are collinear or coincide (exact).
[[nodiscard]] bool triangle_degenerate(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace isoforge
