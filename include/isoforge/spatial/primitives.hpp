#pragma once
/// \file
/// Points (optionally balls), segments and triangles over one vertex array: the generating
/// primitives of distance fields and what `PrimitiveLocator` answers closest-point queries on.

#include <array>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

#include "isoforge/core/closest_point.hpp"
#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Primitive ids run over points, then segments, then triangles: [0, segment_begin()) are
/// points, [segment_begin(), triangle_begin()) segments, [triangle_begin(), size()) triangles.
class PrimitiveSet {
 public:
  using Id = std::uint32_t;
  static constexpr Id kNone = std::numeric_limits<Id>::max();  ///< no primitive

  PrimitiveSet() = default;
  /// \throw Error if a vertex id is out of range, a vertex is not finite, or there are 2^32 − 1
  /// or more vertices or primitives.
  PrimitiveSet(std::vector<Vec3> vertices, std::vector<Id> points,
               std::vector<std::array<Id, 2>> segments, std::vector<std::array<Id, 3>> triangles);

  /// Makes the point primitives balls: `radii[k]` (finite, ≥ 0) for point k; the distance to a
  /// ball is |x − center| − radius. \throw Error on a wrong count or a bad radius.
  void set_radii(std::vector<double> radii);

  [[nodiscard]] const std::vector<Vec3>& vertices() const { return vertices_; }
  [[nodiscard]] const std::vector<Id>& points() const { return points_; }
  [[nodiscard]] const std::vector<std::array<Id, 2>>& segments() const { return segments_; }
  [[nodiscard]] const std::vector<std::array<Id, 3>>& triangles() const { return triangles_; }
  [[nodiscard]] const std::vector<double>& radii() const { return radii_; }
  [[nodiscard]] bool has_radii() const { return !radii_.empty(); }

  [[nodiscard]] Id size() const { return size_; }
  [[nodiscard]] Id segment_begin() const { return segment_begin_; }
  [[nodiscard]] Id triangle_begin() const { return triangle_begin_; }

  /// The radius of primitive `id` (0 for segments, triangles and points without radii).
  [[nodiscard]] double radius(Id id) const {
    return id < segment_begin_ && !radii_.empty() ? radii_[id] : 0.0;
  }
  /// Squared distance from x to primitive `id` (to its center or axis: radii not subtracted),
  /// with the exact kernels of core/closest_point.hpp.
  [[nodiscard, gnu::always_inline]] double dist2(Id id, const Vec3& x) const {
    if (id >= triangle_begin_) {
      const auto& t = triangles_[id - triangle_begin_];
      return triangle_distance2(x, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]);
    }
    if (id >= segment_begin_) {
      const auto& s = segments_[id - segment_begin_];
      return segment_distance2(x, vertices_[s[0]], vertices_[s[1]]);
    }
    return norm2(x - vertices_[points_[id]]);
  }
  /// Bounding box of primitive `id` (radii not included).
  [[nodiscard]] Bounds bounds(Id id) const;
  /// Calls f(vertex position) for each vertex of primitive `id`.
  template <class F>
  void for_each_vertex(Id id, F&& f) const {
    if (id >= triangle_begin_) {
      for (Id v : triangles_[id - triangle_begin_]) f(vertices_[v]);
    } else if (id >= segment_begin_) {
      for (Id v : segments_[id - segment_begin_]) f(vertices_[v]);
    } else {
      f(vertices_[points_[id]]);
    }
  }

 private:
  std::vector<Vec3> vertices_;
  std::vector<Id> points_;
  std::vector<std::array<Id, 2>> segments_;
  std::vector<std::array<Id, 3>> triangles_;
  std::vector<double> radii_;
  Id segment_begin_ = 0, triangle_begin_ = 0, size_ = 0;
};

/// The primitives of polygonal data: vertex cells give points, line and polyline segments
/// segments, polygons (fan-triangulated) and strips triangles. \throw Error naming `what` on an
/// invalid input, one with no primitives, a non-finite point, or too many points or primitives.
[[nodiscard]] PrimitiveSet primitives_of(const PolyData& input, std::string_view what);

}  // namespace isoforge
