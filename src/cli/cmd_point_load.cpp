// isoforge point-load: the stress field of a point load on a half-space (Boussinesq), the
// analytic tensor data of tensor glyphs.

#include <fmt/core.h>

#include <chrono>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/point_load.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_point_load_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string out;
    std::vector<Index> dims{50};
    std::vector<double> bounds;
    double load = 1, poisson = 0.3;
    bool no_effective = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "point-load",
      "Stress tensors of a point load on a half-space (Boussinesq; vtkPointLoad), sampled on a "
      "grid");
  cmd->add_option("-o,--output", args->out, "Output image: .vti .vtk")->required();
  add_dims_option(*cmd, "-d,--dims", args->dims, 2,
                  "Samples per axis: N or NX NY NZ, each >= 2 (default 50)");
  add_bounds_option(*cmd, args->bounds,
                    "The box: xmin xmax ymin ymax zmin zmax (default -1 1 -1 1 -1 1); the load "
                    "acts at the centre of its top face (z = zmax)");
  cmd->add_option("--load", args->load, "Downward force, >= 0 (default 1)")
      ->check(non_negative_number());
  cmd->add_option("--poisson", args->poisson, "Poisson's ratio, 0 .. 0.5 (default 0.3)")
      ->check(number_in(0, 0.5));
  cmd->add_flag("--no-effective-stress", args->no_effective,
                "Leave out the scalar 'effective_stress' (von Mises)");
  cmd->footer(
      "Writes the point arrays 'stress' (3x3, tension positive; active tensors),\n"
      "'effective_stress' (von Mises; active scalars) and 'vtkValidPointMask' (0 only at the\n"
      "load point itself, where the stress is infinite and is written as 0).\n"
      "Examples:\n"
      "  isoforge point-load -o load.vti\n"
      "  isoforge point-load --dims 6 --bounds -10 10 -10 10 -10 10 --load 100 -o load6.vti\n"
      "  isoforge tensor-glyph load6.vti -s 0.5 --max-size 3 -o ellipsoids.vtp");
  cmd->callback([args, &ctx] {
    (void)output_format(args->out, {FileFormat::VtkImageData, FileFormat::VtkLegacy}, ".vti .vtk");
    PointLoadOptions o;
    o.dims = parse_dims(args->dims, "--dims");
    if (!args->bounds.empty()) o.bounds = parse_bounds(args->bounds, "--bounds", true);
    o.load = args->load;
    o.poisson_ratio = args->poisson;
    if (args->no_effective) o.scalars.clear();
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("sampling");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    const auto [out, stats] = point_load(o);
    const double ms = elapsed_ms(t0);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points in {:.3f} s{}{}\n", args->out, out.num_points(),
                 ms / 1000,
                 o.scalars.empty() ? std::string()
                                   : fmt::format("; effective stress up to {:.4g}",
                                                 stats.max_effective_stress),
                 stats.singular ? "; the load point itself is a sample (vtkValidPointMask 0)" : "");
    }
  });
}

}  // namespace isoforge::cli
