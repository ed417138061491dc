// isoforge offset: offset surfaces of points, lines and polygons (implicit modeling), or of a
// distance field.

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/contour/connectivity.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/csg.hpp"
#include "isoforge/model/implicit_modeller.hpp"
#include "progress_bar.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

void add_offset_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, grid;
    std::vector<double> distances, bounds;
    std::vector<Index> dims{64};
    double max_distance = 0, voxel_size = 0;
    bool is_signed = false, no_cap = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("offset",
                         "Offset surfaces at one or more distances from points, lines and polygons "
                         "(implicit modeling), or of a distance field (.vti, .vdb)");
  cmd->add_option("input", args->in,
                  "Polygonal data, or a distance field: image data (.vti .vtk) or .vdb")
      ->required();
  cmd->add_option("-d,--distance", args->distances, "Offset distance (repeat for several)")
      ->required()
      ->check(finite_number());
  auto* dims_opt = add_dims_option(*cmd, "--dims", args->dims, 2,
                                   "Samples per axis: N or NX NY NZ (default 64)");
  auto* bounds_opt = add_bounds_option(
      *cmd, args->bounds,
      "Sampled box (default: the input's bounds grown by 1.25 x the largest distance)");
  auto* max_distance_opt =
      cmd->add_option("-m,--max-distance", args->max_distance,
                      "Band half width, > every |distance| (default: the largest |distance| + 2 "
                      "samples)")
          ->check(positive_number());
  auto* signed_opt = cmd->add_flag("--signed", args->is_signed,
                                   "Signed distance: negative distances offset inward "
                                   "(closed triangle meshes)");
  auto* voxel_size_opt =
      cmd->add_option("--voxel-size", args->voxel_size,
                      "Compute sparsely in an OpenVDB narrow band of this voxel size (no volume)")
          ->check(positive_number());
  auto* no_cap_opt =
      cmd->add_flag("--no-cap", args->no_cap, "Dense: do not cap the volume (surfaces may stay open)");
  auto* grid_opt = add_grid_option(*cmd, args->grid);
  cmd->add_option("-o,--output", args->out, "Output surface: " + std::string(kSurfaceExtensions))
      ->required();
  cmd->footer(
      "The point array IsovalueIndex tells which distance each point belongs to.\n"
      "Examples:\n"
      "  isoforge offset data/hello.vtk -d 0.25 --dims 110 40 20 --bounds -1 10 -1 3 -1 1 -o hello.vtp\n"
      "  isoforge offset data/bunny.ply -d 0.002 -d 0.004 -d 0.008 --dims 128 -o shells.vtp\n"
      "  isoforge offset data/bunny.ply -d 0.001 --voxel-size 0.0005 -o fine.ply      (sparse)\n"
      "  isoforge distance data/bunny.ply -m 0.01 --voxel-size 0.001 -o field.vdb\n"
      "  isoforge offset field.vdb -d 0.005 -o surface.vtp                      (of a distance field)");
  cmd->callback([args, &ctx, dims_opt, bounds_opt, max_distance_opt, signed_opt, voxel_size_opt,
                 no_cap_opt, grid_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_vdb_input(grid_opt, args->in);
    exclude_each_other({dims_opt, voxel_size_opt});
    exclude_each_other({no_cap_opt, voxel_size_opt});
    double dmax = 0;
    for (double d : args->distances) dmax = std::max(dmax, std::abs(d));
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    PolyData surface;
    const auto t0 = std::chrono::steady_clock::now();
    // The options that make a distance field from polygonal data mean nothing for a given field.
    const auto require_polygonal_input = [&](bool polygonal) {
      for (const CLI::Option* opt :
           {dims_opt, bounds_opt, max_distance_opt, signed_opt, voxel_size_opt, no_cap_opt}) {
        require_meaningful(opt, polygonal,
                           "applies when the input is polygonal data (the distance field is "
                           "computed), not to a distance field read from " + args->in);
      }
    };
    // An empty result is written (it is the answer), with a warning naming the field's range.
    const auto warn_if_empty = [&](const std::string& field_range) {
      if (surface.num_points() != 0) return;
      bar.finish();
      warn(fmt::format("offset: no surface at {}: {}", values_text(args->distances, "distance"),
                       field_range));
    };
    const auto image_range = [](const ImageData& img) {
      const DataArray* s = img.point_data.scalars();
      return s ? range_text(*s) : std::string("no point scalars");
    };
    if (format_of(args->in) == FileFormat::Vdb) {
      require_polygonal_input(false);
      std::string range;
      surface = vdb_commands().offset_file(args->in, args->grid, args->distances, bar, range);
      warn_if_empty(range);
    } else {
      Dataset ds = read_input(args->in, bar);
      if (auto* img = std::get_if<ImageData>(&ds)) {
        require_polygonal_input(false);
        bar.stage("contouring");
        surface = offset_surfaces(*img, args->distances).output;
        warn_if_empty(image_range(*img));
      } else if (auto* pd = std::get_if<PolyData>(&ds)) {
        require_polygonal_input(true);
        for (double d : args->distances) {
          if (!args->is_signed && !(d > 0)) {
            throw UsageError(fmt::format(
                "--distance: {:g}: an unsigned distance field has surfaces at distances > 0 only "
                "(give --signed for a closed mesh's inside)", d));
          }
        }
        if (max_distance_opt->count() > 0 && !(args->max_distance > dmax)) {
          throw UsageError(fmt::format(
              "--max-distance: {:g} must exceed the largest |distance| {:g}, or the band does "
              "not reach the surface", args->max_distance, dmax));
        }
        // The field is Float32; samples beyond the band hold the maximum distance.
        if (args->max_distance > std::numeric_limits<float>::max()) {
          throw UsageError(
              fmt::format("--max-distance: {:g} does not fit the Float32 distance "
                          "field (largest {:g})",
                          args->max_distance, std::numeric_limits<float>::max()));
        }
        const Dims dims = parse_dims(args->dims, "--dims");
        const Bounds ib = pd->bounds();
        if (ib.empty()) throw Error("offset: " + args->in + " has no points");
        const Bounds b =
            args->bounds.empty() ? grown(ib, 1.25 * dmax) : parse_bounds(args->bounds, "--bounds");
        DistanceOptions o;
        o.signed_distance = args->is_signed;
        bar.stage("distance");
        o.progress = bar.callback();
        if (voxel_size_opt->count() > 0) {
          GridSpec g;
          try {
            g = cubic_grid(b, args->voxel_size);
          } catch (const Error& e) {
            throw UsageError("--voxel-size", e.what());
          }
          o.max_distance =
              args->max_distance > 0 ? args->max_distance : dmax + 2 * args->voxel_size;
          require_band_memory(*pd, g, o.max_distance, "offset");
          std::string range;
          surface = vdb_commands().offset_band(*pd, g, o, args->distances, bar, range);
          warn_if_empty(range);
        } else {
          const GridSpec g = grid_from_bounds(b, dims);
          const double h = std::max({g.spacing.x, g.spacing.y, g.spacing.z});
          o.max_distance = args->max_distance > 0 ? args->max_distance : dmax + 2 * h;
          ImageData img = distance_image(*pd, g, o).output;
          if (!args->no_cap) cap_boundary(img, o.max_distance);
          bar.stage("contouring");
          surface = offset_surfaces(img, args->distances).output;
          warn_if_empty(image_range(img));
        }
      } else {
        throw Error("offset: " + args->in + " is " + std::string(dataset_type_name(ds)) +
                    "; give polygonal data or a distance field (image data, .vdb)");
      }
    }
    const double ms = elapsed_ms(t0);
    bar.stage("connectivity");
    const std::size_t components = connectivity(surface).stats.components;
    write_output(surface, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points, {} triangles, {} connected surfaces, {:.0f} ms\n",
                 args->out, surface.num_points(), surface.polys.size(), components, ms);
    }
  });
}

}  // namespace isoforge::cli
