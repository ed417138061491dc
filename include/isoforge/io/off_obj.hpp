#pragma once
/// \file
/// OFF (read and write) and Wavefront OBJ (write).

#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

/// Reads an OFF file; `progress` is told the fraction loaded and parsed (about every megabyte).
/// \throw Error naming the file and place; `Cancelled` if `progress` returns false.
[[nodiscard]] PolyData read_off(const std::filesystem::path& path,
                                const ProgressCallback& progress = {});
/// The same from the bytes of a file; `name` is used in error messages.
[[nodiscard]] PolyData read_off(std::span<const std::byte> data, std::string_view name);
/// Writes OFF (points and polys; strips triangulated); `progress` is told the fraction written.
/// \throw Error if there are lines or verts; `Cancelled` if `progress` returns false (the
/// target is then unchanged).
void write_off(const PolyData& mesh, const std::filesystem::path& path,
               const ProgressCallback& progress = {});

/// Writes Wavefront OBJ: v (points), vn (active normals), vt (active tcoords), f (polys and
/// triangulated strips), l (lines), p (verts); `progress` and cancelling as for write_off.
void write_obj(const PolyData& mesh, const std::filesystem::path& path,
               const ProgressCallback& progress = {});

}  // namespace isoforge
