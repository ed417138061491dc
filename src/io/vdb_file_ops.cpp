// The .vdb operations that read() and write() reach through detail/vdb_file_ops.hpp. Part of
// libisoforge_vdb in a shared build.

#include "detail/vdb_file_ops.hpp"

#include "isoforge/io/vdb.hpp"
#include "isoforge/sparse/convert.hpp"

namespace {

isoforge::ImageData read_image(const std::filesystem::path& path, const std::string& grid,
                               std::size_t max_voxels) {
  return isoforge::vdb_to_image(*isoforge::read_vdb_grid(path, grid), max_voxels);
}

void write_image(const isoforge::ImageData& image, const std::filesystem::path& path,
                 double tolerance) {
  isoforge::ImageToVdbOptions o;
  o.tolerance = static_cast<float>(tolerance);
  isoforge::write_vdb(*isoforge::image_to_vdb(image, o), path);
}

constexpr isoforge::io_detail::VdbFileOps kVdbFileOps{read_image, write_image};

}  // namespace

extern "C" const isoforge::io_detail::VdbFileOps* isoforge_vdb_file_ops() {
  return &kVdbFileOps;
}
