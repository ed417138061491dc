// isoforge info FILE: what a file holds (type, dimensions, counts, bounds, arrays and ranges),
// from summarize_file (io/io.hpp): streamed where the format allows, else read whole.

#include <fmt/core.h>

#include <cmath>
#include <map>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "describe.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

void add_info_command(CLI::App& app, Context& ctx) {
  auto* cmd = app.add_subcommand("info",
                                 "Print what a file holds: dataset type, dimensions, "
                                 "point/cell counts, bounds, arrays with ranges (VTK XML, "
                                 "VTK legacy, PLY, OFF, NRRD, MetaImage, PLOT3D and glTF "
                                 "in one streaming pass without loading their arrays)");
  auto path = std::make_shared<std::string>();
  auto q = std::make_shared<std::string>();
  cmd->add_option("file", *path, "Input file (.vtk .vti .vts .vtp .vtu .ply .off .nhdr .nrrd .mhd "
                                 ".mha .vdb, PLOT3D .bin/.xyz)")
      ->required();
  auto* q_opt = add_q_option(*cmd, *q);
  cmd->footer(
      "Examples:\n"
      "  isoforge info data/fran_cut.vtk\n"
      "  isoforge info data/combxyz.bin --q data/combq.bin\n"
      "  isoforge convert data/HeadMRVolume.mhd head.vdb\n"
      "  isoforge info head.vdb          (lists its grids without densifying them)");
  cmd->callback([path, q, &ctx, q_opt] {
    const std::filesystem::path p(*path);
    const FileFormat format = format_of(*path);
    require_plot3d_input(q_opt, *path);
    if (format == FileFormat::Vdb) {
      vdb_commands().print_info(p);
      return;
    }
    ReadOptions ro;
    ro.plot3d_q = *q;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ro.progress = bar.callback();
    const DatasetSummary summary = summarize_file(*path, ro);
    bar.finish();
    fmt::print("file: {} ({})\n", p.string(), format_name(format));
    fmt::print("{}", describe(summary));
  });
}

}  // namespace isoforge::cli
