#pragma once
/// \file
/// Carrying attributes to the output of an algorithm that makes new points along edges or
/// inside cells (contouring, cutting, clipping, probing, decimation): every point array is
/// interpolated as weighted sums of input tuples, every cell array copied from a source cell.

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "isoforge/core/attributes.hpp"

namespace isoforge {

/// Output point and cell arrays with the names, types, components, lookup tables and active
/// roles of the input's, sized for `points` and `cells` output tuples and filled by the calls
/// below. Integer arrays are rounded to the nearest value, halves away from zero (as VTK).
/// Calls writing distinct output indices may run concurrently. A default-constructed interpolator
/// carries nothing (every call is a no-op), for algorithms asked not to carry attributes.
class AttributeInterpolator {
 public:
  /// A weighted input tuple: (input id, weight).
  using Term = std::pair<std::size_t, double>;

  AttributeInterpolator() = default;
  /// Keeps references to `point_data` and `cell_data`, which must outlive the interpolator.
  AttributeInterpolator(const Attributes& point_data, const Attributes& cell_data,
                        std::size_t points, std::size_t cells);

  /// Output point `out` = (1 − t) input point a + t input point b, for every point array.
  void interpolate(std::size_t out, std::size_t a, std::size_t b, double t) const;
  /// Output point `out` = Σ weight × input point over `terms`, for every point array.
  void combine(std::size_t out, std::span<const Term> terms) const;
  /// Output point `out` = input point `in` exactly (no rounding through double).
  void copy_point(std::size_t out, std::size_t in) const;
  /// Output cell `out` = input cell `in` for every cell array.
  void copy_cell(std::size_t out, std::size_t in) const;

  [[nodiscard]] bool has_point_arrays() const { return !points_.empty(); }
  [[nodiscard]] bool has_cell_arrays() const { return !cells_.empty(); }

  /// Moves the filled arrays (with their roles) into an output's attributes.
  void move_into(Attributes& point_data, Attributes& cell_data);

 private:
  using CombineFn = void (*)(const DataArray&, DataArray&, std::size_t, std::span<const Term>);
  const Attributes* src_points_ = nullptr;
  const Attributes* src_cells_ = nullptr;
  Attributes points_, cells_;
  std::vector<CombineFn> combine_;
};

}  // namespace isoforge
