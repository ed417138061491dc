// contour_image(): marching cubes on 3D image data (the lattice kernel in lattice.hpp with the
// regular-grid geometry); 2D images go to marching squares (contour_lines.cpp).

#include "isoforge/contour/contour.hpp"
#include "lattice.hpp"

namespace isoforge {

PolyData contour_image(const ImageData& input, const ContourOptions& options, ContourStats* stats) {
  using namespace contour_detail;
  input.validate();
  const DataArray& scalars = contour_scalars(input.point_data, options, "contour_image");
  if (structured_dimension(input.dims) < 3) return contour_image_2d(input, options, stats);
  return contour_lattice(ImageGeometry(input), input.dims, scalars, input.point_data, input.cell_data,
                         options, stats);
}

}  // namespace isoforge
