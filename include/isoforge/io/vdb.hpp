#pragma once
/// \file
/// OpenVDB `.vdb` files (float grids) and conversion between sparse grids and `ImageData`.
/// This is the one io header that includes OpenVDB.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <openvdb/openvdb.h>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Calls openvdb::initialize() once (thread-safe); every function here does it for you.
void ensure_openvdb_initialized();

/// Reads the float grid named `grid_name` (or the first float grid if empty).
/// \throw Error naming the file if it is not a VDB file, has no such float grid, or is corrupt.
[[nodiscard]] openvdb::FloatGrid::Ptr read_vdb_grid(const std::filesystem::path& path,
                                                    std::string_view grid_name = {});
/// Names and types of all grids in a file (for `isoforge info`).
struct VdbGridInfo {
  std::string name;
  std::string type;             ///< e.g. "float", "vec3s"
  std::string grid_class;       ///< "level set", "fog volume", "unknown"
  openvdb::CoordBBox active_bbox;  ///< index-space bounding box of active voxels
  std::size_t active_voxels = 0;
  double voxel_size = 0;
};
[[nodiscard]] std::vector<VdbGridInfo> inspect_vdb(const std::filesystem::path& path);

/// Writes grids atomically. \throw Error on failure.
void write_vdb(const std::vector<openvdb::GridBase::Ptr>& grids, const std::filesystem::path& path);
void write_vdb(const openvdb::FloatGrid& grid, const std::filesystem::path& path);

/// Densifies the active bounding box of a grid (uniform voxel size required) into image data
/// with point array named after the grid ("Scalars" if unnamed). Inactive voxels take the
/// background value. \throw Error if the box has more than `max_voxels` voxels or the
/// transform is not a uniform scale + translation.
[[nodiscard]] ImageData vdb_to_image(const openvdb::FloatGrid& grid,
                                     std::size_t max_voxels = std::size_t{1} << 28);
/// Converts a scalar point array of image data (active scalars if `array` is empty) to a float
/// grid; values within `tolerance` of `background` stay inactive. Requires equal spacing on all
/// axes. \throw Error otherwise.
[[nodiscard]] openvdb::FloatGrid::Ptr image_to_vdb(const ImageData& image, std::string_view array = {},
                                                   float background = 0.0f, float tolerance = 0.0f);

}  // namespace isoforge
