#pragma once
// Private: the formats' streaming summaries behind io::summarize_file (io.cpp). Each parses
// and checks the file's structure as its reader does, streams the arrays it describes through
// ValueRanges piece by piece (io/detail/tuple_stream.hpp) and counts cells without reading
// their connectivity. \throw Error as the readers do.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>

#include "isoforge/core/progress.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/plot3d.hpp"

namespace isoforge::io_detail {

[[nodiscard]] DatasetSummary summarize_vtk_xml(const std::filesystem::path& path,
                                               const ProgressCallback& progress);
/// The same of a file held in memory (`name` for messages; the fuzzers' entry point).
[[nodiscard]] DatasetSummary summarize_vtk_xml(std::span<const std::byte> data,
                                               std::string_view name);

/// VTK legacy: the points and the point, cell and field arrays streamed; cells read.
[[nodiscard]] DatasetSummary summarize_vtk_legacy(const std::filesystem::path& path,
                                                  const ProgressCallback& progress);
[[nodiscard]] DatasetSummary summarize_vtk_legacy(std::span<const std::byte> data,
                                                  std::string_view name);
/// OFF: the vertices' values into ranges a block at a time, the faces counted, not stored.
[[nodiscard]] DatasetSummary summarize_off(const std::filesystem::path& path,
                                           const ProgressCallback& progress);
[[nodiscard]] DatasetSummary summarize_off(std::span<const std::byte> data,
                                           std::string_view name);
/// NRRD (`nrrd`) or MetaImage: the header, then the samples streamed (raw or inflated).
[[nodiscard]] DatasetSummary summarize_raw_volume(const std::filesystem::path& path,
                                                  const ProgressCallback& progress, bool nrrd);

/// PLY: binary files with fixed-size vertex and face records streamed; the others read whole.
[[nodiscard]] DatasetSummary summarize_ply(const std::filesystem::path& path,
                                           const ProgressCallback& progress);
[[nodiscard]] DatasetSummary summarize_ply(std::span<const std::byte> data, std::string_view name);

/// PLOT3D grid (and solution when `q_path` is not empty): the coordinate, IBLANK and solution
/// planes streamed in blocks, the derived velocity and pressure computed per block.
[[nodiscard]] DatasetSummary summarize_plot3d(const std::filesystem::path& xyz_path,
                                              const std::filesystem::path& q_path,
                                              const Plot3dOptions& options);
[[nodiscard]] DatasetSummary summarize_plot3d(std::span<const std::byte> xyz,
                                              std::string_view xyz_name,
                                              std::span<const std::byte> q,
                                              std::string_view q_name,
                                              const Plot3dOptions& options);

/// glTF binary (.glb): the summary of all meshes appended, one vertex set at a time; the cells
/// counted from the index accessors (each index checked), not stored.
[[nodiscard]] DatasetSummary summarize_gltf(const std::filesystem::path& path,
                                            const ProgressCallback& progress);
[[nodiscard]] DatasetSummary summarize_gltf(std::span<const std::byte> data, std::string_view name);

}  // namespace isoforge::io_detail
