#pragma once
/// \file
/// Exact Euclidean distance fields of polygonal data (section 1.5.3, implicit modeling): the
/// distance from every sample of a regular grid to the nearest generating primitive — vertex
/// (point, optionally a ball of given radius), line segment (lines and polylines), triangle
/// (polygons, fan-triangulated, and strips) — computed up to a maximum distance, into a dense
/// `ImageData` or a sparse OpenVDB narrow band whose memory scales with the band, not the box.
///
/// **Exact.** Every value inside the band is min over all primitives of the exact closest-point
/// distance (closest_point.hpp), evaluated in double precision at the sample's position
/// `GridSpec::coordinate` — never propagated or interpolated from other samples. The dense and
/// sparse results, and the two strategies below, are bit-identical on the band.
///
/// **The band.** A sample is *in the band* when its distance is below `max_distance`. Sparse:
/// exactly the band samples inside the grid's dims are active voxels; every other voxel is
/// inactive with value `max_distance` (the background; with signs, ±`max_distance`). Dense:
/// samples outside the band hold `max_distance` (±`max_distance` when signed).
///
/// **Strategies** (same values, different cost):
/// - *Scatter* (the banded rasterization of vtkImplicitModeller, trimmed): each primitive visits
///   the samples within reach — its bounding box grown by the maximum distance, each row of it cut
///   to the sphere (point), cylinder (segment) or slab (triangle) that can lie within reach — and
///   keeps the minimum. Within a block the nearest primitives come first, and later ones only
///   visit the rows where they can still win (a triangle tests a cheap slab-disc bound before
///   the exact kernel). Cost ~ the sum of the primitives' reach volumes: best for few or large
///   primitives and narrow bands.
/// - *Gather*: every sample of the band asks a bounding volume hierarchy for its nearest
///   primitive (branch and bound, seeded with the previous sample's nearest). Cost ~ band samples
///   × log(primitives): best for many small primitives and wide bands (70k triangles, a band of
///   20 voxels), where reach volumes overlap hundreds of times.
/// `Auto` estimates both costs from the primitives' reach volumes and picks the cheaper.
///
/// Work is split into blocks of samples (8³, the OpenVDB leaf size, for sparse output; 8 x 8 x 64
/// for dense output), processed in parallel (TBB) with no shared writes; the result does not
/// depend on the number of threads. Dense Scatter of points and segments (no triangles, radii or
/// signs) runs by z-planes and rows along x instead: each segment visits its end balls with the
/// point kernel (where its clamped parameter is certainly 0 or 1) and its cylinder with the full
/// kernel, on vectors of 8 samples — the same operations, so the same bits.
///
/// **Signed distance** (closed triangle meshes): the sign is that of (p − q)·n where q is the
/// closest point and n the angle-weighted pseudonormal of the feature (face, edge, vertex) holding
/// it (Bærentzen & Aanæs 2005): negative inside. It is exact for closed, manifold, consistently
/// oriented meshes, which `analyze_topology` checks first (an open, non-manifold or inconsistently
/// oriented mesh is an `Error` naming the problem, unless `require_closed` is false: then the
/// sign is still the pseudonormal test, meaningful near well-oriented patches only). Inward-
/// oriented components (negative enclosed volume) are flipped. Samples beyond the band take the
/// sign of the region they lie in (OpenVDB's signedFloodFill on the sparse grid, a 6-connected
/// flood fill on the dense one), which needs `max_distance` ≥ the largest spacing.

#include <cstddef>
#include <string>

#include <openvdb/openvdb.h>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge {

/// How the band is computed (see the file comment). Results are identical.
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
  std::string name = "Distance";  ///< dense: point array name; sparse: grid name
  ProgressCallback progress;      ///< called with the fraction of blocks done
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

/// The distance field of `input`'s cells on `grid` as a dense image with one point array
/// (`options.name`, Float32 or Float64 by `type`, active scalars). Spacing may differ per axis.
/// \throw Error on an empty input (no cells, or no points), a non-finite point, max_distance not
/// positive and finite, dims < 1 or an invalid grid, a missing/bad radius array, signed distance
/// of lines/verts or of an open, non-manifold or inconsistently oriented mesh (see above).
[[nodiscard]] ImageData distance_image(const PolyData& input, const GridSpec& grid,
                                       const DistanceOptions& options,
                                       ScalarType type = ScalarType::Float32,
                                       DistanceStats* stats = nullptr);

/// The same field as an OpenVDB float grid (voxel (i, j, k) = sample (i, j, k) of `grid`, which
/// must have cubic voxels), named `options.name`: unsigned → GRID_UNKNOWN class with background
/// max_distance; signed → a GRID_LEVEL_SET with background max_distance and inactive values
/// ±background. Only voxels inside the grid's dims are active. Memory ~ the band.
/// \throw Error as `distance_image`, or on unequal spacing.
[[nodiscard]] openvdb::FloatGrid::Ptr distance_grid(const PolyData& input, const GridSpec& grid,
                                                    const DistanceOptions& options,
                                                    DistanceStats* stats = nullptr);

/// A grid of cubic voxels of size `voxel_size` whose samples cover `bounds` grown by `padding`
/// on every side (origin at the grown box's minimum, dims rounded up). \throw Error on an empty
/// or non-finite box, voxel_size ≤ 0 or padding < 0.
[[nodiscard]] GridSpec cubic_grid(const Bounds& bounds, double voxel_size, double padding = 0);

/// OpenVDB's `meshToVolume` on the triangles of `input` (polygons fan-triangulated, strips) on
/// the cubic grid `grid` (origin and voxel size only: the result is not clipped to dims):
/// signed (a level set: needs a closed mesh) or unsigned, with a narrow band of
/// `half_width_voxels` on each side. Fast, exact near the triangles, but the wider band is
/// propagated from neighbouring voxels' closest triangles (an approximation). Provided as the
/// peer of `distance_grid` and as a fast path. \throw Error on an empty or non-finite input,
/// half width < 1 or unequal spacing.
[[nodiscard]] openvdb::FloatGrid::Ptr openvdb_mesh_to_volume(const PolyData& input,
                                                             const GridSpec& grid,
                                                             double half_width_voxels,
                                                             bool signed_distance);

}  // namespace isoforge
