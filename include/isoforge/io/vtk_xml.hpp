#pragma once
/// \file
/// VTK XML files `.vti .vts .vtp .vtu`: ASCII, inline base64 binary and appended (raw or
/// base64) data; zlib-compressed blocks with UInt32 or UInt64 headers on read; Int32/Int64
/// connectivity; either byte order on read.

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <span>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

/// Reads a VTK XML file; the dataset type comes from the `VTKFile type=` attribute. `progress`
/// is told the fraction of the file loaded and decoded (about every megabyte).
/// \throw Error naming the file and what is wrong; `Cancelled` if `progress` returns false.
[[nodiscard]] Dataset read_vtk_xml(const std::filesystem::path& path,
                                   const ProgressCallback& progress = {});
/// Parses VTK XML held in memory; `name` is used in error messages.
[[nodiscard]] Dataset read_vtk_xml(std::span<const std::byte> data, std::string_view name);

enum class VtkXmlEncoding {
  Ascii,     ///< text values
  Base64,    ///< inline base64 binary in each DataArray
  Appended,  ///< raw binary in one <AppendedData> block (smallest, fastest)
};

struct VtkXmlWriteOptions {
  VtkXmlEncoding encoding = VtkXmlEncoding::Appended;  ///< how the arrays are stored
  bool compress = true;  ///< zlib-compress binary blocks (vtkZLibDataCompressor, UInt64 headers)
  /// Told the fraction written (about every megabyte of values); false cancels (`Cancelled`).
  ProgressCallback progress{};
};

/// The extension a dataset type is written with (".vti", ".vts", ".vtp", ".vtu").
[[nodiscard]] std::string_view vtk_xml_extension(DatasetRef ds);

/// Writes atomically. \throw Error if the extension does not match the dataset type, or on
/// I/O failure.
void write_vtk_xml(DatasetRef ds, const std::filesystem::path& path,
                   const VtkXmlWriteOptions& options = {});
/// Writes to a stream (no atomicity, no extension check).
void write_vtk_xml(DatasetRef ds, std::ostream& out, const VtkXmlWriteOptions& options = {});

}  // namespace isoforge
