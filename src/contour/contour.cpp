// contour(): the one dispatcher on the dataset type (and, for structured data, on its
// dimension) to the contour kernels of contour_internal.hpp.

#include "isoforge/contour/contour.hpp"

#include <fmt/format.h>

#include "contour_internal.hpp"
#include "contour_output.hpp"

namespace isoforge {

using namespace contour_detail;

namespace {

/// Triangle normals are the normals of a surface; the contour of cells of dimension 1 or 2 is
/// lines or vertices, whose normals would all be zero.
void require_surface_for_triangle_normals(bool gives_surface, const ContourOptions& options,
                                          const char* caller) {
  if (options.normals == ContourNormals::Triangles && !gives_surface) {
    throw Error(
        fmt::format("{}: normals from triangles need a surface, and the contour of this "
                    "input (no 3D cells) is lines or vertices: ask for gradient normals "
                    "or none",
                    caller));
  }
}

/// Image data and structured grids: marching cubes on 3D lattices, marching squares on 2D ones.
template <class Lattice>
ContourResult contour_lattice(const Lattice& input, const ContourOptions& options,
                              const char* caller) {
  input.validate();
  const DataArray& scalars = contour_scalars(input.point_data, options, caller);
  require_surface_for_triangle_normals(structured_dimension(input.dims) == 3, options, caller);
  ContourResult r;
  r.output = structured_dimension(input.dims) == 3
                 ? marching_cubes(input, scalars, options, r.stats)
                 : marching_squares(input, scalars, options, r.stats);
  return r;
}

ContourResult contour_unstructured_grid(const UnstructuredGrid& grid,
                                        const ContourOptions& options) {
  grid.validate();
  const DataArray& scalars = contour_scalars(grid.point_data, options, "contour");
  if (options.normals == ContourNormals::Triangles) {
    bool has_3d = false;
    for (std::size_t c = 0; c < grid.num_cells() && !has_3d; ++c) {
      has_3d = cell_dimension(grid.types[c]) == 3;
    }
    require_surface_for_triangle_normals(has_3d, options, "contour");
  }
  const CellRun run{&grid.cells, &grid.types, CellType::Empty, 0};
  ContourResult r;
  r.output = marching_cells(grid.points, grid.point_data, grid.cell_data,
                            std::span<const CellRun>(&run, 1), scalars, options, r.stats);
  return r;
}

ContourResult contour_polydata(const PolyData& input, const ContourOptions& options) {
  input.validate();
  const DataArray& scalars = contour_scalars(input.point_data, options, "contour");
  require_surface_for_triangle_normals(false, options, "contour");
  const std::size_t nv = input.verts.size(), nl = input.lines.size(), np = input.polys.size();
  const CellRun runs[] = {
      {&input.lines, nullptr, CellType::PolyLine, nv},
      {&input.polys, nullptr, CellType::Polygon, nv + nl},
      {&input.strips, nullptr, CellType::TriangleStrip, nv + nl + np},
  };
  ContourResult r;
  r.output = marching_cells(input.points, input.point_data, input.cell_data, runs, scalars, options,
                            r.stats);
  return r;
}

}  // namespace

ContourResult contour_image(const ImageData& input, const ContourOptions& options) {
  return contour_lattice(input, options, "contour_image");
}

ContourResult contour(DatasetRef input, const ContourOptions& options) {
  if (const auto* img = input.get_if<ImageData>()) return contour_image(*img, options);
  if (const auto* sg = input.get_if<StructuredGrid>())
    return contour_lattice(*sg, options, "contour");
  if (const auto* ug = input.get_if<UnstructuredGrid>())
    return contour_unstructured_grid(*ug, options);
  return contour_polydata(*input.get_if<PolyData>(), options);
}

}  // namespace isoforge
