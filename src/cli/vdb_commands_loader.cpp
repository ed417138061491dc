// Loading the module of the OpenVDB commands (vdb_commands.hpp) on first use.

#include <dlfcn.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <string>

#include "isoforge/core/error.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

#ifdef ISOFORGE_VDB_COMMANDS_BUILTIN

const VdbCommands& vdb_commands() {
  return *isoforge_cli_vdb_commands();
}

#else

namespace {

/// The module beside the program (the build tree) or in the library directory of its install
/// prefix (ISOFORGE_VDB_COMMANDS_LIBDIR, relative to the program's directory); nullptr with
/// `why` set if it cannot be loaded.
const VdbCommands* load(std::string& why) {
  constexpr const char* kName = ISOFORGE_VDB_COMMANDS_MODULE;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  void* handle = nullptr;
  std::string tried;
  if (!ec) {
    const std::filesystem::path dir = exe.parent_path();
    for (const auto& candidate :
         {dir / kName, (dir / ISOFORGE_VDB_COMMANDS_LIBDIR / kName).lexically_normal()}) {
      if (!std::filesystem::exists(candidate, ec)) {
        tried += (tried.empty() ? "" : ", ") + candidate.string();
        continue;
      }
      handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        const char* e = dlerror();
        why = e ? e : candidate.string();
        return nullptr;
      }
      break;
    }
  }
  if (!handle) {
    why = std::string(kName) + " not found" + (tried.empty() ? "" : " (looked for " + tried + ")");
    return nullptr;
  }
  using Entry = const VdbCommands* (*)();
  auto* entry = reinterpret_cast<Entry>(dlsym(handle, "isoforge_cli_vdb_commands"));
  if (!entry) {
    why = std::string(kName) + " has no isoforge_cli_vdb_commands";
    return nullptr;
  }
  return entry();
}

}  // namespace

const VdbCommands& vdb_commands() {
  static std::string why;
  static const VdbCommands* const commands = load(why);
  if (!commands) throw Error("cannot load the OpenVDB commands: " + why);
  return *commands;
}

#endif

}  // namespace isoforge::cli
