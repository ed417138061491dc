#include "isoforge/core/plugin.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <string>

#include "isoforge/core/error.hpp"

namespace isoforge {

namespace {

/// The directory of the library holding this function (libisoforge), empty if unknown.
std::filesystem::path own_directory() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&own_directory), &info) == 0 || !info.dli_fname) {
    return {};
  }
  return std::filesystem::path(info.dli_fname).parent_path();
}

}  // namespace

void* plugin_symbol(const char* name, const char* symbol, const char* what) {
  // dlopen returns the same handle for a library already loaded, so no cache is needed.
  void* handle = nullptr;
  if (const auto dir = own_directory(); !dir.empty()) {
    handle = dlopen((dir / name).c_str(), RTLD_NOW | RTLD_GLOBAL);
  }
  if (!handle) handle = dlopen(name, RTLD_NOW | RTLD_GLOBAL);
  if (!handle) {
    const char* e = dlerror();
    throw Error(std::string(what) + ": cannot load " + name + ": " + (e ? e : "not found"));
  }
  void* address = dlsym(handle, symbol);
  if (!address) {
    throw Error(std::string(what) + ": cannot load " + name + ": it has no " + symbol);
  }
  return address;
}

}  // namespace isoforge
