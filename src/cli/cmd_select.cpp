// isoforge select: extract the cells of a dataset inside (or outside) an implicit function.

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/shrink.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/implicit/select.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_select_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, function, q;
    bool outside = false, boundary = false, no_ids = false;
    double shrink = 1.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("select", "Extract the cells inside (or outside) an implicit "
                                           "function; output is an unstructured grid");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("-f,--function", args->function, "Function expression (see docs/implicit.md)")->required();
  cmd->add_flag("--outside", args->outside, "Keep the cells outside (F > 0) instead of inside (F <= 0)");
  cmd->add_flag("--boundary", args->boundary, "Keep a cell when any point is in the region (default: all)");
  cmd->add_option("--shrink", args->shrink,
                  "Shrink each selected cell toward its centroid by this factor in [0, 1] (1: "
                  "unchanged, 0.5: half size, 0: a point)")
      ->check(number_in(0, 1));
  cmd->add_flag("--no-ids", args->no_ids, "Do not add OriginalPointIds / OriginalCellIds arrays");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output (.vtu or .vtk)")->required();
  cmd->footer(
      "Examples:\n"
      "  isoforge select data/ironProt.vtk -f 'sphere(center=[34,34,34], r=20)' -o ball.vtu\n"
      "  isoforge select data/post.vtk -f 'plane(origin=[0,0,0], normal=[0,0,1])' --outside -o top.vtu\n"
      "  isoforge sample -f 'sphere()' -b -1 1 -1 1 -1 1 -d 16 -o vol.vti\n"
      "  isoforge select vol.vti -f 'union(scale(sphere(),[1,.5,.5]), scale(sphere(),[.5,1,.5]))' \\\n"
      "      --shrink 0.5 -o fig_1_24b.vtu");
  cmd->callback([args, &ctx, q_opt] {
    (void)output_format(args->out, {FileFormat::VtkUnstructuredGrid, FileFormat::VtkLegacy},
                        ".vtu .vtk (an unstructured grid)");
    require_plot3d_input(q_opt, args->in);
    const ImplicitFunction f = parse_function(args->function, "--function");
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    bar.stage("selecting");
    SelectOptions o;
    o.inside = !args->outside;
    o.any_point = args->boundary;
    o.original_ids = !args->no_ids;
    UnstructuredGrid out = extract_cells(ds, f, o);
    if (out.num_cells() == 0) {
      bar.finish();
      const DataArray values = sample_points(f, ds);  // where F lies, to say why
      warn(fmt::format("select: no cell lies {} '{}' ({} at {} its points): {} over the points "
                       "of {}",
                       o.inside ? "inside" : "outside", args->function,
                       o.inside ? "F <= 0" : "F > 0", o.any_point ? "one of" : "all",
                       range_text(values), args->in));
    }
    if (args->shrink != 1.0) out = shrink(out, args->shrink);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} of {} cells, {} points\n", args->out, out.num_cells(),
                 num_cells(ds), out.num_points());
    }
  });
}

}  // namespace isoforge::cli
