#pragma once
/// \file
/// Closest-primitive queries on points, segments and triangles (`PrimitiveSet`): a one-shot
/// function and a reusable locator that keeps its bounding volume hierarchy, as OpenVDB's tools
/// do. Used by the distance fields (Gather), decimation error metrics and probing of surfaces.
/// Method: docs/algorithms/spatial.md.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>

#include "isoforge/spatial/primitives.hpp"

namespace isoforge {

/// The answer of a closest-primitive query.
struct ClosestPrimitive {
  PrimitiveSet::Id id = PrimitiveSet::kNone;  ///< the nearest primitive, or kNone
  double dist2 =
      std::numeric_limits<double>::infinity();  ///< its squared distance (radii not subtracted)
  std::size_t evaluations = 0;                  ///< exact distances computed to answer
};

/// A 4-wide bounding volume hierarchy over a `PrimitiveSet` (kept by reference: it must outlive
/// the locator and not change). Queries are const and thread-safe; exact (the kernels of
/// core/closest_point.hpp decide; the tree's float bounds only prune, conservatively). Ties go
/// to the smallest id, so answers do not depend on the tree.
class PrimitiveLocator {
 public:
  /// Builds the hierarchy (parallel for large sets; the tree does not depend on the thread
  /// count). \throw Error if the set has 2^31 or more primitives.
  explicit PrimitiveLocator(const PrimitiveSet& primitives);
  ~PrimitiveLocator();
  PrimitiveLocator(PrimitiveLocator&&) noexcept;
  PrimitiveLocator& operator=(PrimitiveLocator&&) noexcept;

  /// The nearest primitive to p (id kNone for an empty set).
  [[nodiscard]] ClosestPrimitive closest(const Vec3& p) const;

  /// Improves `best` — a candidate (e.g. a neighbouring query's answer, with its exact dist2) or
  /// the default — to the nearest primitive among those with squared distance below `limit2`,
  /// adding to `best.evaluations`. `best` is unchanged when no primitive is closer.
  void nearest(const Vec3& p, double limit2, ClosestPrimitive& best) const;

  /// Whether some primitive's bounding box lies within sqrt(r2) of the box [lo, hi]
  /// (conservative: may answer true for a box slightly farther than that, never false wrongly).
  [[nodiscard]] bool any_within(const Vec3& lo, const Vec3& hi, double r2) const;

  [[nodiscard]] const PrimitiveSet& primitives() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot: the nearest primitive of `primitives` to p (builds a locator; for many queries
/// keep a `PrimitiveLocator`).
[[nodiscard]] ClosestPrimitive closest_primitive(const PrimitiveSet& primitives, const Vec3& p);

}  // namespace isoforge
