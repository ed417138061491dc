// Loading libisoforge_vdb on the first .vdb file (detail/vdb_file_ops.hpp).

#include <dlfcn.h>

#include <string>

#include "detail/vdb_file_ops.hpp"
#include "isoforge/core/error.hpp"

namespace isoforge::io_detail {

#ifdef ISOFORGE_VDB_BUILTIN

const VdbFileOps& vdb_file_ops(const std::filesystem::path&) {
  return *isoforge_vdb_file_ops();
}

#else

namespace {

/// The directory of the library holding this function (libisoforge), empty if unknown.
std::filesystem::path own_directory() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&own_directory), &info) == 0 || !info.dli_fname) {
    return {};
  }
  return std::filesystem::path(info.dli_fname).parent_path();
}

/// libisoforge_vdb beside libisoforge (the layout of the build tree and of an install), else
/// wherever the loader finds it; nullptr with `why` set if neither loads.
const VdbFileOps* load(std::string& why) {
  constexpr const char* kName = ISOFORGE_VDB_LIBRARY;
  void* handle = nullptr;
  if (const auto dir = own_directory(); !dir.empty()) {
    handle = dlopen((dir / kName).c_str(), RTLD_NOW | RTLD_GLOBAL);
  }
  if (!handle) handle = dlopen(kName, RTLD_NOW | RTLD_GLOBAL);
  if (!handle) {
    const char* e = dlerror();
    why = e ? e : kName;
    return nullptr;
  }
  using Entry = const VdbFileOps* (*)();
  auto* entry = reinterpret_cast<Entry>(dlsym(handle, "isoforge_vdb_file_ops"));
  if (!entry) {
    why = std::string(kName) + " has no isoforge_vdb_file_ops";
    return nullptr;
  }
  return entry();
}

}  // namespace

const VdbFileOps& vdb_file_ops(const std::filesystem::path& path) {
  static std::string why;
  static const VdbFileOps* const ops = load(why);
  if (!ops) throw Error(path.string() + ": cannot load OpenVDB support (" + why + ")");
  return *ops;
}

#endif

}  // namespace isoforge::io_detail
