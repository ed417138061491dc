#pragma once
/// \file
/// PLY (read and write; ASCII, binary little and big endian).
///
/// Vertex properties beyond x, y, z become point arrays: nx/ny/nz → "Normals" (active normals),
/// red/green/blue[/alpha] → "Colors" (uint8, active scalars), u/v or s/t or texture_u/texture_v
/// → "TCoords", anything else → a 1-component array of that name. Scalar face properties beyond
/// the index list become cell arrays the same way; a face list "texcoord" (u v per corner) becomes
/// "TCoords" per point, vertices duplicated where their corners differ (docs/formats.md).

#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

/// Reads a PLY file; `progress` is told the fraction loaded and parsed (about every megabyte).
/// \throw Error naming the file and place; `Cancelled` if `progress` returns false.
[[nodiscard]] PolyData read_ply(const std::filesystem::path& path,
                                const ProgressCallback& progress = {});
/// The same from the bytes of a file; `name` is used in error messages.
[[nodiscard]] PolyData read_ply(std::span<const std::byte> data, std::string_view name);

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };
struct PlyWriteOptions {
  PlyEncoding encoding = PlyEncoding::BinaryLittleEndian;  ///< ASCII or binary (either order)
  /// Told the fraction written (about every megabyte of values); false cancels (`Cancelled`).
  ProgressCallback progress{};
};
/// Writes vertices (with point arrays as properties) and faces (polys; verts/lines/strips are
/// not representable and make it throw unless empty; strips are triangulated).
void write_ply(const PolyData& mesh, const std::filesystem::path& path,
               const PlyWriteOptions& options = {});

}  // namespace isoforge
