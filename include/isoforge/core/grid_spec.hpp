#pragma once
/// \file
/// A regular grid of sample points, shared by sampling, distance fields, the attractor and
/// probing: point (i, j, k) at origin + (i, j, k) * spacing, i fastest.

#include <cstddef>
#include <string_view>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

struct GridSpec {
  Dims dims{64, 64, 64};
  Vec3 origin{0, 0, 0};
  Vec3 spacing{1, 1, 1};

  /// A grid whose first and last samples lie on the box corners (VTK's model bounds). Axes with
  /// dims 1 sample the box's minimum. \throw Error on dims < 1, an empty or non-finite box, or
  /// dims > 1 along an axis of zero extent.
  [[nodiscard]] static GridSpec from_bounds(const Bounds& bounds, const Dims& dims);

  /// Coordinate of sample `i` along `axis`, computed exactly as every sampler computes it (so
  /// dense and sparse samples of one grid agree bit for bit).
  [[nodiscard]] double coordinate(int axis, Index i) const {
    return origin[axis] + static_cast<double>(i) * spacing[axis];
  }
  [[nodiscard]] Vec3 point(Index i, Index j, Index k) const {
    return {coordinate(0, i), coordinate(1, j), coordinate(2, k)};
  }
  /// Number of samples. \throw Error (naming `what`) on dims < 1 or overflow.
  [[nodiscard]] std::size_t num_points(std::string_view what = "grid") const {
    return checked_point_count(dims, what);
  }
  /// Checks dims (≥ 1, no overflow), a finite origin and spacing, positive along every axis
  /// with more than one sample (every axis when `all_axes`). \throw Error naming `what`.
  void validate(std::string_view what, bool all_axes = false) const;
  /// Image data with this geometry and no arrays.
  [[nodiscard]] ImageData image() const;
};

/// A grid of cubic voxels of size `voxel_size` whose samples cover `bounds` grown by `padding`
/// on every side (origin at the grown box's minimum, dims rounded up). \throw Error on an empty
/// or non-finite box, voxel_size ≤ 0 or not finite, padding < 0, or more than 2^30 samples
/// along an axis.
[[nodiscard]] GridSpec cubic_grid(const Bounds& bounds, double voxel_size, double padding = 0);

}  // namespace isoforge
