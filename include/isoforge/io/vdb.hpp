#pragma once
/// \file
/// OpenVDB `.vdb` files (float grids) and conversion between sparse grids and `ImageData`.
/// This is the one io header that includes OpenVDB.
///
/// References implemented: the OpenVDB file format as written by OpenVDB 10 (format versions
/// 222-224: header, metadata maps, grid descriptors with offsets, transforms, the 5-4-3 tree's
/// topology and leaf buffers with active-mask, zip and Blosc compression); Museth, "VDB:
/// High-resolution sparse volumes with dynamic topology", ACM TOG 32(3), 2013.
///
/// ## Robustness of the readers
/// Before any byte reaches OpenVDB, the file is walked and checked by isoforge: magic number,
/// format version (222 to 224), every string length, metadata size, grid count, descriptor and
/// grid offset against the bytes that remain, and, for the grid that is read (any standard
/// 5-4-3 tree of float/double/int/vec values), the whole tree: node counts, masks, per-node
/// compression headers and compressed block sizes (including Blosc block headers). Metadata of
/// types whose OpenVDB readers trust internal counts (delayed-load metadata) is dropped. OpenVDB
/// then reads from a bounded in-memory stream that throws at its end. So truncated or corrupt
/// files give an `Error` naming the file and the byte offset instead of a crash or a giant
/// allocation; memory is bounded by the tree OpenVDB builds (at most ~40x the grid's bytes).
/// Residual trust: the contents of Blosc/zlib blocks are checked by those libraries.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <openvdb/openvdb.h>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Calls openvdb::initialize() once (thread-safe); every function here does it for you.
void ensure_openvdb_initialized();

/// Reads the float grid named `grid_name` (or the first float grid if empty). A name matches a
/// grid's name, or `name[N]` the N-th of several grids sharing a name (OpenVDB's convention).
/// \throw Error naming the file if it is not a VDB file, has no such float grid, or is corrupt.
[[nodiscard]] openvdb::FloatGrid::Ptr read_vdb_grid(const std::filesystem::path& path,
                                                    std::string_view grid_name = {});
/// Same, from the bytes of a `.vdb` file (or of an OpenVDB stream, which has no grid offsets);
/// `name` is used in error messages. Used by the fuzzer.
[[nodiscard]] openvdb::FloatGrid::Ptr read_vdb_grid(std::span<const std::byte> data,
                                                    std::string_view name,
                                                    std::string_view grid_name = {});
/// Names and types of all grids in a file (for `isoforge info`).
struct VdbGridInfo {
  std::string name;
  std::string type;                ///< e.g. "float", "vec3s"
  std::string grid_class;          ///< "level set", "fog volume", "unknown"
  openvdb::CoordBBox active_bbox;  ///< index-space bounding box of active voxels
  std::size_t active_voxels = 0;
  double voxel_size = 0;
};
/// Lists the grids of a file from their metadata (the active bbox and count come from the
/// statistics OpenVDB writes; grids without them are read to compute them).
/// \throw Error naming the file if it is not a VDB file or is corrupt.
[[nodiscard]] std::vector<VdbGridInfo> inspect_vdb(const std::filesystem::path& path);

/// Writes grids atomically (to a temporary file beside `path`, renamed over it on success), with
/// OpenVDB's default compression and grid statistics metadata. \throw Error on failure (no
/// grids, a null grid, an OpenVDB or I/O error); `path` is then left unchanged.
void write_vdb(const std::vector<openvdb::GridBase::Ptr>& grids, const std::filesystem::path& path);
void write_vdb(const openvdb::FloatGrid& grid, const std::filesystem::path& path);

/// The uniform-scale transform of isoforge's grids: voxel (i, j, k) at origin + (i, j, k) *
/// voxel_size. \throw Error naming `what` if OpenVDB cannot represent it: a voxel size not
/// positive and finite, or so small that OpenVDB's transforms reject the scale (below about
/// 1e-5: its determinant must exceed 1e-15), or a non-finite origin.
[[nodiscard]] openvdb::math::Transform::Ptr vdb_transform(double voxel_size, const Vec3& origin,
                                                          std::string_view what);

/// Densifies the active bounding box of a grid (uniform voxel size required) into image data
/// with point array named after the grid ("Scalars" if unnamed), float32, set as the active
/// scalars. Voxel (i, j, k) is centred at world i * voxel size + translation, so the image's
/// origin is the world position of the bbox's min corner voxel and its spacing the voxel size.
/// Inactive voxels take the background value. \throw Error if the grid has no active voxels,
/// the box has more than `max_voxels` voxels or the transform is not a uniform scale +
/// translation.
[[nodiscard]] ImageData vdb_to_image(const openvdb::FloatGrid& grid,
                                     std::size_t max_voxels = std::size_t{1} << 28);
/// Converts a scalar point array of image data (active scalars if `array` is empty) to a float
/// grid; values within `tolerance` of `background` (|v - background| <= tolerance) stay inactive
/// and are pruned. Point (i, j, k) becomes voxel (i, j, k); the transform is a uniform scale by
/// the spacing plus a translation by the origin. The grid is named after the array; its class
/// stays GRID_UNKNOWN (set it yourself for a level set or fog volume). Requires equal positive
/// spacing on all axes (to 1e-9 relative). \throw Error otherwise, or if the array is missing or
/// has more than one component, or background/tolerance are not finite (tolerance >= 0).
[[nodiscard]] openvdb::FloatGrid::Ptr image_to_vdb(const ImageData& image,
                                                   std::string_view array = {},
                                                   float background = 0.0f, float tolerance = 0.0f);

}  // namespace isoforge
