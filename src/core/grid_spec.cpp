// Regular sample grids (core/grid_spec.hpp).

#include "isoforge/core/grid_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace isoforge {

GridSpec GridSpec::from_bounds(const Bounds& bounds, const Dims& dims) {
  (void)checked_point_count(dims, "grid dims");
  if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max)) {
    throw Error("grid bounds: the box is empty or not finite");
  }
  GridSpec g;
  g.dims = dims;
  g.origin = bounds.min;
  for (int a = 0; a < 3; ++a) {
    const double extent = bounds.max[a] - bounds.min[a];
    if (dims[a] > 1) {
      if (!(extent > 0)) {
        throw Error(fmt::format("grid bounds: axis {} has zero extent but {} samples", a, dims[a]));
      }
      g.spacing[a] = extent / static_cast<double>(dims[a] - 1);
    } else {
      g.spacing[a] = extent > 0 ? extent : 1.0;
    }
  }
  return g;
}

void GridSpec::validate(std::string_view what, bool all_axes) const {
  (void)checked_point_count(dims, what);
  if (!is_finite(origin)) throw Error(fmt::format("{}: the grid origin is not finite", what));
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(spacing[a]) || ((all_axes || dims[a] > 1) && !(spacing[a] > 0))) {
      throw Error(fmt::format("{}: spacing along axis {} is {:g}, must be positive and finite",
                              what, a, spacing[a]));
    }
  }
}

ImageData GridSpec::image() const {
  ImageData img;
  img.dims = dims;
  img.origin = origin;
  img.spacing = spacing;
  return img;
}

GridSpec cubic_grid(const Bounds& bounds, double voxel_size, double padding) {
  if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max)) {
    throw Error("cubic grid: the box is empty or not finite");
  }
  if (!(voxel_size > 0) || !std::isfinite(voxel_size)) {
    throw Error(
        fmt::format("cubic grid: voxel size must be positive and finite, got {:g}", voxel_size));
  }
  if (!(padding >= 0) || !std::isfinite(padding)) {
    throw Error(fmt::format("cubic grid: padding must be finite and >= 0, got {:g}", padding));
  }
  GridSpec g;
  g.spacing = {voxel_size, voxel_size, voxel_size};
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = bounds.min[a] - padding;
    const double n = std::ceil((bounds.max[a] + padding - g.origin[a]) / voxel_size - 1e-9) + 1;
    if (!(n <= static_cast<double>(Index{1} << 30))) {
      throw Error(fmt::format("cubic grid: more than 2^30 voxels along axis {}", a));
    }
    g.dims[a] = std::max<Index>(1, static_cast<Index>(n));
  }
  return g;
}

}  // namespace isoforge
