#pragma once
/// \file
/// Exact distance fields in OpenVDB narrow bands, whose memory scales with the band, not the
/// box (the sparse form of distance.hpp; the same values bit for bit), and OpenVDB's own
/// `meshToVolume` as their peer. Methods: docs/algorithms/implicit_modeling.md.

#include <openvdb/openvdb.h>

#include "isoforge/model/distance.hpp"

namespace isoforge {

using DistanceGridResult = Result<openvdb::FloatGrid::Ptr, DistanceStats>;

/// The same field as an OpenVDB float grid (voxel (i, j, k) = sample (i, j, k) of `grid`, which
/// must have cubic voxels), named `options.name`: unsigned → GRID_UNKNOWN class with background
/// max_distance; signed → a GRID_LEVEL_SET with background max_distance and inactive values
/// ±background. Only voxels inside the grid's dims are active. Memory ~ the band.
/// \throw Error as `distance_image`, or on unequal spacing.
[[nodiscard]] DistanceGridResult distance_grid(const PolyData& input, const GridSpec& grid,
                                               const DistanceOptions& options);

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
