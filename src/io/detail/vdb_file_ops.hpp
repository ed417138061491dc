#pragma once
// The .vdb reading and writing behind read() and write() (io.cpp). In a shared build they live in
// libisoforge_vdb, with the rest of the OpenVDB code, which io loads on the first .vdb file: a
// program that never touches one does not load OpenVDB (whose relocations cost about 70 ms per
// process start). In a static build they are linked in.

#include <cstddef>
#include <filesystem>
#include <string>

#include "isoforge/core/dataset.hpp"

namespace isoforge::io_detail {

struct VdbFileOps {
  /// The float grid `grid` of `path` (the first if empty), densified (at most `max_voxels`).
  ImageData (*read_image)(const std::filesystem::path& path, const std::string& grid,
                          std::size_t max_voxels);
  /// `image` as a grid, its voxels with |value - background| <= `tolerance` inactive.
  void (*write_image)(const ImageData& image, const std::filesystem::path& path, double tolerance);
};

/// The operations, loaded on the first call. \throw Error naming `path` (the file at hand) when
/// libisoforge_vdb cannot be loaded.
[[nodiscard]] const VdbFileOps& vdb_file_ops(const std::filesystem::path& path);

}  // namespace isoforge::io_detail

/// Defined in libisoforge_vdb (io/vdb_file_ops.cpp); looked up by name when loaded.
extern "C" const isoforge::io_detail::VdbFileOps* isoforge_vdb_file_ops();
