#pragma once
/// \file
/// Warping: points displaced by a vector field or along a direction by a scalar (VTK's
/// vtkWarpVector and vtkWarpScalar), and the displacement plot's scalar (vtkVectorDot).
/// Method: docs/algorithms/attributes.md.

#include <optional>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

struct WarpVectorOptions {
  std::string vectors;  ///< point array of 3 components; empty: the active vectors
  double scale = 1;     ///< finite
  ProgressCallback progress = {};
};

struct WarpScalarOptions {
  std::string scalars;  ///< point array of 1 component; empty: the active scalars
  double scale = 1;     ///< finite
  /// Displace along this direction (normalised; not zero). nullopt: along the point normals.
  std::optional<Vec3> direction = std::nullopt;
  std::string normals;  ///< without `direction`: point array of 3 components; empty: the active
                        ///< normals
  ProgressCallback progress = {};
};

/// The input with each point p moved to p + scale · v(p). Image data becomes a structured grid
/// of the same dimensions; every other type keeps its type and cells. All point, cell and field
/// data is carried. Points are stored as Float32 unless the input's are Float64.
/// \throw Error naming the array when it is missing or has the wrong number of components, or
/// when `scale` is not finite.
[[nodiscard]] Dataset warp_by_vector(DatasetRef input, const WarpVectorOptions& options = {});

/// The input with each point p moved to p + scale · s(p) · n, n the unit `direction` or the
/// point's normal (used as stored). Output types and carried data as `warp_by_vector`.
/// \throw Error as `warp_by_vector`, and on a zero or non-finite direction.
[[nodiscard]] Dataset warp_by_scalar(DatasetRef input, const WarpScalarOptions& options = {});

struct DisplacementOptions {
  std::string vectors;  ///< point array of 3 components; empty: the active vectors
  std::string normals;  ///< point array of 3 components; empty: the active normals
  std::string name = "Displacement";  ///< the output array's name (not empty)
};

/// The displacement plot's scalar: a Float32 point array of v(p) · n(p), the motion of each
/// point along its normal (positive: outward). \throw Error naming a missing array.
[[nodiscard]] DataArray displacement(DatasetRef input, const DisplacementOptions& options = {});

}  // namespace isoforge
