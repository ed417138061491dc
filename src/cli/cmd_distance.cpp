// isoforge distance: distance fields of points, lines and polygons, dense or OpenVDB.

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/implicit_modeller.hpp"
#include "progress_bar.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

namespace {

DistanceStrategy parse_strategy(const std::string& s) {
  if (s == "scatter") return DistanceStrategy::Scatter;
  if (s == "gather") return DistanceStrategy::Gather;
  return DistanceStrategy::Auto;
}

const char* strategy_name(DistanceStrategy s) {
  switch (s) {
    case DistanceStrategy::Scatter:
      return "scatter";
    case DistanceStrategy::Gather:
      return "gather";
    case DistanceStrategy::Auto:
      return "auto";
  }
  return "?";
}

double largest_side(const Bounds& b) {
  const Vec3 s = b.size();
  return std::max({s.x, s.y, s.z});
}

// The cubic grid covering `b` whose largest axis has dims[axis] samples (as `isoforge sample`),
// or of the given voxel size (> 0).
GridSpec cubic_from_dims(const Bounds& b, const Dims& dims, double voxel_size) {
  double h = voxel_size;
  if (h == 0) {
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (b.size()[a] / static_cast<double>(dims[a] - 1) >
          b.size()[axis] / static_cast<double>(dims[axis] - 1)) {
        axis = a;
      }
    }
    h = b.size()[axis] / static_cast<double>(dims[axis] - 1);
    if (!(h > 0)) throw UsageError("--bounds: the box has zero extent");
  }
  try {
    return cubic_grid(b, h);
  } catch (const Error& e) {
    throw UsageError(voxel_size > 0 ? "--voxel-size" : "--dims", e.what());
  }
}

}  // namespace

void add_distance_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, strategy = "auto", radius;
    std::vector<double> bounds;
    std::vector<Index> dims{50};
    double max_distance = 0, voxel_size = 0, cap_value = 0;
    bool is_signed = false, cap = false, float64 = false, open_ok = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "distance",
      "Exact distance field of points, lines and polygons up to a maximum distance: "
      "a dense volume (.vti, .vtk) or an OpenVDB narrow band (.vdb)");
  cmd->add_option("input", args->in, "Polygonal data (.vtk .vtp .ply .obj .off)")->required();
  cmd->add_option("-m,--max-distance", args->max_distance,
                  "Band half width in world units, > 0 (default: 0.1 x the largest side, as VTK)")
      ->check(positive_number());
  auto* dims_opt = add_dims_option(*cmd, "-d,--dims", args->dims, 2,
                                   "Samples per axis: N or NX NY NZ (default 50)");
  add_bounds_option(*cmd, args->bounds,
                    "Sampled box: xmin xmax ymin ymax zmin zmax (default: the input's bounds grown "
                    "by the maximum distance)");
  cmd->add_flag("--signed", args->is_signed,
                "Signed distance, negative inside (closed triangle meshes)");
  auto* open_opt =
      cmd->add_flag("--allow-open", args->open_ok,
                    "With --signed: accept open/non-manifold meshes (pseudonormal sign, no check)");
  auto* cap_opt = cmd->add_flag("--cap", args->cap,
                                "Dense: set the boundary samples to the cap value, so that "
                                "offset surfaces close at the volume boundary");
  auto* cap_value_opt =
      cmd->add_option("--cap-value", args->cap_value,
                      "With --cap: value of capped samples (default: the maximum distance)")
          ->check(finite_number());
  cmd->add_option("--radius", args->radius,
                  "Point-data array of vertex radii (vertices become balls)");
  auto* float64_opt =
      cmd->add_flag("--float64", args->float64, "Dense: store Float64 values (default Float32)");
  auto* voxel_size_opt =
      cmd->add_option("--voxel-size", args->voxel_size,
                      "Sparse: voxel size (default: the largest extent / (its dims - 1))")
          ->check(positive_number());
  cmd->add_option("--strategy", args->strategy,
                  "auto, scatter (per primitive) or gather (per sample)")
      ->check(CLI::IsMember({"auto", "scatter", "gather"}));
  cmd->add_option("-o,--output", args->out, "Output: .vti or .vtk (dense), .vdb (sparse)")
      ->required();
  cmd->footer(
      "Values are exact Euclidean distances below the maximum distance; farther samples hold the\n"
      "maximum distance (dense) or are inactive background (sparse).\n"
      "Examples:\n"
      "  isoforge distance data/hello.vtk -m 0.25 -d 110 40 20 --cap -o hello.vti\n"
      "  isoforge distance data/bunny.ply -m 0.02 -d 128 -o bunny.vti\n"
      "  isoforge distance data/bunny.ply -m 0.003 --voxel-size 0.0005 -o bunny.vdb   (narrow band)\n"
      "  isoforge sample -f 'sphere(r=1)' -b -1.5 1.5 -1.5 1.5 -1.5 1.5 -d 64 -o sphere.vti\n"
      "  isoforge contour sphere.vti -v 0 -o sphere.ply\n"
      "  isoforge distance sphere.ply --signed -m 0.1 -d 64 -o sphere_sdf.vti");
  cmd->callback([args, &ctx, dims_opt, open_opt, cap_opt, cap_value_opt, float64_opt,
                 voxel_size_opt] {
    const FileFormat format =
        output_format(args->out, {FileFormat::VtkImageData, FileFormat::VtkLegacy, FileFormat::Vdb},
                      ".vti .vtk (dense) or .vdb (sparse)");
    const bool sparse = format == FileFormat::Vdb;
    require_meaningful(open_opt, args->is_signed, "applies with --signed only");
    require_meaningful(cap_opt, !sparse, "applies to dense output (.vti .vtk) only");
    require_meaningful(cap_value_opt, args->cap, "applies with --cap only");
    require_meaningful(float64_opt, !sparse, "applies to dense output (.vti .vtk) only");
    require_meaningful(voxel_size_opt, sparse, "applies to sparse output (.vdb) only");
    exclude_each_other({dims_opt, voxel_size_opt});
    const Dims dims = parse_dims(args->dims, "--dims");
    const std::optional<Bounds> given_bounds =
        args->bounds.empty() ? std::nullopt
                             : std::optional<Bounds>(parse_bounds(args->bounds, "--bounds"));
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    const PolyData in = read_polydata(args->in, bar, "distance: distances are measured from polygonal data (points, lines, polygons)");
    const Bounds ib = in.bounds();
    if (ib.empty()) throw Error("distance: " + args->in + " has no points");
    DistanceOptions o;
    o.max_distance = args->max_distance != 0 ? args->max_distance : 0.1 * largest_side(ib);
    if (!(o.max_distance > 0)) {
      throw UsageError("--max-distance: " + args->in +
                       " has zero extent, so give the maximum distance");
    }
    o.signed_distance = args->is_signed;
    o.require_closed = !args->open_ok;
    o.radius_array = args->radius;
    o.strategy = parse_strategy(args->strategy);
    const Bounds b = given_bounds ? *given_bounds : grown(ib, o.max_distance);
    for (int a = 0; a < 3 && !given_bounds; ++a) {
      if (!std::isfinite(b.max[a] - b.min[a])) {
        throw UsageError(
            fmt::format("--max-distance: {:g} grows the box of {} beyond the range "
                        "of a double: give --bounds, or a smaller distance",
                        o.max_distance, args->in));
      }
    }
    if (!sparse && !args->float64) {
      // Samples beyond the band hold the maximum distance (or the cap): it must be a float.
      constexpr double kFloatMax = std::numeric_limits<float>::max();
      if (o.max_distance > kFloatMax) {
        throw UsageError(
            fmt::format("--max-distance: {:g} does not fit the Float32 distances "
                        "(largest {:g}): give --float64, or a smaller distance",
                        o.max_distance, kFloatMax));
      }
      if (args->cap && cap_value_opt->count() > 0 && std::abs(args->cap_value) > kFloatMax) {
        throw UsageError(
            fmt::format("--cap-value: {:g} does not fit the Float32 distances "
                        "(largest {:g}): give --float64, or a smaller value",
                        args->cap_value, kFloatMax));
      }
    }
    DistanceStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    // An empty band is written (it is the answer), with a warning.
    const auto warn_empty_band = [&] {
      bar.finish();
      warn(fmt::format("distance: no sample lies within {:g} of {}: every value is the maximum "
                       "distance (the box is x {:g} .. {:g}, y {:g} .. {:g}, z {:g} .. {:g}; the "
                       "input x {:g} .. {:g}, y {:g} .. {:g}, z {:g} .. {:g})",
                       o.max_distance, args->in, b.min.x, b.max.x, b.min.y, b.max.y, b.min.z,
                       b.max.z, ib.min.x, ib.max.x, ib.min.y, ib.max.y, ib.min.z, ib.max.z));
    };
    bar.stage("distance");
    o.progress = bar.callback();
    if (sparse) {
      const GridSpec g =
          cubic_from_dims(b, dims, voxel_size_opt->count() > 0 ? args->voxel_size : 0.0);
      o.name = "distance";
      double reach = o.max_distance;  // of a vertex: its ball's radius too
      if (const DataArray* r = in.point_data.find(o.radius_array); r && r->tuples() > 0) {
        const double largest = r->range().second;
        if (largest > 0) reach += largest;
      }
      require_band_memory(in, g, reach, "distance");
      double ms = 0;
      stats = vdb_commands().distance(in, g, o, args->out, bar, [&](const DistanceStats& s) {
        if (s.active_voxels == 0) warn_empty_band();
        ms = elapsed_ms(t0);
      });
      bar.finish();
      if (!ctx.quiet) {
        fmt::print(stderr,
                   "wrote {}: {} x {} x {} voxels of size {:g}, {} active ({:.1f} MB tree), "
                   "{} strategy, {:.0f} ms\n",
                   args->out, g.dims[0], g.dims[1], g.dims[2], g.spacing.x, stats.active_voxels,
                   static_cast<double>(stats.memory_bytes) / 1e6, strategy_name(stats.strategy),
                   ms);
      }
      return;
    }
    const GridSpec g = grid_from_bounds(b, dims);
    o.type = args->float64 ? ScalarType::Float64 : ScalarType::Float32;
    auto [img, image_stats] = distance_image(in, g, o);
    stats = image_stats;
    if (stats.active_voxels == 0) warn_empty_band();
    if (args->cap) cap_boundary(img, cap_value_opt->count() > 0 ? args->cap_value : o.max_distance);
    const double ms = elapsed_ms(t0);
    write_output(img, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} x {} x {} samples, {} within {:g}, {} strategy, {:.0f} ms\n",
                 args->out, dims[0], dims[1], dims[2], stats.active_voxels, o.max_distance,
                 strategy_name(stats.strategy), ms);
    }
  });
}

}  // namespace isoforge::cli
