#pragma once
// Private: the dense distance field with a chosen value beyond the band (distance.cpp), which the
// implicit modeller needs, and the rows along x of points and segments (distance_rows.cpp).

#include <array>
#include <cstddef>
#include <vector>

#include "isoforge/model/distance.hpp"

namespace isoforge::model_detail {

/// `distance_image` with samples beyond the band set to `far_value` (−far_value inside when
/// signed) instead of the maximum distance; adds to `stats`.
[[nodiscard]] ImageData distance_image_far(const PolyData& input, const GridSpec& grid,
                                           const DistanceOptions& options, double far_value,
                                           DistanceStats& stats);

/// What `distance_rows` did.
struct RowStats {
  std::size_t evaluations = 0;  ///< (sample, primitive) pairs evaluated
  std::size_t active = 0;       ///< samples in the band
  std::size_t planes = 0;       ///< z-planes computed
};

/// The dense unsigned distance field of point primitives `centers` and segments on `grid`,
/// written to `out` (x fastest): sqrt of the minimum squared distance where below
/// `max_distance`, else `far`. Values equal the block engine's bit for bit (distance_rows.cpp).
template <class T>
RowStats distance_rows(const std::vector<Vec3>& centers,
                       const std::vector<std::array<Vec3, 2>>& segments, const GridSpec& grid,
                       double max_distance, double far, T* out, const ProgressCallback& progress);

}  // namespace isoforge::model_detail
