#pragma once
/// \file
/// Implicit functions F(x, y, z) with the region-separation property of the chapter
/// (section 1.5.2): F < 0 inside, F = 0 on the surface, F > 0 outside. Primitives, affine
/// transforms and boolean combinations compose into one value type, `ImplicitFunction`.
///
/// **Distance convention.** The plane, sphere, cylinder, cone, box and torus are *signed
/// distance functions* (|∇F| = 1), not VTK's algebraic forms (VTK's sphere is |p − c|² − r²).
/// Distances make the narrow band of a sparse level set exactly w voxels wide, make linear
/// interpolation along grid edges more accurate when contouring, and let bounds over a box be
/// computed from the value at its center. Booleans by min/max keep |∇F| ≤ 1 (they are bounds on
/// the distance, exact outside a union and inside an intersection). The general quadric and the
/// superquadric are algebraic (no closed-form distance exists); the superquadric is scaled so that
/// it is a distance for a sphere.
///
/// **Evaluation.** `value`/`gradient` evaluate one point. `evaluate` evaluates many points in
/// blocks: the function tree is walked once per block of points and each node runs a tight loop
/// over the block, so there is no virtual call per point.

#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "isoforge/core/error.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge {

/// A closed interval [lo, hi] of function values.
struct Interval {
  double lo = 0;
  double hi = 0;
};

/// An affine map p ↦ A p + t (row-major 3x3 A).
struct Affine {
  std::array<double, 9> a{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 t{0, 0, 0};

  [[nodiscard]] Vec3 apply(const Vec3& p) const {
    return {a[0] * p.x + a[1] * p.y + a[2] * p.z + t.x, a[3] * p.x + a[4] * p.y + a[5] * p.z + t.y,
            a[6] * p.x + a[7] * p.y + a[8] * p.z + t.z};
  }
  [[nodiscard]] static Affine translation(const Vec3& t);
  [[nodiscard]] static Affine scaling(const Vec3& s);
  /// Rotation by `degrees` about `axis` (right-hand rule). \throw Error on a zero axis.
  [[nodiscard]] static Affine rotation(const Vec3& axis, double degrees);
  /// this ∘ other (apply `other` first).
  [[nodiscard]] Affine operator*(const Affine& other) const;
  /// \throw Error naming `what` if the matrix is singular or not finite.
  [[nodiscard]] Affine inverse() const;
};

/// The deepest an implicit function may be nested: at most this many levels of functions from
/// the outermost one to a primitive (`sphere()` is 1 level, `complement(sphere())` 2). Evaluation
/// recurses once per level with up to 12 KiB of stack (blocks of 512 points), so the limit keeps
/// it within about 1.2 MiB, a third of a TBB worker thread's stack, sanitizers included.
inline constexpr int kMaxFunctionDepth = 100;

/// An implicit function: a primitive, a transformed function, or a boolean combination.
/// Immutable value type; copies share the tree (cheap). Combinations are at most
/// kMaxFunctionDepth levels deep: a factory that would exceed it throws Error.
class ImplicitFunction {
 public:
  /// Node kinds (see the factory functions).
  enum class Kind : std::uint8_t {
    Plane,
    Sphere,
    Cylinder,
    Cone,
    Box,
    Quadric,
    Superquadric,
    Torus,
    Transform,
    Union,
    Intersection,
    Difference,
    Complement,
    Offset,
  };

  // ---- primitives (every parameter is checked: Error names the parameter) ----

  /// Signed distance to the plane through `origin` with normal `normal` (positive on the normal
  /// side). \throw Error if the normal has zero length or anything is non-finite.
  [[nodiscard]] static ImplicitFunction plane(const Vec3& origin, const Vec3& normal);
  /// Signed distance |p − center| − radius. \throw Error if radius < 0 or non-finite.
  [[nodiscard]] static ImplicitFunction sphere(const Vec3& center, double radius);
  /// Infinite cylinder around the line through `point` along `axis`.
  [[nodiscard]] static ImplicitFunction cylinder(const Vec3& point, const Vec3& axis, double radius);
  /// Infinite double cone with apex `apex`, axis `axis` and half angle `half_angle_degrees`
  /// in (0, 90): ρ cos θ − |h| sin θ, the exact signed distance to the conical surface.
  [[nodiscard]] static ImplicitFunction cone(const Vec3& apex, const Vec3& axis,
                                             double half_angle_degrees);
  /// Axis-aligned box [min, max], exact signed distance. \throw Error if min > max on an axis.
  [[nodiscard]] static ImplicitFunction box(const Vec3& min, const Vec3& max);
  /// General quadric a0x² + a1y² + a2z² + a3xy + a4yz + a5xz + a6x + a7y + a8z + a9 (VTK's
  /// coefficient order). Algebraic, not a distance. \throw Error if all quadratic and linear
  /// coefficients are zero.
  [[nodiscard]] static ImplicitFunction quadric(const std::array<double, 10>& coefficients);
  /// Superquadric centered at `center` with semi-axes `radii`: with
  /// g = (|x/a|^(2/e) + |y/b|^(2/e))^(e/n) + |z/c|^(2/n) the value is (g^(n/2) − 1)·min(a, b, c),
  /// where n = `north_south` (roundness from pole to pole) and e = `east_west` roundness; both in
  /// (0, 4]. n = e = 1 gives an ellipsoid (a sphere's exact distance when a = b = c).
  [[nodiscard]] static ImplicitFunction superquadric(const Vec3& center, const Vec3& radii,
                                                     double north_south, double east_west);
  /// Torus around `axis` through `center`: ring radius `major`, tube radius `minor`.
  /// \throw Error unless 0 <= minor and 0 < major.
  [[nodiscard]] static ImplicitFunction torus(const Vec3& center, const Vec3& axis, double major,
                                              double minor);

  // ---- combinations ----

  /// The function placed by `placement` (object space → world space): F'(p) = F(placement⁻¹ p).
  /// A non-rigid placement scales distances. \throw Error if the placement is singular.
  [[nodiscard]] ImplicitFunction transformed(const Affine& placement) const;
  /// Union min(F1, …, Fn). \throw Error if `parts` is empty.
  [[nodiscard]] static ImplicitFunction union_of(std::vector<ImplicitFunction> parts);
  /// Intersection max(F1, …, Fn). \throw Error if `parts` is empty.
  [[nodiscard]] static ImplicitFunction intersection_of(std::vector<ImplicitFunction> parts);
  /// Difference max(F, −G): this minus `other`.
  [[nodiscard]] ImplicitFunction minus(const ImplicitFunction& other) const;
  /// Complement −F (inside and outside swapped).
  [[nodiscard]] ImplicitFunction complement() const;
  /// F − distance: grows the region by `distance` (shrinks if negative).
  [[nodiscard]] ImplicitFunction offset(double distance) const;

  friend ImplicitFunction operator|(const ImplicitFunction& a, const ImplicitFunction& b) {
    return union_of({a, b});
  }
  friend ImplicitFunction operator&(const ImplicitFunction& a, const ImplicitFunction& b) {
    return intersection_of({a, b});
  }
  friend ImplicitFunction operator-(const ImplicitFunction& a, const ImplicitFunction& b) {
    return a.minus(b);
  }

  // ---- evaluation ----

  [[nodiscard]] double value(const Vec3& p) const;
  /// Analytic gradient (of the active branch for booleans; a one-sided gradient on creases).
  [[nodiscard]] Vec3 gradient(const Vec3& p) const;
  /// Values at many points (xyz interleaved doubles, `values.size()` points).
  void evaluate(std::span<const double> xyz, std::span<double> values) const;
  /// Values at many points given as structure-of-arrays; all spans have the same size.
  void evaluate(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                std::span<double> values) const;
  /// Conservative bounds of F over an axis-aligned box (interval arithmetic for algebraic
  /// nodes, Lipschitz bounds for distances). Used to skip regions far from the surface.
  [[nodiscard]] Interval bound(const Bounds& box) const;

  [[nodiscard]] Kind kind() const;
  /// Levels of nesting: 1 for a primitive, 1 + the deepest operand for a combination; at most
  /// kMaxFunctionDepth.
  [[nodiscard]] int depth() const;
  /// The expression, in the syntax `parse_implicit` reads (see docs/implicit.md).
  [[nodiscard]] std::string to_string() const;

  struct Node;  ///< implementation detail (defined in function.cpp)
  [[nodiscard]] const Node& node() const { return *node_; }

 private:
  explicit ImplicitFunction(std::shared_ptr<const Node> node) : node_(std::move(node)) {}
  std::shared_ptr<const Node> node_;
};

/// The chapter's ice cream cone (Fig. 1.23c, after VTK's IceCream example): a cone of half angle
/// 20° along +x clipped by the planes x = 0.1 and x = 1.2, united with a sphere of radius 0.5 at
/// (1.333, 0, 0) minus a "bite" sphere of radius 0.25 at (1.5, 0, 0.5).
/// Natural sampling bounds: [-0.1, 2.0] x [-0.7, 0.7] x [-0.7, 0.7].
[[nodiscard]] ImplicitFunction ice_cream_cone();

}  // namespace isoforge
