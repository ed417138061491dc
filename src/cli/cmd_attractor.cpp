// isoforge attractor: the Lorenz strange attractor (Fig. 1.25).

#include <fmt/core.h>

#include <chrono>
#include <cstdint>
#include <limits>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/attractor.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_attractor_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string out, volume;
    std::int64_t steps = 10'000'000, transient = 0;
    std::vector<Index> dims{200};
    std::vector<double> bounds, start{0.1, 0.1, 0.1};
    double value = 50, step = 0.01, sigma = 10, rho = 28, beta = 8.0 / 3.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "attractor",
      "The Lorenz strange attractor (Fig. 1.25): RK4 trajectory, visits counted per "
      "voxel, marching cubes at a visit value");
  cmd->add_option("-n,--steps", args->steps,
                  "Integration steps, 1 .. 4294967295 (the UInt32 visit counts; default "
                  "10000000)")
      ->transform(integer_in(1, std::numeric_limits<std::uint32_t>::max()));
  cmd->add_option("--transient", args->transient, "Steps integrated before counting (default 0)")
      ->transform(integer_in(0));
  add_dims_option(*cmd, "-d,--dims", args->dims, 2,
                  "Samples per axis: N or NX NY NZ, each >= 2 (default 200)");
  auto* value_opt = cmd->add_option("-v,--value", args->value,
                                    "Contour value in visits, > 0 (default 50)")
                        ->check(positive_number());
  cmd->add_option("--step", args->step, "Time step h, > 0 (default 0.01)")
      ->check(positive_number());
  cmd->add_option("--start", args->start, "Start point X Y Z (default 0.1 0.1 0.1)")
      ->expected(3)
      ->check(finite_number());
  add_bounds_option(*cmd, args->bounds,
                    "Volume box: xmin xmax ymin ymax zmin zmax (default -30 30 -30 30 -10 60)");
  cmd->add_option("--sigma", args->sigma, "Lorenz sigma (default 10)")->check(finite_number());
  cmd->add_option("--rho", args->rho, "Lorenz rho (default 28)")->check(finite_number());
  cmd->add_option("--beta", args->beta, "Lorenz beta (default 8/3)")->check(finite_number());
  auto* volume_opt =
      cmd->add_option("--volume", args->volume, "Also write the visit counts (.vti .vtk)");
  cmd->add_option("-o,--output", args->out,
                  "Output surface (" + std::string(kSurfaceExtensions) + "), or the counts if .vti")
      ->required();
  cmd->footer(
      "States outside the box are discarded (reported), not an error.\n"
      "Examples:\n"
      "  isoforge attractor -o lorenz.vtp                       (Fig. 1.25: 10M steps, 200^3, "
      "value 50)\n"
      "  isoforge attractor --steps 1000000 --dims 100 --value 20 -o small.ply\n"
      "  isoforge attractor --rho 99.96 --bounds -60 60 -120 120 0 200 -o rho100.vtp");
  cmd->callback([args, &ctx, value_opt, volume_opt] {
    std::vector<FileFormat> outputs = kSurfaceFormats;
    outputs.push_back(FileFormat::VtkImageData);
    const FileFormat format = output_format(
        args->out, outputs, std::string(kSurfaceExtensions) + " (the surface) or .vti (the counts)");
    const bool counts_only = format == FileFormat::VtkImageData;
    require_meaningful(value_opt, !counts_only, "applies to a surface output, not to .vti counts");
    require_meaningful(volume_opt, !counts_only,
                       "the counts are the output already (-o " + args->out + ")");
    if (!args->volume.empty()) {
      (void)output_format(args->volume, {FileFormat::VtkImageData, FileFormat::VtkLegacy},
                          ".vti .vtk");
    }
    AttractorOptions o;
    o.lorenz = {args->sigma, args->rho, args->beta};
    o.value = args->value;
    TrajectoryOptions& t = o.trajectory;
    t.steps = static_cast<std::uint64_t>(args->steps);
    t.transient = static_cast<std::uint64_t>(args->transient);
    t.step = args->step;
    t.start = {args->start[0], args->start[1], args->start[2]};
    t.dims = parse_dims(args->dims, "--dims");
    if (!args->bounds.empty()) t.bounds = parse_bounds(args->bounds, "--bounds");
    (void)grid_from_bounds(t.bounds, t.dims);  // a usage error before any work
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("integrating");
    t.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    if (counts_only) {
      const auto [volume, d] = lorenz_density(o.lorenz, t);
      if (d.counted == 0) {
        bar.finish();
        warn(fmt::format("attractor: every one of the {} states fell outside the box: the counts "
                         "are all 0", d.discarded));
      }
      write_output(volume, args->out, bar);
      bar.finish();
      if (!ctx.quiet) {
        fmt::print(stderr,
                   "wrote {}: {} states counted, {} discarded outside the box, max {} visits\n",
                   args->out, d.counted, d.discarded, d.max_visits);
      }
      return;
    }
    const auto [out, stats] = lorenz_attractor(o);
    const TrajectoryStats& d = stats.trajectory;
    if (out.surface.num_points() == 0) {
      bar.finish();
      warn(fmt::format("attractor: no surface at {:g} visits: the counts range 0 .. {} ({} states "
                       "counted, {} outside the box)",
                       o.value, d.max_visits, d.counted, d.discarded));
    }
    const double ms = elapsed_ms(t0);
    bar.stage("writing");
    if (!args->volume.empty()) write_output(out.volume, args->volume, bar);
    write_output(out.surface, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr,
                 "wrote {}: {} triangles at {:g} visits; {} states counted, {} discarded outside "
                 "the box, max {} visits, {:.0f} ms\n",
                 args->out, out.surface.polys.size(), o.value, d.counted, d.discarded,
                 d.max_visits, ms);
    }
  });
}

}  // namespace isoforge::cli
