// isoforge normals: consistent, outward polygon order and point/cell normals of a surface, with
// points split along sharp edges.

#include <fmt/core.h>

#include <chrono>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/compute_normals.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_normals_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q;
    double feature_angle = 30;
    bool no_split = false, no_consistency = false, no_auto_orient = false, flip = false,
         no_cell = false, no_point = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "normals", "Point and cell normals of a surface: polygons oriented consistently (outward "
                 "on closed surfaces), points split along sharp edges");
  cmd->add_option("input", args->in, "Input polygonal data")->required();
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  auto* angle_opt = cmd->add_option("-a,--feature-angle", args->feature_angle,
                                    "Edges sharper than this (degrees, 0..180) split their "
                                    "points (default 30)")
                        ->check(number_in(0, 180));
  auto* split_opt = cmd->add_flag("--no-split", args->no_split, "Never split points");
  auto* consistency_opt = cmd->add_flag("--no-consistency", args->no_consistency,
                                        "Keep every polygon's order as it is");
  auto* orient_opt = cmd->add_flag("--no-auto-orient", args->no_auto_orient,
                                   "Do not turn closed surfaces outward (or open ones to their "
                                   "majority order)");
  cmd->add_flag("--flip", args->flip, "Reverse every polygon (and normal) at the end");
  auto* no_cell_opt = cmd->add_flag("--no-cell-normals", args->no_cell, "No cell array 'Normals'");
  auto* no_point_opt =
      cmd->add_flag("--no-point-normals", args->no_point, "No point array 'Normals'");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "Triangle strips become triangles; vertices and lines are kept.\n"
      "Examples:\n"
      "  isoforge normals data/bunny.ply -o bunny_normals.vtp\n"
      "  isoforge normals data/fran_cut.vtk --flip -a 60 -o fran_out.vtp\n"
      "  isoforge normals data/Torso.vtp --no-split --no-cell-normals -o torso_smooth.vtp");
  cmd->callback([args, &ctx, angle_opt, split_opt, consistency_opt, orient_opt, no_cell_opt,
                 no_point_opt, q_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    require_meaningful(angle_opt, split_opt->count() == 0, "means nothing with --no-split");
    require_meaningful(orient_opt, consistency_opt->count() == 0,
                       "means nothing with --no-consistency (orientation needs it)");
    if (no_cell_opt->count() > 0 && no_point_opt->count() > 0) {
      throw UsageError("--no-cell-normals and --no-point-normals together leave no normals");
    }
    NormalsOptions o;
    o.feature_angle = args->feature_angle;
    o.split = !args->no_split;
    o.consistency = !args->no_consistency;
    o.auto_orient = !args->no_auto_orient;
    o.flip = args->flip;
    o.cell_normals = !args->no_cell;
    o.point_normals = !args->no_point;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const PolyData input =
        read_polydata(args->in, bar, "normals: only polygonal data has surface normals", ro);
    if (input.polys.empty() && input.strips.empty()) {
      throw Error(
          fmt::format("normals: {} has no polygons or strips ({} vertices, {} lines): no "
                      "surface to take normals of",
                      args->in, input.verts.size(), input.lines.size()));
    }
    bar.stage("normals");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    auto [out, stats] = compute_normals(input, o);
    const double ms = elapsed_ms(t0);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points ({} added by splitting), {} polygons in {:.3f} s\n",
                 args->out, out.num_points(), stats.split_points, out.polys.size(), ms / 1000);
      fmt::print(stderr,
                 "  {} surfaces ({} closed), {} polygons reversed, {} non-manifold edges, {} "
                 "inconsistent edges\n",
                 stats.surfaces, stats.closed_surfaces, stats.flipped_polygons,
                 stats.non_manifold_edges, stats.inconsistent_edges);
    }
  });
}

}  // namespace isoforge::cli
