#pragma once
// Private: what the dense and sparse implicit modellers share (implicit_modeller.cpp).

#include "isoforge/model/implicit_modeller.hpp"

namespace isoforge::model_detail {

/// \throw Error on an input with no cells or points, or a non-finite point.
void check_modeller_input(const PolyData& input);

/// The distance-field options of the modeller's options, with band `max_distance`.
[[nodiscard]] DistanceOptions modeller_distance_options(const ImplicitModellerOptions& o,
                                                        double max_distance);

}  // namespace isoforge::model_detail
