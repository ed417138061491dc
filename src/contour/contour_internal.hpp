#pragma once
// Private: the contour kernels `contour()` dispatches to (contour.cpp), one per kind of input.
// Each takes a validated input and its scalar array (contour_scalars), contours every isovalue
// of the options (contour_each_value) and adds to `stats`.

#include <cstddef>
#include <span>
#include <vector>

#include "isoforge/contour/contour.hpp"

namespace isoforge::contour_detail {

/// Marching cubes on a 3D image: the lattice kernel (marching_cubes.hpp) with the regular
/// grid's geometry (marching_cubes.cpp).
[[nodiscard]] PolyData marching_cubes(const ImageData& image, const DataArray& scalars,
                                      const ContourOptions& options, ContourStats& stats);
/// Marching cubes on a structured grid with three dimensions > 1: the lattice kernel with the
/// grid's own points (marching_cubes.cpp).
[[nodiscard]] PolyData marching_cubes(const StructuredGrid& grid, const DataArray& scalars,
                                      const ContourOptions& options, ContourStats& stats);

/// Marching squares on an image with at most two dimensions > 1: polylines (one dimension:
/// vertices) (marching_squares.cpp).
[[nodiscard]] PolyData marching_squares(const ImageData& image, const DataArray& scalars,
                                        const ContourOptions& options, ContourStats& stats);
/// The same on a structured grid, with quads in the grid's own points (marching_squares.cpp).
[[nodiscard]] PolyData marching_squares(const StructuredGrid& grid, const DataArray& scalars,
                                        const ContourOptions& options, ContourStats& stats);

/// A run of cells of an unstructured grid or polygonal data: `cells` with one type each
/// (`types`) or all of kind `kind` (`types` null; Polygon means triangle/quad/polygon by size,
/// PolyLine means line/polyline); cell c of the run is input cell `first_cell + c`.
struct CellRun {
  const CellArray* cells = nullptr;
  const std::vector<CellType>* types = nullptr;
  CellType kind = CellType::Empty;
  std::size_t first_cell = 0;
};

/// Marching cells on any list of linear cells sharing `points` (marching_cells.cpp): 3D cells
/// give triangles, 2D cells polylines, 1D cells vertices; points merged by global edge
/// (min id, max id) and numbered in order of first use.
[[nodiscard]] PolyData marching_cells(const Points& points, const Attributes& point_data,
                                      const Attributes& cell_data, std::span<const CellRun> runs,
                                      const DataArray& scalars, const ContourOptions& options,
                                      ContourStats& stats);

}  // namespace isoforge::contour_detail
