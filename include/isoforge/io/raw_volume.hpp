#pragma once
/// \file
/// Raw volume headers: NRRD (`.nhdr` detached or `.nrrd` attached; raw encoding; data file
/// lists such as `data file: quarter.%d 1 93 1`) and MetaImage (`.mhd` + raw, or `.mha`).
/// The result is `ImageData` with one point array "Scalars" of the file's element type.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

/// Reads a volume; `progress` is told the fraction of the header and data files loaded (about
/// every megabyte). \throw Error naming the header (or data file) and what is wrong;
/// `Cancelled` if `progress` returns false.
[[nodiscard]] ImageData read_nrrd(const std::filesystem::path& path,
                                  const ProgressCallback& progress = {});
/// In-memory header (with attached data for .nrrd); detached data files are looked up in
/// `base_dir`.
[[nodiscard]] ImageData read_nrrd(std::span<const std::byte> data, std::string_view name,
                                  const std::filesystem::path& base_dir);

/// As `read_nrrd`, for MetaImage headers.
[[nodiscard]] ImageData read_metaimage(const std::filesystem::path& path,
                                       const ProgressCallback& progress = {});
[[nodiscard]] ImageData read_metaimage(std::span<const std::byte> data, std::string_view name,
                                       const std::filesystem::path& base_dir);

}  // namespace isoforge
