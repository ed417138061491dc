#pragma once
/// \file
/// Elevation: a scalar from each point's position along a direction (VTK's vtkElevationFilter),
/// an attribute made from the geometry. Method: docs/algorithms/attributes.md.

#include <array>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

struct ElevationOptions {
  Vec3 low_point{0, 0, 0};   ///< where the elevation is range[0]
  Vec3 high_point{0, 0, 1};  ///< where it is range[1]; must differ from low_point
  std::array<double, 2> range{0, 1};  ///< finite
  /// Clamp the projection to the segment low..high (VTK's behaviour), so values stay in range.
  bool clamp = true;
  std::string name = "Elevation";  ///< the output array's name (not empty)
  ProgressCallback progress = {};
};

/// A Float32 point array, one value per point: range[0] + (range[1] − range[0]) · t with
/// t = (p − low) · (high − low) / |high − low|², clamped to [0, 1] unless `clamp` is false.
/// \throw Error on equal or non-finite points, a non-finite range or an empty name.
[[nodiscard]] DataArray elevation(DatasetRef input, const ElevationOptions& options = {});

}  // namespace isoforge
