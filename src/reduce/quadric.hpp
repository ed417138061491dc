#pragma once
// Garland–Heckbert error quadrics: Q(p) = pᵀ A p + 2 bᵀ p + c, the sum of weighted squared
// distances from p to a set of planes; and the placement that minimises it robustly.

#include <algorithm>
#include <cmath>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <vector>

#include "isoforge/core/progress.hpp"
#include "isoforge/core/vec.hpp"
#include "isoforge/reduce/decimate.hpp"
#include "reduce/edit_mesh.hpp"

namespace isoforge::reduce {

struct Quadric {
  // Symmetric A (xx, xy, xz, yy, yz, zz), b and c.
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
  double b0 = 0, b1 = 0, b2 = 0;
  double c = 0;

  /// The plane n·p + d = 0 (n of unit length) with weight w.
  static Quadric plane(const Vec3& n, double d, double w) {
    Quadric q;
    q.a00 = w * n.x * n.x;
    q.a01 = w * n.x * n.y;
    q.a02 = w * n.x * n.z;
    q.a11 = w * n.y * n.y;
    q.a12 = w * n.y * n.z;
    q.a22 = w * n.z * n.z;
    q.b0 = w * n.x * d;
    q.b1 = w * n.y * d;
    q.b2 = w * n.z * d;
    q.c = w * d * d;
    return q;
  }

  Quadric& operator+=(const Quadric& o) {
    a00 += o.a00;
    a01 += o.a01;
    a02 += o.a02;
    a11 += o.a11;
    a12 += o.a12;
    a22 += o.a22;
    b0 += o.b0;
    b1 += o.b1;
    b2 += o.b2;
    c += o.c;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }

  /// A x.
  [[nodiscard]] Vec3 times_a(const Vec3& x) const {
    return {a00 * x.x + a01 * x.y + a02 * x.z, a01 * x.x + a11 * x.y + a12 * x.z,
            a02 * x.x + a12 * x.y + a22 * x.z};
  }
  /// Q(p), clamped at 0 (rounding can make it slightly negative).
  [[nodiscard]] double operator()(const Vec3& p) const {
    const Vec3 a = times_a(p);
    const double v = p.x * a.x + p.y * a.y + p.z * a.z + 2 * (b0 * p.x + b1 * p.y + b2 * p.z) + c;
    return v > 0 ? v : 0;
  }
};

/// Σ w_i |p − x_i|²: point quadrics, kept apart from the planes so errors stay distances to
/// planes. Pulls placements toward the merged vertices.
struct PointQuadric {
  double w = 0, x = 0, y = 0, z = 0, xx = 0;  // Σ w, Σ w x, Σ w |x|²

  static PointQuadric at(const Vec3& p, double w) {
    return {w, w * p.x, w * p.y, w * p.z, w * dot(p, p)};
  }
  PointQuadric& operator+=(const PointQuadric& o) {
    w += o.w;
    x += o.x;
    y += o.y;
    z += o.z;
    xx += o.xx;
    return *this;
  }
  friend PointQuadric operator+(PointQuadric a, const PointQuadric& b) { return a += b; }
  [[nodiscard]] double operator()(const Vec3& p) const {
    const double v = w * dot(p, p) - 2 * (x * p.x + y * p.y + z * p.z) + xx;
    return v > 0 ? v : 0;
  }
  /// q + this as one quadric (for the placement).
  [[nodiscard]] Quadric added_to(Quadric q) const {
    q.a00 += w;
    q.a11 += w;
    q.a22 += w;
    q.b0 -= x;
    q.b1 -= y;
    q.b2 -= z;
    q.c += xx;
    return q;
  }
};

/// What a vertex carries through the collapses: the quadric of its planes, its point quadric
/// and the area of its faces, summed when vertices merge. 128 bytes on two cache lines, so an
/// edge's evaluation reads its two ends' records and nothing else of theirs.
struct alignas(64) VertexQuadric {
  Quadric planes;
  PointQuadric point;
  double area = 0;

  VertexQuadric& operator+=(const VertexQuadric& o) {
    planes += o.planes;
    point += o.point;
    area += o.area;
    return *this;
  }
  friend VertexQuadric operator+(VertexQuadric a, const VertexQuadric& b) { return a += b; }
  /// The planes and the point quadric as one quadric (for the placement and the cost).
  [[nodiscard]] Quadric total() const { return point.added_to(planes); }
};
static_assert(sizeof(VertexQuadric) == 128);

/// The minimiser of q next to `anchor` (the edge midpoint): the exact one when q's Hessian A is
/// well conditioned (Cramer's rule), otherwise the damped step anchor + (A + λI)⁻¹(−A anchor − b)
/// with λ = `relative_cutoff` / 10 × trace(A), which keeps directions whose eigenvalues are well
/// above λ and drops those well below it, so a flat or cylindrical neighbourhood (singular or
/// nearly singular system) places the vertex on the minimising set next to the anchor instead of
/// far away along it.
Vec3 minimize(const Quadric& q, const Vec3& anchor, double relative_cutoff = 1e-3);

/// The minimiser of q on the plane n·p = offset, next to `anchor` (the edge midpoint): the
/// volume-preserving placement (Lindstrom–Turk's first constraint). Within the plane the 2×2
/// system is solved exactly when well conditioned and damped toward the anchor's projection
/// otherwise, as `minimize` does in 3D. Returns nullopt when the constraint is not usable: n is
/// short against `normal_scale` (the faces' normals nearly cancel, as at the tip of a spike) or
/// the plane is farther from the anchor than `max_offset`.
[[nodiscard]] std::optional<Vec3> minimize_on_plane(const Quadric& q, const Vec3& anchor,
                                                    const Vec3& n, double offset,
                                                    double normal_scale, double max_offset);

/// Weight of the point quadric each vertex gets (× its faces' area): small enough not to move
/// placements measurably, large enough to order collapses on flat regions (where every plane
/// error is zero) by edge length, so fans stay small instead of sweeping through the mesh.
inline constexpr double kPointQuadricWeight = 1e-7;

/// The placement of a merged vertex: `minimize(q, anchor)`, unless one of `alternatives` (the
/// merged vertices' positions, the anchor) has a smaller q — a safeguard against rounding.
[[nodiscard]] inline Vec3 place(const Quadric& q, const Vec3& anchor,
                                std::initializer_list<Vec3> alternatives) {
  Vec3 p = minimize(q, anchor);
  double best = q(p);
  for (const Vec3& x : alternatives) {
    const double e = q(x);
    if (e < best) {
      best = e;
      p = x;
    }
  }
  return p;
}

/// The quadrics of every vertex: its faces' planes weighted by area, plus (with
/// `preserve_boundary`) planes through border edges perpendicular to their face and (with a
/// feature angle below 180) the same planes along feature edges, weighted by
/// `boundary_weight` × the squared edge length; a point quadric at the vertex
/// (kPointQuadricWeight × its faces' area); and that area. Parallel. With `side` (one entry per
/// vertex) only the vertices whose entry is `which` are computed, the others left as they are
/// (the halves of a partitioned run fill one set); `quadrics` must then have a vertex's size.
void vertex_quadrics(const EditMesh& mesh, const DecimateOptions& options,
                     std::vector<VertexQuadric>& quadrics, const ProgressCallback& progress,
                     std::span<const std::uint8_t> side = {}, std::uint8_t which = 0);

}  // namespace isoforge::reduce
