// Loading the module of the OpenVDB commands (vdb_commands.hpp) on first use: installed beside
// libisoforge (the library directory, installed and in the build tree), where core/plugin.hpp looks.

#include "isoforge/core/plugin.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

const VdbCommands& vdb_commands() {
#ifdef ISOFORGE_VDB_COMMANDS_BUILTIN
  return *isoforge_cli_vdb_commands();
#else
  using Entry = const VdbCommands* (*)();
  static const auto entry = reinterpret_cast<Entry>(plugin_symbol(
      ISOFORGE_VDB_COMMANDS_MODULE, "isoforge_cli_vdb_commands", "the OpenVDB commands"));
  return *entry();
#endif
}

}  // namespace isoforge::cli
