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

}  // namespace isoforge::io_detail
