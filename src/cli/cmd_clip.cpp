// isoforge clip: the part of a dataset on one side of an implicit function, cells split.

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/clip.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_clip_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, function, q;
    double value = 0;
    bool inside_out = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("clip", "Keep the part of a dataset where F >= VALUE (or F < VALUE "
                                         "with --inside-out), cells split along F = VALUE; "
                                         "polygonal data stays polygonal, the rest becomes an "
                                         "unstructured grid");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("-f,--function", args->function, "Function expression (see docs/implicit.md)")
      ->required();
  cmd->add_option("-v,--value", args->value, "Clip value (default 0)")->check(finite_number());
  cmd->add_flag("--inside-out", args->inside_out, "Keep F < VALUE (inside) instead of F >= VALUE");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out,
                  "Output: .vtu or .vtk (any input); " + std::string(kSurfaceExtensions) +
                      " for polygonal input")
      ->required();
  cmd->footer(
      "Examples:\n"
      "  isoforge clip data/ironProt.vtk -f 'sphere(center=[34,34,34], r=20)' --inside-out -o ball.vtu\n"
      "  isoforge clip data/combxyz.bin --q data/combq.bin -f 'plane(origin=[8.255,0,29.763], normal=[-0.287,0,0.9579])' -o half.vtu\n"
      "  isoforge clip data/bunny.ply -f 'plane(origin=[0,0.1,0], normal=[0,1,0])' -o top.ply");
  cmd->callback([args, &ctx, q_opt] {
    (void)format_of(args->out);  // a known extension, before reading
    require_plot3d_input(q_opt, args->in);
    const ImplicitFunction f = parse_function(args->function, "--function");
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    const bool poly = std::holds_alternative<PolyData>(ds);
    if (poly) {
      (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    } else {
      (void)output_format(args->out, {FileFormat::VtkUnstructuredGrid, FileFormat::VtkLegacy},
                          ".vtu .vtk (an unstructured grid)");
    }
    bar.stage("clipping");
    ClipOptions o;
    o.value = args->value;
    o.inside_out = args->inside_out;
    o.progress = bar.callback();
    ClipStats stats;
    if (poly) {
      auto r = clip_polydata(std::get<PolyData>(ds), f, o);
      stats = r.stats;
      write_output(r.output, args->out, bar);
    } else {
      auto r = clip(ds, f, o);
      stats = r.stats;
      write_output(r.output, args->out, bar);
    }
    bar.finish();
    if (stats.cells == 0) {
      warn(fmt::format("clip: nothing of {} lies where {} {} {}", args->in, args->function,
                       args->inside_out ? "<" : ">=", args->value));
    }
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} cells ({} of {} input cells kept whole, {} split), {} points\n",
                 args->out, stats.cells, stats.cells_kept, num_cells(ds), stats.cells_split,
                 stats.points);
    }
  });
}

}  // namespace isoforge::cli
