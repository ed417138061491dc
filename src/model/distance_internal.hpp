#pragma once
// Internal interface of the distance-field engine (distance.cpp), shared with the implicit
// modeller, which needs its own value for samples beyond the band.

#include "isoforge/model/distance.hpp"

namespace isoforge::model_detail {

/// `distance_image` with samples beyond the band set to `far_value` (−far_value inside when
/// signed) instead of the maximum distance.
[[nodiscard]] ImageData distance_image(const PolyData& input, const GridSpec& grid,
                                       const DistanceOptions& options, ScalarType type,
                                       double far_value, DistanceStats* stats);

}  // namespace isoforge::model_detail
