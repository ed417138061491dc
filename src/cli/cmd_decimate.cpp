// isoforge decimate: reduce a triangle mesh (quadric edge collapse, vertex removal or cell
// collapse), optionally refit to the input (Ceres), and measure the result against the input.

#include <fmt/core.h>

#include <chrono>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/fit/refine.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/reduce/decimate.hpp"
#include "isoforge/reduce/mesh_distance.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_decimate_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, method = "quadric", lock;
    std::int64_t target = 0;
    double reduction = 0, max_error = 0, feature_angle = 180, max_turn = 90, boundary_weight = 10,
           attribute_weight = 0;
    bool relative = false, preserve_boundary = true, preserve_topology = true,
         preserve_volume = true, refine = false, no_measure = false, no_intersection_check = false;
    ColorBy color_by;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "decimate",
      "Reduce a triangle mesh: quadric edge collapse, vertex removal or cell collapse; "
      "never self-intersecting, topology kept");
  cmd->add_option("input", args->in, "Input surface (" + std::string(kSurfaceExtensions) + ")")
      ->required();
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  auto* target_opt =
      cmd->add_option("-t,--target-triangles", args->target, "Stop at this many triangles (N >= 1)")
          ->transform(integer_in(1));
  auto* reduction_opt = cmd->add_option("-r,--reduction", args->reduction,
                                        "Or remove this fraction of the triangles, in (0, 1)")
                            ->check(number_in(0, 1, true));
  auto* error_opt = cmd->add_option("-e,--max-error", args->max_error,
                                    "Or stop before an operation would move the surface by more "
                                    "than this (data units, or a fraction of the diagonal with "
                                    "--relative)")
                        ->check(positive_number());
  auto* relative_opt =
      cmd->add_flag("--relative", args->relative, "--max-error is relative to the bbox diagonal");
  cmd->add_option("-m,--method", args->method, "quadric, vertex-removal or cell-collapse")
      ->check(CLI::IsMember({"quadric", "vertex-removal", "cell-collapse"}));
  auto* boundary_opt =
      cmd->add_flag("--preserve-boundary,!--free-boundary", args->preserve_boundary,
                    "Keep borders in place with constraint planes (default on)");
  auto* volume_opt = cmd->add_flag(
      "--preserve-volume,!--free-volume", args->preserve_volume,
      "Quadric method: place merged vertices so the surface keeps its volume (lower RMS "
      "distance; default on); --free-volume: the quadric's own minimum (Garland-Heckbert)");
  cmd->add_flag("--preserve-topology,!--free-topology", args->preserve_topology,
                "Never change genus, close holes or make non-manifold parts (default on)");
  cmd->add_option("--feature-angle", args->feature_angle,
                  "Edges with a dihedral angle above this (degrees) are kept as features "
                  "(default 180: none)")
      ->check(number_in(0, 180, true));
  cmd->add_option("--max-normal-turn", args->max_turn,
                  "Refuse operations turning a face normal more than this (degrees, default 90)")
      ->check(number_in(0, 180, true));
  auto* boundary_weight_opt =
      cmd->add_option("--boundary-weight", args->boundary_weight,
                      "Weight of the border and feature constraint planes (default 10)")
          ->check(non_negative_number());
  auto* attribute_weight_opt =
      cmd->add_option(
             "--attribute-weight", args->attribute_weight,
             "Weight of point-array differences in the collapse cost, as a fraction of the "
             "diagonal per full-range difference (default 0: geometry only)")
          ->check(non_negative_number());
  cmd->add_option("--lock", args->lock,
                  "Point array whose non-zero entries lock a vertex in place");
  cmd->add_flag("--no-intersection-check", args->no_intersection_check,
                "Skip the exact self-intersection test of new faces (faster; no guarantee)");
  cmd->add_flag("--refine", args->refine,
                "Refit the decimated vertices to the input surface (Ceres; lowers RMS and "
                "Hausdorff distance, never folds)");
  cmd->add_flag("--no-measure", args->no_measure,
                "Do not measure the Hausdorff and RMS distance to the input");
  add_color_by_options(*cmd, args->color_by);
  cmd->footer(
      "Prints the achieved triangle count, the time and the Hausdorff and RMS distances between\n"
      "the output and the input (relative to the input's bounding-box diagonal).\n"
      "Examples:\n"
      "  isoforge decimate data/bunny.ply -r 0.9 -o bunny10.ply\n"
      "  isoforge decimate data/bunny.ply -t 1000 --refine -o bunny1k.vtp\n"
      "  isoforge decimate data/bunny.ply -t 5000 -m vertex-removal --feature-angle 60 -o "
      "bunny5k.vtp\n"
      "  isoforge decimate data/bunny.ply -e 0.001 --relative -o bunny_err.vtp\n"
      "  isoforge decimate data/bunny.ply -r 0.5 --color-by intensity --colormap inferno -o bunny_colored.ply");
  cmd->callback([args, &ctx, target_opt, reduction_opt, error_opt, relative_opt, boundary_opt,
                 boundary_weight_opt, attribute_weight_opt, volume_opt] {
    const FileFormat format = output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    exclude_each_other({target_opt, reduction_opt});
    if (target_opt->count() == 0 && reduction_opt->count() == 0 && error_opt->count() == 0) {
      throw UsageError("give a stop: --target-triangles N, --reduction R or --max-error E");
    }
    require_meaningful(relative_opt, error_opt->count() > 0, "applies to --max-error only");
    check_color_by(args->color_by, format);
    if (args->reduction >= 1) {
      throw UsageError("--reduction: must be below 1 (1 would remove every triangle), got " +
                       fmt::format("{}", args->reduction));
    }
    // Options the chosen method does not use are errors, not silently ignored.
    const bool removal = args->method == "vertex-removal";
    require_meaningful(attribute_weight_opt, args->method == "quadric",
                       "applies to --method quadric only");
    require_meaningful(volume_opt, args->method == "quadric", "applies to --method quadric only");
    require_meaningful(boundary_opt, !removal,
                       "vertex removal has no border constraint planes (use --method quadric or "
                       "cell-collapse)");
    require_meaningful(boundary_weight_opt,
                       !removal && (args->preserve_boundary || args->feature_angle < 180),
                       removal ? "vertex removal has no constraint planes"
                               : "weighs border and feature planes: with --free-boundary it needs "
                                 "--feature-angle below 180");
    DecimateOptions o;
    o.method = args->method == "vertex-removal"  ? DecimateMethod::VertexRemoval
               : args->method == "cell-collapse" ? DecimateMethod::CellCollapse
                                                 : DecimateMethod::Quadric;
    o.target_triangles = static_cast<std::size_t>(args->target);
    o.target_reduction = args->reduction;
    o.max_error = args->max_error;
    o.max_error_relative = args->relative;
    o.preserve_boundary = args->preserve_boundary;
    o.preserve_topology = args->preserve_topology;
    o.preserve_volume = args->preserve_volume;
    o.feature_angle = args->feature_angle;
    o.max_normal_turn = args->max_turn;
    o.boundary_weight = args->boundary_weight;
    o.attribute_weight = args->attribute_weight;
    o.lock_array = args->lock;
    o.check_self_intersections = !args->no_intersection_check;

    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    const PolyData input =
        read_polydata(args->in, bar, "decimate: only polygonal data can be decimated");
    require_color_array(args->color_by, input, true);  // decimation keeps point data only
    bar.stage("decimating");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    auto [surface, stats] = decimate(input, o);
    const double decimate_ms = elapsed_ms(t0);
    RefineStats refined;
    double refine_ms = 0;
    if (args->refine) {
      bar.stage("refining");
      RefineOptions ro;
      ro.lock_array = args->lock;
      ro.progress = bar.callback();
      const auto t1 = std::chrono::steady_clock::now();
      auto r = refine_mesh(input, surface, ro);
      refine_ms = elapsed_ms(t1);
      surface = std::move(r.output);
      refined = r.stats;
    }
    MeshDistance distance;
    if (!args->no_measure) {
      bar.stage("measuring");
      MeshDistanceOptions mo;
      mo.progress = bar.callback();
      distance = mesh_distance(input, surface, mo);
    }
    const std::string colored = apply_color_by(args->color_by, surface);
    write_output(surface, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points, {} triangles (from {}; {}, {}) in {:.3f} s\n",
                 args->out, stats.output_points, stats.output_triangles, stats.input_triangles,
                 to_string(o.method), to_string(stats.stop), decimate_ms / 1000);
      fmt::print(stderr,
                 "  {} operations, largest error {:.4g}; refused: {} topology, {} normal turn, "
                 "{} self-intersection; {} vertices locked\n",
                 stats.operations, stats.max_error, stats.refused_topology, stats.refused_flip,
                 stats.refused_intersection, stats.locked_vertices);
      if (stats.intersection_reruns > 0) {
        fmt::print(stderr, "  redone {} time(s) with more merges tested for intersections\n",
                   stats.intersection_reruns);
      }
      if (!colored.empty()) fmt::print(stderr, "  {}\n", colored);
      if (args->refine) {
        fmt::print(stderr,
                   "  refined in {:.3f} s: RMS {:.4g} -> {:.4g}, Hausdorff {:.4g} -> {:.4g} "
                   "({} vertices moved, {} moves rejected, {} triangles changed by edge flips)\n",
                   refine_ms / 1000, refined.rms_before, refined.rms_after,
                   refined.hausdorff_before, refined.hausdorff_after, refined.moved_vertices,
                   refined.rejected_moves, refined.flips);
      }
      if (!args->no_measure) {
        fmt::print(stderr,
                   "  distance to the input: Hausdorff {:.4g} ({:.3e} of the diagonal), RMS "
                   "{:.4g} ({:.3e})\n",
                   distance.hausdorff, distance.relative_hausdorff(), distance.rms,
                   distance.relative_rms());
      }
    }
  });
}

}  // namespace isoforge::cli
