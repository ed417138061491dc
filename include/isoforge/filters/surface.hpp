#pragma once
/// \file
/// Surface extraction: the boundary of a dataset as polygonal data (VTK's vtkGeometryFilter /
/// vtkDataSetSurfaceFilter), so volume meshes can be written as surfaces and exported.
/// Method and measurements: docs/algorithms/threshold.md.

#include <cstddef>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

struct SurfaceOptions {
  bool original_cell_ids = true;    ///< adds cell data "OriginalCellIds" (Int64): the owning cell
  bool original_point_ids = false;  ///< adds point data "OriginalPointIds" (Int64)
  ProgressCallback progress;
};

struct SurfaceStats {
  std::size_t boundary_faces = 0;  ///< faces of 3D cells used by exactly one cell
  std::size_t passed_cells = 0;    ///< 0D, 1D and 2D cells passed through
  std::size_t points = 0;          ///< points of the output
};

using SurfaceResult = Result<PolyData, SurfaceStats>;

/// The faces of 3D cells that belong to exactly one cell (faces matched by their sorted point
/// ids), as polygons oriented outward (the right-hand normal points out of the cell that owns
/// the face), plus every 2D cell as a polygon (a pixel becomes a quad), triangle strips as
/// strips, 1D cells as lines and 0D cells as verts. Output cells run in order of the owning
/// cell, then of the face in VTK's face table; only the used points are kept (renumbered in
/// increasing original id) with their point data; cell data comes from the owning cell. For
/// 3D image data and structured grids the outer faces are enumerated directly (same output as
/// for the grid converted to an unstructured grid). Deterministic for any number of threads.
/// \throw Error if `input` is invalid.
[[nodiscard]] SurfaceResult extract_surface(DatasetRef input, const SurfaceOptions& options = {});

}  // namespace isoforge
