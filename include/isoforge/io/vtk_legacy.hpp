#pragma once
/// \file
/// VTK legacy `.vtk` files: ASCII and binary (big-endian), header versions 1.0–5.1, all four
/// dataset types (STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID on read (converted to a
/// structured grid), POLYDATA, UNSTRUCTURED_GRID), POINT_DATA/CELL_DATA with SCALARS (+ lookup
/// table name), COLOR_SCALARS, VECTORS, NORMALS, TENSORS, TEXTURE_COORDINATES and FIELD arrays,
/// and dataset-level FIELD data. Version 5.1 cell sections use OFFSETS/CONNECTIVITY.

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

/// Reads a VTK legacy file; `progress` is told the fraction of the file loaded and parsed (about
/// every megabyte). \throw Error naming the file, the line (ASCII) or byte offset (binary) and
/// what is wrong; `Cancelled` if `progress` returns false.
[[nodiscard]] Dataset read_vtk_legacy(const std::filesystem::path& path,
                                      const ProgressCallback& progress = {});
/// Parses VTK legacy data held in memory; `name` is used in error messages.
[[nodiscard]] Dataset read_vtk_legacy(std::span<const std::byte> data, std::string_view name);

struct VtkLegacyWriteOptions {
  bool binary = true;                   ///< BINARY (big-endian) or ASCII
  std::string version = "4.2";          ///< "4.2" (classic cell lists) or "5.1" (OFFSETS/CONNECTIVITY)
  std::string title = "written by isoforge";  ///< header line 2 (newlines are replaced)
  /// Told the fraction written (about every megabyte of values); false cancels (`Cancelled`).
  ProgressCallback progress{};
};

/// Writes atomically. \throw Error on invalid datasets or I/O failure.
void write_vtk_legacy(DatasetRef ds, const std::filesystem::path& path,
                      const VtkLegacyWriteOptions& options = {});
/// Writes to a stream (no atomicity).
void write_vtk_legacy(DatasetRef ds, std::ostream& out, const VtkLegacyWriteOptions& options = {});

}  // namespace isoforge
