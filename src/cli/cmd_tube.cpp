// isoforge tube: capped tubes with normals around the lines of a polydata (streamlines,
// isolines), radius constant or varying with a point array.

#include <fmt/core.h>

#include <chrono>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/tube.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_tube_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, radius_by;
    double radius = 0, max_radius = 0;
    std::int64_t sides = 12;
    std::vector<double> range;
    bool cap = true;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "tube", "Tubes around the lines of a polydata: capped, with normals, radius constant or "
              "by a point array");
  cmd->add_option("input", args->in, "Input polygonal data with lines")->required();
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  cmd->add_option("-r,--radius", args->radius,
                  "Tube radius (data units; the smallest radius with --radius-by)")
      ->required()
      ->check(positive_number());
  cmd->add_option("-n,--sides", args->sides, "Sides of each tube (N >= 3, default 12)")
      ->transform(integer_in(3, 4096));
  auto* by_opt = cmd->add_option("--radius-by", args->radius_by,
                                 "Point array (scalar, or a vector's length) varying the radius "
                                 "from --radius to --max-radius");
  auto* max_opt = cmd->add_option("--max-radius", args->max_radius,
                                  "Radius at the top of the range (default 10 x --radius)")
                      ->check(positive_number());
  auto* range_opt = cmd->add_option("--range", args->range,
                                    "Values mapped to --radius .. --max-radius (MIN MAX; "
                                    "default: the array's range)")
                        ->expected(2)
                        ->check(finite_number());
  cmd->add_flag("--cap,!--no-cap", args->cap, "Close the ends with discs (default on)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "Each polyline becomes one tube; other cells are ignored. Point data goes to the rings,\n"
      "each line's cell data to its triangles.\n"
      "Examples:\n"
      "  isoforge tube data/hello.vtk -r 0.1 -o hello_tubes.vtp\n"
      "  isoforge contour data/bunny.ply -a intensity --range 0.05 0.45 9 -o isolines.vtp\n"
      "  isoforge tube isolines.vtp -r 0.0005 -n 8 --radius-by intensity --max-radius 0.002 "
      "-o isotubes.vtp\n"
      "  isoforge tube data/hello.vtk -r 0.05 -n 3 --no-cap -o hello_prisms.ply");
  cmd->callback([args, &ctx, by_opt, max_opt, range_opt, q_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    require_meaningful(max_opt, by_opt->count() > 0, "applies with --radius-by only");
    require_meaningful(range_opt, by_opt->count() > 0, "applies with --radius-by only");
    const auto range = parse_color_range(args->range, "--range");  // MIN < MAX, finite width
    TubeOptions o;
    o.radius = args->radius;
    o.sides = static_cast<int>(args->sides);
    o.radius_array = args->radius_by;
    o.max_radius = args->max_radius;
    o.scalar_range = range;
    o.capping = args->cap;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const PolyData input =
        read_polydata(args->in, bar, "tube: tubes go around the lines of polygonal data", ro);
    if (input.lines.empty()) {
      throw Error(fmt::format("tube: {} has no lines (it has {} polygons, {} vertices)", args->in,
                              input.polys.size(), input.verts.size()));
    }
    bar.stage("tubing");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    auto [out, stats] = tube(input, o);
    const double ms = elapsed_ms(t0);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr,
                 "wrote {}: {} tubes ({} lines skipped: fewer than 2 distinct points), {} points, "
                 "{} triangles in {:.3f} s; radius {:.4g} .. {:.4g}\n",
                 args->out, stats.tubes, stats.skipped_lines, out.num_points(), out.polys.size(),
                 ms / 1000, stats.min_radius, stats.max_radius);
    }
  });
}

}  // namespace isoforge::cli
