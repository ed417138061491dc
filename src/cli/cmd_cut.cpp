// isoforge cut: the surfaces (or lines, or points) where an implicit function takes given values.

#include <fmt/core.h>

#include <cmath>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/cut.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {
// --range N: more cut values than this cannot be told apart (and each costs a pass of work).
constexpr std::int64_t kMaxCutValues = 1'000'000;

/// The function of "--plane OX OY OZ NX NY NZ" or "-f EXPRESSION" (exactly one of them).
ImplicitFunction cut_function(const std::vector<double>& plane, const CLI::Option* plane_opt,
                              const std::string& expression, const CLI::Option* f_opt) {
  exclude_each_other({plane_opt, f_opt});
  if (f_opt->count() > 0) return parse_function(expression, "--function");
  if (plane_opt->count() == 0) throw UsageError("give the cut function: --plane ORIGIN NORMAL or -f FUNCTION");
  const Vec3 normal{plane[3], plane[4], plane[5]};
  if (normal.x == 0 && normal.y == 0 && normal.z == 0) {
    throw UsageError("--plane: the normal (the last three numbers) must not be zero");
  }
  return ImplicitFunction::plane({plane[0], plane[1], plane[2]}, normal);
}

}  // namespace

void add_cut_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, function, q;
    std::vector<double> plane, values, range;
    bool triangulate = false, linear = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("cut", "Cut any dataset with a plane or an implicit function at one "
                                        "or more values: polygons from 3D cells, lines from 2D cells, "
                                        "points from lines");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  auto* plane_opt = cmd->add_option("--plane", args->plane,
                                    "The plane F = signed distance: OX OY OZ NX NY NZ (a point and "
                                    "a non-zero normal)")
                        ->expected(6)
                        ->check(finite_number());
  auto* f_opt = cmd->add_option("-f,--function", args->function,
                                "Function expression (see docs/implicit.md)");
  auto* v_opt = cmd->add_option("-v,--value", args->values,
                                "Cut value c of F = c (repeat for several; default 0)")
                    ->check(finite_number());
  auto* range_opt =
      cmd->add_option("--range", args->range,
                      "N evenly spaced values from FIRST to LAST: FIRST LAST N (FIRST <= LAST, N at "
                      "most " + std::to_string(kMaxCutValues) + ")")
          ->expected(3)
          ->check(finite_number().application_index(0))
          ->check(finite_number().application_index(1))
          ->transform(integer_in(1, kMaxCutValues).application_index(2));
  cmd->add_flag("--triangulate", args->triangulate, "Triangles instead of polygons");
  cmd->add_flag("--linear", args->linear,
                "Place cut points by linear interpolation of F along edges (default: on F = c, "
                "by root finding)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))->required();
  cmd->footer(
      "Examples:\n"
      "  isoforge cut data/combxyz.bin --q data/combq.bin --plane 8.255 0 29.763 -0.287 0 0.9579 -o comb_cut.vtp\n"
      "  isoforge cut data/Torso.vtp --plane 0 0 0 0 1 0 --range 1.5 136.5 46 -o torso_lines.vtp\n"
      "  isoforge cut data/ironProt.vtk -f 'sphere(center=[34,34,34], r=20)' -v 0 -v 5 -o shells.vtp");
  cmd->callback([args, &ctx, plane_opt, f_opt, v_opt, range_opt, q_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    exclude_each_other({v_opt, range_opt});
    const ImplicitFunction f = cut_function(args->plane, plane_opt, args->function, f_opt);
    CutOptions o;
    o.values = args->values;
    if (!args->range.empty()) {
      const auto n = static_cast<int>(args->range[2]);  // an integer (checked)
      require_finite_width("--range", args->range[0], args->range[1]);
      if (args->range[0] == args->range[1] && n > 1) {
        throw UsageError("--range: FIRST equals LAST, so N must be 1");
      }
      try {
        o.values = generate_values(n, args->range[0], args->range[1]);
      } catch (const Error& e) {
        throw UsageError(std::string("--range: ") + e.what());
      }
    }
    if (o.values.empty()) o.values = {0.0};
    o.triangulate = args->triangulate;
    o.refine = !args->linear;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    bar.stage("cutting");
    o.progress = bar.callback();
    auto [out, stats] = cut(ds, f, o);
    if (out.num_cells() == 0) {
      bar.finish();
      const DataArray values = sample_points(f, ds);  // where F lies, to say why
      warn(fmt::format("cut: nothing at {}: {} over the points of {}", values_text(o.values, "value"),
                       range_text(values), args->in));
    }
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} polygons, {} lines, {} vertices, {} points\n", args->out,
                 stats.polygons, stats.lines, stats.vertices, stats.points);
    }
  });
}

}  // namespace isoforge::cli
