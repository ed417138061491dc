#include "isoforge/io/io.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "detail/progress.hpp"
#include "detail/summaries.hpp"
#include "detail/vdb_file_ops.hpp"
#include "isoforge/core/append.hpp"
#include "isoforge/io/draco.hpp"
#include "isoforge/io/gltf.hpp"
#include "isoforge/io/off_obj.hpp"
#include "isoforge/io/plot3d.hpp"
#include "isoforge/io/ply.hpp"
#include "isoforge/io/raw_volume.hpp"
#include "isoforge/io/vtk_legacy.hpp"
#include "isoforge/io/vtk_xml.hpp"

namespace isoforge {

namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

const PolyData& require_poly(DatasetRef ds, const std::filesystem::path& path,
                             std::string_view format) {
  if (const auto* pd = ds.get_if<PolyData>()) return *pd;
  throw Error(path.string() + ": " + std::string(format) + " holds polygonal data only, not " +
              std::string(dataset_type_name(ds)) + " (try .vtk or " +
              std::string(vtk_xml_extension(ds)) + ")");
}

}  // namespace

FileFormat format_from_path(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".vtk") return FileFormat::VtkLegacy;
  if (ext == ".vti") return FileFormat::VtkImageData;
  if (ext == ".vts") return FileFormat::VtkStructuredGrid;
  if (ext == ".vtp") return FileFormat::VtkPolyData;
  if (ext == ".vtu") return FileFormat::VtkUnstructuredGrid;
  if (ext == ".ply") return FileFormat::Ply;
  if (ext == ".obj") return FileFormat::Obj;
  if (ext == ".off") return FileFormat::Off;
  if (ext == ".xyz" || ext == ".bin" || ext == ".p3d" || ext == ".x") return FileFormat::Plot3d;
  if (ext == ".nhdr" || ext == ".nrrd") return FileFormat::Nrrd;
  if (ext == ".mhd" || ext == ".mha") return FileFormat::MetaImage;
  if (ext == ".vdb") return FileFormat::Vdb;
  if (ext == ".glb") return FileFormat::Glb;
  if (ext == ".drc") return FileFormat::Draco;
  throw Error(path.string() + ": unknown file extension '" + ext +
              "' (known: .vtk .vti .vts .vtp .vtu .ply .obj .off .xyz/.bin (PLOT3D) .nhdr .nrrd "
              ".mhd .mha .vdb .drc .glb)");
}

std::string_view format_name(FileFormat format) {
  switch (format) {
    case FileFormat::VtkLegacy: return "VTK legacy";
    case FileFormat::VtkImageData: return "VTK XML image data";
    case FileFormat::VtkStructuredGrid: return "VTK XML structured grid";
    case FileFormat::VtkPolyData: return "VTK XML polydata";
    case FileFormat::VtkUnstructuredGrid: return "VTK XML unstructured grid";
    case FileFormat::Ply: return "PLY";
    case FileFormat::Obj: return "OBJ";
    case FileFormat::Off: return "OFF";
    case FileFormat::Plot3d: return "PLOT3D";
    case FileFormat::Nrrd: return "NRRD";
    case FileFormat::MetaImage: return "MetaImage";
    case FileFormat::Vdb: return "OpenVDB";
    case FileFormat::Glb: return "glTF binary";
    case FileFormat::Draco: return "Draco";
  }
  return "?";
}

namespace io_detail {

std::uint64_t file_size_or_zero(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? 0 : static_cast<std::uint64_t>(size);
}

}  // namespace io_detail

namespace {

Plot3dOptions plot3d_options(const ReadOptions& options) {
  Plot3dOptions p;
  p.progress = options.progress;
  if (options.plot3d_byte_order == "big") {
    p.byte_order = Plot3dByteOrder::Big;
  } else if (options.plot3d_byte_order == "little") {
    p.byte_order = Plot3dByteOrder::Little;
  } else if (options.plot3d_byte_order != "auto") {
    throw Error("plot3d byte order must be auto, big or little, not '" + options.plot3d_byte_order +
                "'");
  }
  return p;
}

}  // namespace

std::vector<std::byte> read_file_bytes(const std::filesystem::path& path) {
  const io_detail::MappedFile file(path);
  return {file.bytes().begin(), file.bytes().end()};
}

DatasetSummary summarize_file(const std::filesystem::path& path, const ReadOptions& options) {
  switch (format_from_path(path)) {
    case FileFormat::VtkImageData:
    case FileFormat::VtkStructuredGrid:
    case FileFormat::VtkPolyData:
    case FileFormat::VtkUnstructuredGrid:
      return io_detail::summarize_vtk_xml(path, options.progress);
    case FileFormat::VtkLegacy:
      return io_detail::summarize_vtk_legacy(path, options.progress);
    case FileFormat::Ply:
      return io_detail::summarize_ply(path, options.progress);
    case FileFormat::Off:
      return io_detail::summarize_off(path, options.progress);
    case FileFormat::Nrrd:
      return io_detail::summarize_raw_volume(path, options.progress, true);
    case FileFormat::MetaImage:
      return io_detail::summarize_raw_volume(path, options.progress, false);
    case FileFormat::Plot3d:
      return io_detail::summarize_plot3d(path, options.plot3d_q, plot3d_options(options));
    case FileFormat::Glb:
      return io_detail::summarize_gltf(path, options.progress);
    default:
      return summarize(read(path, options));
  }
}

Dataset read(const std::filesystem::path& path, const ReadOptions& options) {
  const ProgressCallback& progress = options.progress;
  switch (format_from_path(path)) {
    case FileFormat::VtkLegacy: return read_vtk_legacy(path, progress);
    case FileFormat::VtkImageData:
    case FileFormat::VtkStructuredGrid:
    case FileFormat::VtkPolyData:
    case FileFormat::VtkUnstructuredGrid: return read_vtk_xml(path, progress);
    case FileFormat::Ply: return read_ply(path, progress);
    case FileFormat::Obj:
      throw Error(path.string() + ": reading OBJ is not supported (OBJ is an export format here)");
    case FileFormat::Off: return read_off(path, progress);
    case FileFormat::Plot3d:
      return read_plot3d(path, options.plot3d_q, plot3d_options(options));
    case FileFormat::Draco: return read_draco(path, progress);
    case FileFormat::Nrrd: return read_nrrd(path, progress);
    case FileFormat::MetaImage: return read_metaimage(path, progress);
    case FileFormat::Vdb: {
      ImageData img =
          io_detail::vdb_file_ops(path).read_image(path, options.vdb_grid, options.vdb_max_voxels);
      report_progress(progress, 1.0, "reading");
      return img;
    }
    case FileFormat::Glb: {
      GltfContent content = read_gltf(path);
      std::vector<PolyData> parts;
      for (auto& m : content.meshes) parts.push_back(std::move(m.mesh));
      report_progress(progress, 1.0, "reading");
      return parts.empty() ? PolyData{} : append(std::move(parts));
    }
  }
  throw Error(path.string() + ": unsupported format");
}

void write(DatasetRef ds, const std::filesystem::path& path, const WriteOptions& options) {
  const FileFormat format = format_from_path(path);
  switch (format) {
    case FileFormat::VtkLegacy: {
      VtkLegacyWriteOptions o;
      o.binary = options.binary;
      o.version = options.vtk_legacy_version;
      o.progress = options.progress;
      write_vtk_legacy(ds, path, o);
      return;
    }
    case FileFormat::VtkImageData:
    case FileFormat::VtkStructuredGrid:
    case FileFormat::VtkPolyData:
    case FileFormat::VtkUnstructuredGrid: {
      VtkXmlWriteOptions o;
      o.encoding = options.binary ? VtkXmlEncoding::Appended : VtkXmlEncoding::Ascii;
      o.compress = options.compress;
      o.compressor = options.xml_compressor;
      o.level = options.xml_level;
      o.id_type = options.xml_id_type;
      o.progress = options.progress;
      write_vtk_xml(ds, path, o);
      return;
    }
    case FileFormat::Ply: {
      PlyWriteOptions o;
      o.encoding = options.binary ? PlyEncoding::BinaryLittleEndian : PlyEncoding::Ascii;
      o.progress = options.progress;
      write_ply(require_poly(ds, path, "PLY"), path, o);
      return;
    }
    case FileFormat::Obj:
      write_obj(require_poly(ds, path, "OBJ"), path, options.progress);
      return;
    case FileFormat::Off:
      write_off(require_poly(ds, path, "OFF"), path, options.progress);
      return;
    case FileFormat::Vdb: {
      const auto* img = ds.get_if<ImageData>();
      if (!img) {
        throw Error(path.string() + ": .vdb holds volumes (image data) only, not " +
                    std::string(dataset_type_name(ds)));
      }
      io_detail::vdb_file_ops(path).write_image(*img, path, options.vdb_tolerance);
      if (options.progress) (void)options.progress(1.0);  // done: too late to cancel
      return;
    }
    case FileFormat::Glb: {
      GltfWriteOptions o;
      o.codec = options.gltf_codec;
      o.draco = options.draco;
      o.progress = options.progress;
      (void)write_gltf(require_poly(ds, path, "glTF"), path, o);
      return;
    }
    case FileFormat::Draco: {
      DracoWriteOptions o = options.draco;
      if (options.progress) o.progress = options.progress;
      (void)write_draco(require_poly(ds, path, "Draco"), path, o);
      return;
    }
    case FileFormat::Plot3d:
    case FileFormat::Nrrd:
    case FileFormat::MetaImage:
      throw Error(path.string() + ": writing " + std::string(format_name(format)) +
                  " is not supported (write .vts/.vti or .vtk instead)");
  }
}

}  // namespace isoforge
