#pragma once
/// \file
/// Exact Euclidean distance fields of polygonal data (section 1.5.3, implicit modeling): the
/// distance from every sample of a regular grid to the nearest vertex (optionally a ball),
/// line segment or triangle, up to a maximum distance, into a dense `ImageData`. Every value in
/// the band is the exact minimum over all primitives (core/closest_point.hpp), never propagated;
/// the strategies and the sparse form (distance_sparse.hpp) agree bit for bit. Deterministic
/// for any thread count. Methods, strategies and signs: docs/algorithms/implicit_modeling.md.

#include <cstddef>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

/// How the band is computed (docs/algorithms/implicit_modeling.md). Results are identical.
enum class DistanceStrategy {
  Auto,     ///< the cheaper of the two by an estimate from the primitives' reach volumes
  Scatter,  ///< per primitive: the samples within reach
  Gather,   ///< per sample: nearest primitive through a bounding volume hierarchy
};

struct DistanceOptions {
  double max_distance = 0;  ///< band half width in world units (> 0): samples closer are computed
  bool signed_distance = false;  ///< negative inside (closed triangle meshes only)
  bool require_closed = true;    ///< signed: an open/non-manifold/misoriented mesh is an Error
  /// Vertex cells become balls: the name of a 1-component point-data array of radii (≥ 0); the
  /// distance to a ball is |p − center| − radius (negative inside it). "" = plain points.
  std::string radius_array;
  DistanceStrategy strategy = DistanceStrategy::Auto;
  std::string name = "Distance";          ///< dense: point array name; sparse: grid name
  ScalarType type = ScalarType::Float32;  ///< dense values: Float32 or Float64
  ProgressCallback progress;              ///< fraction of blocks done; false cancels
};

struct DistanceStats {
  std::size_t points = 0;     ///< vertex primitives
  std::size_t segments = 0;   ///< line segments
  std::size_t triangles = 0;  ///< triangles (polygons fan-triangulated, strips)
  DistanceStrategy strategy = DistanceStrategy::Auto;  ///< the strategy used
  std::size_t blocks = 0;  ///< sample blocks computed (8³ sparse, 8 x 8 x 64 dense; z-planes
                           ///< for dense points and segments)
  std::size_t active_voxels = 0;  ///< samples in the band
  std::size_t evaluations = 0;    ///< (sample, primitive) pairs examined (kernel or cheaper bound)
  double scatter_estimate = 0;    ///< estimated kernel calls of Scatter (the reach volumes)
  std::size_t memory_bytes = 0;   ///< sparse: the tree's memory use
};

using DistanceImageResult = Result<ImageData, DistanceStats>;

/// The distance field of `input`'s cells on `grid` as a dense image with one point array
/// (`options.name`, of `options.type`, active scalars). Samples beyond the band hold
/// max_distance (± with signs; signs beyond the band by a 6-connected flood fill, which needs
/// max_distance ≥ the largest spacing). Spacing may differ per axis.
/// \throw Error on an empty input (no cells, or no points), a non-finite point, max_distance not
/// positive and finite, an invalid grid, a missing/bad radius array, an output type other than
/// Float32/Float64, signed distance of lines/verts or of an open, non-manifold or inconsistently
/// oriented mesh (unless `require_closed` is false).
[[nodiscard]] DistanceImageResult distance_image(const PolyData& input, const GridSpec& grid,
                                                 const DistanceOptions& options);

}  // namespace isoforge
