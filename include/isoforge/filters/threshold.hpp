#pragma once
/// \file
/// Thresholding: the cells of a dataset whose values of one array lie in a range (VTK's
/// vtkThreshold). Method, modes and measurements: docs/algorithms/threshold.md.

#include <cstddef>
#include <limits>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

/// How a cell is judged from the values of a point array at its points.
enum class ThresholdMode {
  AllPoints,  ///< every point's value is in [lower, upper]
  AnyPoint,   ///< at least one point's value is
  Overlap,    ///< [min, max] of its points' values meets [lower, upper] (VTK's
              ///< UseContinuousCellRange: a cell a continuous field crosses the range in)
};

/// Where the thresholded array is looked up.
enum class ThresholdArrayAssociation {
  Auto,    ///< point data, else cell data
  Points,  ///< point data only
  Cells,   ///< cell data only: a cell passes when its own value is in the range
};

struct ThresholdOptions {
  /// The array to threshold; "" = the active scalars (point data, else cell data).
  std::string array;
  ThresholdArrayAssociation association = ThresholdArrayAssociation::Auto;
  double lower = -std::numeric_limits<double>::infinity();  ///< inclusive, array units
  double upper = std::numeric_limits<double>::infinity();   ///< inclusive, array units
  /// Component of a multi-component array, or -1 for the tuple magnitude (Euclidean norm).
  int component = 0;
  ThresholdMode mode = ThresholdMode::AllPoints;  ///< point arrays only
  /// Adds the Int64 arrays "OriginalPointIds" (point data) and "OriginalCellIds" (cell data).
  bool original_ids = false;
  ProgressCallback progress;
};

struct ThresholdStats {
  std::size_t cells_in = 0;    ///< cells of the input
  std::size_t cells_kept = 0;  ///< cells of the output
  std::size_t points_kept = 0;
  bool point_array = true;  ///< the array was point data (false: cell data)
};

using ThresholdResult = Result<UnstructuredGrid, ThresholdStats>;

/// The cells of `input` whose array values lie in [lower, upper] (by `mode` for a point array),
/// in increasing cell id, with only the points they use (renumbered in increasing original id),
/// every point and cell array carried. A NaN value never lies in the range. Image data keeps
/// its voxels/pixels, structured grids their hexahedra/quads. Deterministic for any number of
/// threads.
/// \throw Error naming the argument when the array is missing (listing the arrays), the
/// component is out of range, lower > upper or either bound is NaN.
[[nodiscard]] ThresholdResult threshold(DatasetRef input, const ThresholdOptions& options = {});

}  // namespace isoforge
