#pragma once
/// \file
/// Format-agnostic reading and writing: the format is chosen by the file extension.
///
/// | extension | format | read | write |
/// |---|---|---|---|
/// | .vtk | VTK legacy (ASCII/binary, 1.0–5.1) | all datasets | all datasets |
/// | .vti .vts .vtp .vtu | VTK XML | yes | yes |
/// | .ply | Stanford PLY | polydata | polydata |
/// | .obj | Wavefront OBJ | — | polydata |
/// | .off | Object File Format | polydata | polydata |
/// | .xyz/.bin/.q (with ReadOptions::plot3d_q) | PLOT3D | structured grid | — |
/// | .nhdr .nrrd | NRRD (raw) | image data | — |
/// | .mhd .mha | MetaImage | image data | — |
/// | .vdb | OpenVDB float grid | image data (densified) | image data |
/// | .glb | glTF 2.0 binary | polydata (all meshes appended) | polydata |
/// | .drc | Draco (compressed, quantized) | polydata | polydata: triangles or points |
///
/// See docs/formats.md for the details of each reader and writer.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/gltf.hpp"
#include "isoforge/io/draco.hpp"
#include "isoforge/io/vtk_xml.hpp"

namespace isoforge {

enum class FileFormat {
  VtkLegacy,
  VtkImageData,        ///< .vti
  VtkStructuredGrid,   ///< .vts
  VtkPolyData,         ///< .vtp
  VtkUnstructuredGrid, ///< .vtu
  Ply,
  Obj,
  Off,
  Plot3d,
  Nrrd,
  MetaImage,
  Vdb,
  Glb,  ///< glTF 2.0 binary
  Draco,  ///< .drc
};

/// Format for a path's extension (case-insensitive). \throw Error naming the path when the
/// extension is not recognised.
[[nodiscard]] FileFormat format_from_path(const std::filesystem::path& path);
[[nodiscard]] std::string_view format_name(FileFormat format);

/// Options understood by `read`. Zero/empty values are safe defaults.
struct ReadOptions {
  /// PLOT3D: solution (Q) file to read with an XYZ grid file; empty = grid only.
  std::filesystem::path plot3d_q;
  /// PLOT3D: "auto" detects byte order, iblank and multi-grid from the file size; or
  /// "big"/"little" to force the byte order.
  std::string plot3d_byte_order = "auto";
  /// OpenVDB: name of the grid to read; empty = the first float grid.
  std::string vdb_grid;
  /// OpenVDB: refuse to densify grids with more voxels than this (guards memory).
  std::size_t vdb_max_voxels = std::size_t{1} << 28;
  /// Told the fraction of the file(s) loaded and parsed, about every megabyte (VTK legacy and
  /// XML, PLY, OFF, NRRD, MetaImage, PLOT3D; OpenVDB only at the end); false cancels.
  ProgressCallback progress{};
};

/// Options understood by `write`.
struct WriteOptions {
  bool binary = true;     ///< VTK legacy/XML and PLY: binary (true) or ASCII (false)
  bool compress = true;   ///< VTK XML: compress binary blocks with `xml_compressor`
  VtkXmlCompressor xml_compressor = VtkXmlCompressor::Zlib;  ///< VTK XML: zlib or LZ4
  int xml_level = 0;  ///< VTK XML: compression level (vtk_xml_level_range; 0: the default)
  VtkXmlIdType xml_id_type = VtkXmlIdType::Auto;  ///< VTK XML: type of cell ids and offsets
  /// VTK legacy header version to write: "4.2" (classic cell lists, opens in every VTK) or
  /// "5.1" (OFFSETS/CONNECTIVITY).
  std::string vtk_legacy_version = "4.2";
  /// OpenVDB: voxels with |value - background| <= tolerance become inactive.
  double vdb_tolerance = 0.0;
  /// glTF: how meshes are stored (io/gltf.hpp); the Draco codec uses `draco` below.
  GltfCodec gltf_codec = GltfCodec::Draco;
  /// Draco: quantization or error budget, compression level, method (the stats of the
  /// verifying decode are returned by `write_draco` itself).
  DracoWriteOptions draco{};
  /// Told the fraction written, about every megabyte of values (VTK legacy and XML, PLY; the
  /// other formats only at the end); false cancels (`Cancelled`, the target is not changed).
  ProgressCallback progress{};
};

/// Reads any supported file. \throw Error naming the file and what is wrong; `Cancelled` if
/// `options.progress` returns false.
[[nodiscard]] Dataset read(const std::filesystem::path& path, const ReadOptions& options = {});

/// What a file holds (core/summary.hpp), read in one streaming pass without loading its arrays or
/// its connectivity: VTK XML (arrays in ascii text are parsed whole), VTK legacy (cells listed
/// before the points are read), PLY, OFF, NRRD, MetaImage, PLOT3D (with
/// `options.plot3d_q`) and glTF (one vertex set at a time; Draco-compressed primitives
/// decoded); the other formats are read and summarised. \throw Error as `read` does.
[[nodiscard]] DatasetSummary summarize_file(const std::filesystem::path& path,
                                            const ReadOptions& options = {});

/// Writes `ds` atomically in the format given by the extension. \throw Error if the format
/// cannot hold this dataset type (e.g. an unstructured grid to .ply) or on I/O failure.
void write(DatasetRef ds, const std::filesystem::path& path, const WriteOptions& options = {});

/// Reads a whole file into memory. \throw Error naming the path if it cannot be read.
[[nodiscard]] std::vector<std::byte> read_file_bytes(const std::filesystem::path& path);

}  // namespace isoforge
