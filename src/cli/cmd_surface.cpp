// isoforge surface: the boundary surface of a dataset as polygonal data (vtkGeometryFilter).

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/surface.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_surface_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q;
    bool no_ids = false, point_ids = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "surface", "Extract the boundary surface: faces of 3D cells used by one cell, plus every "
                 "2D, 1D and 0D cell; output is polygonal data");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_flag("--no-ids", args->no_ids, "Do not add the OriginalCellIds cell array");
  cmd->add_flag("--point-ids", args->point_ids, "Add the OriginalPointIds point array");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  cmd->footer(
      "Faces point out of their cells. Point data is carried; cell data comes from the owning cell.\n"
      "Examples:\n"
      "  isoforge surface data/post.vtk -o post.vtp\n"
      "  isoforge surface data/blow.vtk -o blow.ply\n"
      "  isoforge surface data/combxyz.bin --q data/combq.bin --point-ids -o combustor.vtp\n"
      "  isoforge surface data/ironProt.vtk --no-ids -o box.obj");
  cmd->callback([args, &ctx, q_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    bar.stage("surface");
    SurfaceOptions o;
    o.original_cell_ids = !args->no_ids;
    o.original_point_ids = args->point_ids;
    o.progress = bar.callback();
    auto [out, stats] = extract_surface(ds, o);
    if (out.num_cells() == 0) {
      bar.finish();
      warn(fmt::format("surface: {} has no cells ({} points)", args->in, num_points(ds)));
    }
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr,
                 "wrote {}: {} boundary faces of 3D cells, {} other cells passed, {} points "
                 "(of {} cells, {} points)\n",
                 args->out, stats.boundary_faces, stats.passed_cells, stats.points, num_cells(ds),
                 num_points(ds));
    }
  });
}

}  // namespace isoforge::cli
