// contour(): dispatch on the dataset type.

#include "isoforge/contour/contour.hpp"

#include "contour_internal.hpp"

namespace isoforge {

PolyData contour(DatasetRef input, const ContourOptions& options, ContourStats* stats) {
  using namespace contour_detail;
  if (const auto* img = input.get_if<ImageData>()) return contour_image(*img, options, stats);
  if (const auto* pd = input.get_if<PolyData>()) return contour_polydata(*pd, options, stats);
  return contour_cells(input, options, stats);
}

}  // namespace isoforge
