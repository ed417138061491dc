// Loading libisoforge_vdb on the first .vdb file (detail/vdb_file_ops.hpp).

#include <string>

#include "detail/vdb_file_ops.hpp"
#include "isoforge/core/plugin.hpp"

namespace isoforge::io_detail {

const VdbFileOps& vdb_file_ops(const std::filesystem::path& path) {
#ifdef ISOFORGE_ONE_LIBRARY
  (void)path;
  return *isoforge_vdb_file_ops();
#else
  using Entry = const VdbFileOps* (*)();
  static const auto entry = reinterpret_cast<Entry>(
      plugin_symbol(ISOFORGE_VDB_LIBRARY, "isoforge_vdb_file_ops", path.c_str()));
  return *entry();
#endif
}

}  // namespace isoforge::io_detail
