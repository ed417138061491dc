#pragma once
/// \file
/// VTK XML files `.vti .vts .vtp .vtu`: ASCII, inline base64 binary and appended (raw or
/// base64) data; compressed blocks (zlib and LZ4 read and written, LZMA read), UInt32 or UInt64
/// headers on read; Int32/Int64 connectivity (written as Int32 when the ids fit); either byte
/// order on read. Blocks are
/// (de)compressed in parallel; docs/algorithms/vtk_xml_io.md has the measurements.

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <span>
#include <string_view>
#include <utility>

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

/// The compressor of binary blocks (each block of 256 KiB is compressed on its own, as VTK does
/// with its 32 KiB blocks).
enum class VtkXmlCompressor {
  Zlib,  ///< vtkZLibDataCompressor: opens in every VTK and ParaView
  Lz4,   ///< vtkLZ4DataCompressor: larger files, several times faster (VTK 8.2 and later)
};

/// The integer type cell connectivity and offsets are written with.
enum class VtkXmlIdType {
  Auto,   ///< Int32 when every id and offset fits, else Int64
  Int32,  ///< Int32, an error when the ids do not fit
  Int64,  ///< Int64 always (VTK's default with 64-bit ids)
};

/// "zlib" or "lz4".
[[nodiscard]] std::string_view vtk_xml_compressor_name(VtkXmlCompressor compressor);
/// The levels a compressor accepts: zlib 1-12 (libdeflate's levels: 1-9 as zlib's, 10-12
/// slower and smaller), LZ4 1-12 (1: LZ4's fast compressor; 2-12: LZ4 HC of that level).
[[nodiscard]] std::pair<int, int> vtk_xml_level_range(VtkXmlCompressor compressor);

struct VtkXmlWriteOptions {
  VtkXmlEncoding encoding = VtkXmlEncoding::Appended;  ///< how the arrays are stored
  bool compress = true;  ///< compress binary blocks with `compressor` (UInt64 headers)
  VtkXmlCompressor compressor = VtkXmlCompressor::Zlib;  ///< when `compress`
  /// Compression level in vtk_xml_level_range(compressor); 0: the default (zlib 5, LZ4 1).
  int level = 0;
  /// Type of the cell connectivity and offsets: Auto writes Int32 when every id and offset fits
  /// (half the bytes; VTK's SetIdTypeToInt32), else Int64.
  VtkXmlIdType id_type = VtkXmlIdType::Auto;
  /// Told the fraction written (about every megabyte of values); false cancels (`Cancelled`).
  ProgressCallback progress{};
};

/// The extension a dataset type is written with (".vti", ".vts", ".vtp", ".vtu").
[[nodiscard]] std::string_view vtk_xml_extension(DatasetRef ds);

/// Writes atomically. \throw Error if the extension does not match the dataset type, the level
/// is out of range, or on I/O failure.
void write_vtk_xml(DatasetRef ds, const std::filesystem::path& path,
                   const VtkXmlWriteOptions& options = {});
/// Writes to a stream (no atomicity, no extension check).
void write_vtk_xml(DatasetRef ds, std::ostream& out, const VtkXmlWriteOptions& options = {});

}  // namespace isoforge
