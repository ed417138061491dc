#pragma once
/// \file
/// Conversion between OpenVDB float grids and `ImageData`.

#include <cstddef>
#include <string>

#include <openvdb/openvdb.h>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Densifies the active bounding box of a grid (uniform voxel size required) into image data
/// with a Float32 point array named after the grid ("Scalars" if unnamed), set as the active
/// scalars. Voxel (i, j, k) is at world translation + (i, j, k) * voxel size, so the image's
/// origin is the world position of the box's min corner voxel and its spacing the voxel size.
/// Inactive voxels take the background value. \throw Error if the grid has no active voxels,
/// the box has more than `max_voxels` voxels or the transform is not a uniform scale +
/// translation.
[[nodiscard]] ImageData vdb_to_image(const openvdb::FloatGrid& grid,
                                     std::size_t max_voxels = std::size_t{1} << 28);

struct ImageToVdbOptions {
  std::string array;        ///< point array to convert; "" = the active scalars
  float background = 0.0f;  ///< the grid's background value (finite)
  float tolerance = 0.0f;   ///< values within this of the background stay inactive (≥ 0)
};

/// Converts a scalar point array of image data to a float grid; values within `tolerance` of
/// `background` (|v − background| ≤ tolerance) stay inactive and are pruned. Point (i, j, k)
/// becomes voxel (i, j, k); the transform is a uniform scale by the spacing plus a translation
/// by the origin. The grid is named after the array; its class stays GRID_UNKNOWN (set it
/// yourself for a level set or fog volume). Requires equal positive spacing on all axes (to
/// 1e-9 relative). \throw Error otherwise, or if the array is missing or has more than one
/// component, or background/tolerance are not finite (tolerance ≥ 0).
[[nodiscard]] openvdb::FloatGrid::Ptr image_to_vdb(const ImageData& image,
                                                   const ImageToVdbOptions& options = {});

}  // namespace isoforge
