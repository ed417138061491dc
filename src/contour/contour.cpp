// contour(): dispatch on the dataset type.

#include "isoforge/contour/contour.hpp"

#include "contour_internal.hpp"

namespace isoforge {

PolyData contour(const Dataset& input, const ContourOptions& options, ContourStats* stats) {
  using namespace contour_detail;
  if (const auto* img = std::get_if<ImageData>(&input)) return contour_image(*img, options, stats);
  if (const auto* pd = std::get_if<PolyData>(&input)) return contour_polydata(*pd, options, stats);
  return contour_cells(input, options, stats);
}

}  // namespace isoforge
