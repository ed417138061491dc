// The isoforge command: one subcommand per algorithm (CLI11).

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "isoforge/core/error.hpp"
#include "isoforge/version.hpp"

int main(int argc, char** argv) {
  using namespace isoforge::cli;
#if defined(__x86_64__)
  if (!__builtin_cpu_supports("popcnt") || !__builtin_cpu_supports("sse4.2")) {
    fmt::print(stderr, "isoforge: error: this build needs an x86-64-v2 CPU (POPCNT, SSE4.2); "
                       "rebuild with -DISOFORGE_X86_64_V2=OFF\n");
    return 1;
  }
#endif
  CLI::App app{
      "isoforge: scientific visualization algorithms (contouring, implicit modeling, cutting,\n"
      "probing, decimation) on VTK, PLY, PLOT3D, NRRD and OpenVDB data.\n"
      "Run 'isoforge SUBCOMMAND --help' for the options and examples of each subcommand.",
      "isoforge"};
  app.set_version_flag("--version", std::string(isoforge::kVersion));
  app.require_subcommand(1);
  Context ctx;
  app.add_flag("-q,--quiet", ctx.quiet, "No progress bar or informational messages on stderr");
  add_info_command(app, ctx);
  add_convert_command(app, ctx);
  add_sample_command(app, ctx);
  add_select_command(app, ctx);
  add_contour_command(app, ctx);
  add_distance_command(app, ctx);
  add_offset_command(app, ctx);
  add_csg_command(app, ctx);
  add_attractor_command(app, ctx);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const isoforge::Error& e) {
    fmt::print(stderr, "isoforge: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "isoforge: internal error: {}\n", e.what());
    return 2;
  }
  return 0;
}
