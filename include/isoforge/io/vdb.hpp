#pragma once
/// \file
/// OpenVDB `.vdb` files (float grids): validated reading, inspection and atomic writing.
/// Conversion to and from `ImageData` is in sparse/convert.hpp. The one io header that includes
/// OpenVDB.
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

}  // namespace isoforge
