// isoforge streamlines: lines tangent to a vector field from seeds on a line, a plane, points or
// the points of a file, optionally as tubes or ribbons.

#include <fmt/core.h>

#include <chrono>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/probe.hpp"
#include "isoforge/filters/streamline.hpp"
#include "isoforge/filters/tube.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {

/// The seeds of `--seeds`: "line X0 Y0 Z0 X1 Y1 Z1 N", "plane OX OY OZ X1 Y1 Z1 X2 Y2 Z2 NU
/// NV", "point X Y Z" or a file name (its points). \throw UsageError naming --seeds.
std::optional<PolyData> generated_seeds(const std::vector<std::string>& v) {
  const std::string& kind = v[0];
  auto count = [&](std::size_t n, const char* form) {
    if (v.size() != n + 1) {
      throw UsageError("--seeds", fmt::format("'{}' takes {} values: {} {}, got {}", kind, n,
                                              kind, form, v.size() - 1));
    }
  };
  if (kind == "line") {
    count(7, "X0 Y0 Z0 X1 Y1 Z1 N");
    const Vec3 p0 = vec_at(v, 1, "--seeds", "P0"), p1 = vec_at(v, 4, "--seeds", "P1");
    const Index n = integer_at(v, 7, "--seeds", "N", 1);
    if (p0 == p1 && n > 1) {
      throw UsageError("--seeds", "line P0 equals P1: N seeds would all be the same (give N = 1)");
    }
    return probe_line(p0, p1, n);
  }
  if (kind == "plane") {
    count(11, "OX OY OZ X1 Y1 Z1 X2 Y2 Z2 NU NV");
    const Vec3 o = vec_at(v, 1, "--seeds", "ORIGIN"), p1 = vec_at(v, 4, "--seeds", "P1"),
               p2 = vec_at(v, 7, "--seeds", "P2");
    const Index nu = integer_at(v, 10, "--seeds", "NU", 2), nv = integer_at(v, 11, "--seeds", "NV", 2);
    const Vec3 u = p1 - o, w = p2 - o;
    if (!(norm(cross(u, w)) > 1e-12 * std::max(dot(u, u), dot(w, w)))) {
      throw UsageError("--seeds", "degenerate plane: ORIGIN->P1 and ORIGIN->P2 are parallel or "
                                  "of zero length");
    }
    return probe_plane(o, p1, p2, nu, nv);
  }
  if (kind == "point") {
    count(3, "X Y Z");
    PolyData seeds;
    seeds.points.push_back(vec_at(v, 1, "--seeds", "the point"));
    return seeds;
  }
  if (v.size() != 1) {
    throw UsageError("--seeds", fmt::format("give 'line ...', 'plane ...', 'point X Y Z' or one "
                                            "file name, got '{}' and {} more values",
                                            kind, v.size() - 1));
  }
  return std::nullopt;  // a file, read with the input
}

}  // namespace

void add_streamlines_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, vectors, direction = "both", integrator = "rk45";
    std::vector<std::string> seeds;
    double step = 0.2, min_step = 0.01, max_step = 1.0, max_error = 1e-6, max_length = 0,
           terminal_speed = 1e-12, tube = 0, ribbon = 0;
    std::string tube_by;
    std::size_t max_steps = 2000;
    int sides = 8;
    bool no_vorticity = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "streamlines", "Streamlines of a vector field (vtkStreamTracer): RK2, RK4 or adaptive RK45 "
                     "from seeds on a line, a plane, a point or a file's points; optional tubes");
  cmd->add_option("input", args->in, "Input dataset with a point vector array (any type)")
      ->required();
  cmd->add_option("--seeds", args->seeds,
                  "Seeds: 'line X0 Y0 Z0 X1 Y1 Z1 N', 'plane OX OY OZ X1 Y1 Z1 X2 Y2 Z2 NU NV', "
                  "'point X Y Z', or a dataset file (its points)")
      ->required()
      ->expected(1, 12)
      ->type_name("KIND VALUES... | FILE");
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  cmd->add_option("--vectors", args->vectors, "Point array to follow (default: active vectors)");
  cmd->add_option("--direction", args->direction, "forward, backward or both (default both)")
      ->check(CLI::IsMember({"forward", "backward", "both"}));
  cmd->add_option("--integrator", args->integrator, "rk2, rk4 or rk45 (default rk45, adaptive)")
      ->check(CLI::IsMember({"rk2", "rk4", "rk45"}));
  cmd->add_option("--step", args->step,
                  "Step length in cell lengths (the input's mean cell size; default 0.2); RK45's "
                  "first step")
      ->check(positive_number());
  auto* min_opt = cmd->add_option("--min-step", args->min_step,
                                  "RK45's smallest step, cell lengths (default 0.01)")
                      ->check(positive_number());
  auto* max_opt = cmd->add_option("--max-step", args->max_step,
                                  "RK45's largest step, cell lengths (default 1)")
                      ->check(positive_number());
  auto* err_opt = cmd->add_option("--max-error", args->max_error,
                                  "RK45's largest local error per step, cell lengths (default "
                                  "1e-6)")
                      ->check(positive_number());
  cmd->add_option("--max-steps", args->max_steps, "Steps per direction (N >= 1, default 2000)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 40));
  cmd->add_option("--max-length", args->max_length,
                  "Arc length per direction, data units (default: no limit)")
      ->check(positive_number());
  cmd->add_option("--terminal-speed", args->terminal_speed,
                  "Speed at or below which a line stops (default 1e-12)")
      ->check(non_negative_number());
  cmd->add_flag("--no-vorticity", args->no_vorticity,
                "Leave out the Vorticity and AngularVelocity arrays");
  auto* tube_opt = cmd->add_option("--tube", args->tube,
                                   "Write tubes of this radius (data units) around the lines")
                       ->check(positive_number());
  auto* sides_opt = cmd->add_option("--sides", args->sides, "Sides of each tube (N >= 3, default 8)")
                        ->check(CLI::Range(3, 1024));
  auto* by_opt = cmd->add_option("--tube-by", args->tube_by,
                                 "Vary the tube radius from --tube to 10 x --tube with this point "
                                 "array (a scalar, or a vector's length: the speed)");
  auto* ribbon_opt = cmd->add_option("--ribbon", args->ribbon,
                                     "Write ribbons of this width (data units), turned by the "
                                     "flow's rotation about each line")
                         ->check(positive_number());
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "One polyline per seed and direction (forward first), with every point array of the input\n"
      "interpolated, IntegrationTime, ArcLength, Vorticity, AngularVelocity, Rotation and\n"
      "Normals; cell arrays SeedIds and ReasonForTermination (1 out of domain, 4 length, 5 steps,\n"
      "6 stagnation). --tube or --ribbon turn the lines into surfaces.\n"
      "Method: docs/algorithms/streamline.md.\n"
      "Examples:\n"
      "  isoforge streamlines data/office.binary.vtk --seeds line 0.1 2.1 0.5 0.1 2.7 0.5 20 \\\n"
      "      -o office_lines.vtp\n"
      "  isoforge streamlines data/office.binary.vtk --seeds plane 0.1 0.5 0.3 0.1 3.5 0.3 0.1 0.5 "
      "2.5 8 8 \\\n"
      "      --integrator rk4 --max-length 20 --tube 0.01 -o office_tubes.vtp\n"
      "  isoforge streamlines data/office.binary.vtk --seeds line 0.1 2.1 0.5 0.1 2.7 0.5 10 \\\n"
      "      --tube 0.005 --tube-by vectors -o office_speed_tubes.vtp\n"
      "  isoforge streamlines data/combxyz.bin --q data/combq.bin --vectors Momentum \\\n"
      "      --seeds point 3 0 25 --direction forward --ribbon 0.2 -o comb_ribbon.vtk");
  cmd->callback([args, &ctx, min_opt, max_opt, err_opt, tube_opt, sides_opt, by_opt, ribbon_opt,
                 q_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    require_meaningful(sides_opt, tube_opt->count() > 0, "applies with --tube only");
    require_meaningful(by_opt, tube_opt->count() > 0, "applies with --tube only");
    exclude_each_other({tube_opt, ribbon_opt});
    if (ribbon_opt->count() && args->no_vorticity) {
      throw UsageError("--ribbon: ribbons turn with the flow's rotation: leave out --no-vorticity");
    }
    const bool adaptive = args->integrator == "rk45";
    require_meaningful(min_opt, adaptive, "applies with --integrator rk45 only");
    require_meaningful(max_opt, adaptive, "applies with --integrator rk45 only");
    require_meaningful(err_opt, adaptive, "applies with --integrator rk45 only");
    if (adaptive && args->min_step > args->max_step) {
      throw UsageError(fmt::format("--min-step {} exceeds --max-step {}", args->min_step,
                                   args->max_step));
    }
    std::optional<PolyData> seeds = generated_seeds(args->seeds);

    StreamlineOptions o;
    o.vectors = args->vectors;
    o.integrator = args->integrator == "rk2"   ? StreamIntegrator::RK2
                   : args->integrator == "rk4" ? StreamIntegrator::RK4
                                               : StreamIntegrator::RK45;
    o.direction = args->direction == "forward"    ? StreamDirection::Forward
                  : args->direction == "backward" ? StreamDirection::Backward
                                                  : StreamDirection::Both;
    o.step = args->step;
    o.min_step = args->min_step;
    o.max_step = args->max_step;
    o.max_error = args->max_error;
    o.max_steps = args->max_steps;
    if (args->max_length > 0) o.max_length = args->max_length;
    o.terminal_speed = args->terminal_speed;
    o.vorticity = !args->no_vorticity;

    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset input = read_input(args->in, bar, ro);
    std::optional<Dataset> seed_file;
    if (!seeds) seed_file = read_input(args->seeds[0], bar);
    const DatasetRef seed_ref = seeds ? DatasetRef(*seeds) : DatasetRef(*seed_file);
    bar.stage("integrating");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    auto [lines, stats] = streamlines(input, seed_ref, o);
    std::string tubes;
    if (tube_opt->count()) {
      bar.stage("tubing");
      TubeOptions to;
      to.radius = args->tube;
      to.sides = args->sides;
      to.radius_array = args->tube_by;
      to.progress = bar.callback();
      auto tubed = tube(lines, to);
      tubes = fmt::format(", {} tubes of {} triangles", tubed.stats.tubes,
                          tubed.output.polys.size());
      lines = std::move(tubed.output);
    } else if (ribbon_opt->count()) {
      bar.stage("ribbons");
      RibbonOptions ro;
      ro.width = args->ribbon;
      ro.progress = bar.callback();
      auto ribbons = ribbon(lines, ro);
      tubes = fmt::format(", {} ribbons of {} triangles", ribbons.stats.ribbons,
                          ribbons.output.polys.size());
      lines = std::move(ribbons.output);
    }
    const double ms = elapsed_ms(t0);
    write_output(lines, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      const auto& r = stats.by_reason;
      fmt::print(stderr,
                 "wrote {}: {} lines, {} points from {} seeds ({} outside the input){} in "
                 "{:.3f} s; {} steps ({} rejected), cell length {:.4g}; ended by domain {}, "
                 "length {}, steps {}, stagnation {}\n",
                 args->out, stats.lines, stats.points, stats.seeds, stats.seeds_outside, tubes,
                 ms / 1000, stats.steps, stats.rejected_steps, stats.cell_length,
                 r[size_t(StreamTermination::OutOfDomain)],
                 r[size_t(StreamTermination::OutOfLength)], r[size_t(StreamTermination::OutOfSteps)],
                 r[size_t(StreamTermination::Stagnation)]);
    }
  });
}

}  // namespace isoforge::cli
