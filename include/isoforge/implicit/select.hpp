#pragma once
/// \file
/// Selecting (extracting) the cells of a dataset that lie inside or outside an implicit function
/// (section 1.5.2.2; VTK's vtkExtractGeometry): "a cell lies in a region if all its points lie
/// in the region".

#include "isoforge/core/dataset.hpp"
#include "isoforge/implicit/function.hpp"

namespace isoforge {

struct SelectOptions {
  /// true: keep cells inside (F <= 0 at the points); false: keep cells outside (F > 0).
  bool inside = true;
  /// false: a cell is kept when all its points are in the region; true: when any point is
  /// (the boundary cells are kept too).
  bool any_point = false;
  /// Arrays recording where each output point and cell came from.
  bool original_ids = true;
};

/// Extracts the selected cells of any dataset into an unstructured grid holding only the points
/// those cells use (renumbered, in increasing original id). Point and cell data are carried;
/// with `original_ids` the Int64 arrays "OriginalPointIds" (point data) and "OriginalCellIds"
/// (cell data) are added. Image data yields voxels (pixels in 2D). A point exactly on the
/// surface (F = 0) counts as inside.
[[nodiscard]] UnstructuredGrid extract_cells(DatasetRef input, const ImplicitFunction& f,
                                             const SelectOptions& options = {});

}  // namespace isoforge
