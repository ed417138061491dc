// Implicit modeling subcommands: isoforge distance (distance fields, dense or OpenVDB),
// isoforge offset (offset surfaces), isoforge csg (booleans of distance fields) and
// isoforge attractor (the Lorenz strange attractor).

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "commands.hpp"
#include "isoforge/contour/connectivity.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/vdb.hpp"
#include "isoforge/model/attractor.hpp"
#include "isoforge/model/csg_sparse.hpp"
#include "isoforge/model/distance_sparse.hpp"
#include "isoforge/model/implicit_modeller.hpp"
#include "progress.hpp"

namespace isoforge::cli {

namespace {

PolyData read_polydata(const std::string& path, const char* command) {
  Dataset ds = read(path);
  if (auto* pd = std::get_if<PolyData>(&ds)) return std::move(*pd);
  throw Error(std::string(command) + ": " + path + " is " + std::string(dataset_type_name(ds)) +
              "; distances are measured from polygonal data (points, lines, polygons)");
}

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

Bounds grown(const Bounds& b, double pad) {
  Bounds r = b;
  r.min = b.min - Vec3{pad, pad, pad};
  r.max = b.max + Vec3{pad, pad, pad};
  return r;
}

// The cubic grid covering `b` whose largest axis has dims[axis] samples (as `isoforge sample`),
// or of the given voxel size.
GridSpec cubic_from_dims(const Bounds& b, const Dims& dims, double voxel_size) {
  double h = voxel_size;
  if (h == 0) {
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (b.size()[a] / static_cast<double>(std::max<Index>(1, dims[a] - 1)) >
          b.size()[axis] / static_cast<double>(std::max<Index>(1, dims[axis] - 1))) {
        axis = a;
      }
    }
    if (dims[axis] < 2) throw Error("--dims: need at least 2 samples along every axis");
    h = b.size()[axis] / static_cast<double>(dims[axis] - 1);
  }
  if (!(h > 0)) throw Error("--voxel-size must be positive");
  return cubic_grid(b, h);
}

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void add_distance_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, strategy = "auto", radius;
    std::vector<double> bounds;
    std::vector<Index> dims{50};
    double max_distance = 0, voxel_size = 0, cap_value = NAN;
    bool is_signed = false, cap = false, float64 = false, open_ok = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "distance",
      "Exact distance field of points, lines and polygons up to a maximum distance: "
      "a dense volume (.vti, .vtk) or an OpenVDB narrow band (.vdb)");
  cmd->add_option("input", args->in, "Polygonal data (.vtk .vtp .ply .obj .off)")->required();
  cmd->add_option("-m,--max-distance", args->max_distance,
                  "Band half width in world units (default: 0.1 x the largest side, as VTK)");
  cmd->add_option("-d,--dims", args->dims, "Samples per axis: N or NX NY NZ (default 50)")
      ->expected(1, 3);
  cmd->add_option("-b,--bounds", args->bounds,
                  "Sampled box: xmin xmax ymin ymax zmin zmax (default: the input's bounds grown "
                  "by the maximum distance)")
      ->expected(6);
  cmd->add_flag("--signed", args->is_signed,
                "Signed distance, negative inside (closed triangle meshes)");
  cmd->add_flag("--allow-open", args->open_ok,
                "With --signed: accept open/non-manifold meshes (pseudonormal sign, no check)");
  cmd->add_flag("--cap", args->cap,
                "Dense: set the boundary samples to the cap value, so that "
                "offset surfaces close at the volume boundary");
  cmd->add_option("--cap-value", args->cap_value,
                  "Value of capped samples (default: the maximum distance)");
  cmd->add_option("--radius", args->radius,
                  "Point-data array of vertex radii (vertices become balls)");
  cmd->add_flag("--float64", args->float64, "Dense: store Float64 values (default Float32)");
  cmd->add_option("--voxel-size", args->voxel_size,
                  "Sparse: voxel size (default: the largest extent / (its dims - 1))");
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
      "  isoforge distance data/bunny.ply -m 0.003 --voxel-size 0.0005 -o bunny.vdb   (narrow "
      "band)\n"
      "  isoforge distance sphere.ply --signed -m 0.1 -d 64 -o sphere_sdf.vti");
  cmd->callback([args, &ctx] {
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    const PolyData in = read_polydata(args->in, "distance");
    const Bounds ib = in.bounds();
    if (ib.empty()) throw Error("distance: the input has no points");
    DistanceOptions o;
    if (args->max_distance < 0 || std::isnan(args->max_distance)) {
      throw Error("--max-distance: must be positive, got " + std::to_string(args->max_distance));
    }
    o.max_distance = args->max_distance != 0 ? args->max_distance : 0.1 * largest_side(ib);
    if (!(o.max_distance > 0)) {
      throw Error("--max-distance: the input has zero extent, give the maximum distance");
    }
    o.signed_distance = args->is_signed;
    o.require_closed = !args->open_ok;
    o.radius_array = args->radius;
    o.strategy = parse_strategy(args->strategy);
    const Bounds b =
        args->bounds.empty() ? grown(ib, o.max_distance) : parse_bounds(args->bounds, "--bounds");
    const Dims dims = parse_dims(args->dims, "--dims");
    const FileFormat format = format_from_path(args->out);
    DistanceStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    bar.stage("distance");
    o.progress = bar.callback();
    if (format == FileFormat::Vdb) {
      const GridSpec g = cubic_from_dims(b, dims, args->voxel_size);
      o.name = "distance";
      auto [grid, grid_stats] = distance_grid(in, g, o);
      stats = grid_stats;
      const double ms = elapsed_ms(t0);
      bar.stage("writing");
      write_vdb(*grid, args->out);
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
    for (int a = 0; a < 3; ++a) {
      if (dims[a] < 2) throw Error("--dims: need at least 2 samples along every axis");
    }
    const GridSpec g = GridSpec::from_bounds(b, dims);
    o.type = args->float64 ? ScalarType::Float64 : ScalarType::Float32;
    auto [img, image_stats] = distance_image(in, g, o);
    stats = image_stats;
    if (args->cap)
      cap_boundary(img, std::isnan(args->cap_value) ? o.max_distance : args->cap_value);
    const double ms = elapsed_ms(t0);
    bar.stage("writing");
    write(img, args->out);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} x {} x {} samples, {} within {:g}, {} strategy, {:.0f} ms\n",
                 args->out, dims[0], dims[1], dims[2], stats.active_voxels, o.max_distance,
                 strategy_name(stats.strategy), ms);
    }
  });
}

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
      ->required();
  cmd->add_option("--dims", args->dims, "Samples per axis: N or NX NY NZ (default 64)")
      ->expected(1, 3);
  cmd->add_option("-b,--bounds", args->bounds,
                  "Sampled box (default: the input's bounds grown by 1.25 x the largest distance)")
      ->expected(6);
  cmd->add_option("-m,--max-distance", args->max_distance,
                  "Band half width (default: the largest |distance| + 2 samples)");
  cmd->add_flag("--signed", args->is_signed,
                "Signed distance: negative distances offset inward "
                "(closed triangle meshes)");
  cmd->add_option("--voxel-size", args->voxel_size,
                  "Compute sparsely in an OpenVDB narrow band of this voxel size (no volume)");
  cmd->add_flag("--no-cap", args->no_cap, "Dense: do not cap the volume (surfaces may stay open)");
  cmd->add_option("--grid", args->grid, "OpenVDB input: name of the float grid");
  cmd->add_option("-o,--output", args->out, "Output surface: .vtp .vtk .ply .obj .off")->required();
  cmd->footer(
      "The point array IsovalueIndex tells which distance each point belongs to.\n"
      "Examples:\n"
      "  isoforge offset data/hello.vtk -d 0.25 --dims 110 40 20 --bounds -1 10 -1 3 -1 1 -o "
      "hello.vtp\n"
      "  isoforge offset data/bunny.ply -d 0.002 -d 0.004 -d 0.008 --dims 128 -o shells.vtp\n"
      "  isoforge offset data/bunny.ply -d 0.001 --voxel-size 0.0002 -o fine.ply      (sparse)\n"
      "  isoforge offset field.vdb -d 0 -o surface.vtp");
  cmd->callback([args, &ctx] {
    double dmax = 0;
    for (double d : args->distances) {
      if (!std::isfinite(d)) throw Error("--distance: not finite");
      dmax = std::max(dmax, std::abs(d));
    }
    (void)format_from_path(args->out);
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    PolyData surface;
    const auto t0 = std::chrono::steady_clock::now();
    const FileFormat in_format = format_from_path(args->in);
    if (in_format == FileFormat::Vdb) {
      const auto grid = read_vdb_grid(args->in, args->grid);
      bar.stage("contouring");
      surface = offset_surfaces(*grid, args->distances).output;
    } else {
      Dataset ds = read(args->in);
      if (auto* img = std::get_if<ImageData>(&ds)) {
        bar.stage("contouring");
        surface = offset_surfaces(*img, args->distances).output;
      } else if (auto* pd = std::get_if<PolyData>(&ds)) {
        const Dims dims = parse_dims(args->dims, "--dims");
        const Bounds ib = pd->bounds();
        if (ib.empty()) throw Error("offset: the input has no points");
        if (!(dmax > 0) && args->max_distance == 0) {
          throw Error("offset: give a non-zero distance or --max-distance");
        }
        const Bounds b =
            args->bounds.empty() ? grown(ib, 1.25 * dmax) : parse_bounds(args->bounds, "--bounds");
        DistanceOptions o;
        o.signed_distance = args->is_signed;
        bar.stage("distance");
        o.progress = bar.callback();
        if (args->voxel_size > 0) {
          const GridSpec g = cubic_grid(b, args->voxel_size);
          o.max_distance =
              args->max_distance > 0 ? args->max_distance : dmax + 2 * args->voxel_size;
          const auto grid = distance_grid(*pd, g, o).output;
          bar.stage("contouring");
          surface = offset_surfaces(*grid, args->distances).output;
        } else {
          for (int a = 0; a < 3; ++a) {
            if (dims[a] < 2) throw Error("--dims: need at least 2 samples along every axis");
          }
          const GridSpec g = GridSpec::from_bounds(b, dims);
          const double h = std::max({g.spacing.x, g.spacing.y, g.spacing.z});
          o.max_distance = args->max_distance > 0 ? args->max_distance : dmax + 2 * h;
          ImageData img = distance_image(*pd, g, o).output;
          if (!args->no_cap) cap_boundary(img, o.max_distance);
          bar.stage("contouring");
          surface = offset_surfaces(img, args->distances).output;
        }
      } else {
        throw Error("offset: " + args->in + " is " + std::string(dataset_type_name(ds)) +
                    "; give polygonal data or a distance field (image data, .vdb)");
      }
    }
    const double ms = elapsed_ms(t0);
    bar.stage("connectivity");
    const std::size_t components = connectivity(surface).stats.components;
    bar.stage("writing");
    write(surface, args->out);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points, {} triangles, {} connected surfaces, {:.0f} ms\n",
                 args->out, surface.num_points(), surface.polys.size(), components, ms);
    }
  });
}

void add_csg_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string op, a, b, out;
    double offset_a = 0, offset_b = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "csg",
      "Union, intersection or difference (A minus B) of two distance fields / level sets "
      "on the same grid: OpenVDB level sets (.vdb) or images (.vti .vtk)");
  cmd->add_option("operation", args->op, "union, intersection or difference")
      ->required()
      ->check(CLI::IsMember({"union", "intersection", "difference"}));
  cmd->add_option("a", args->a, "Field A (.vdb level set or image data)")->required();
  cmd->add_option("b", args->b, "Field B (same kind and grid as A)")->required();
  cmd->add_option("--offset-a", args->offset_a,
                  "Offset A first by this distance (makes an unsigned distance field a solid)");
  cmd->add_option("--offset-b", args->offset_b, "Offset B first by this distance");
  cmd->add_option("-o,--output", args->out,
                  "Output: a field of A's kind (.vdb, .vti), or its zero surface (.vtp .ply ...)")
      ->required();
  cmd->footer(
      "Fields are negative inside. Unsigned distance fields become solids with --offset-a/-b.\n"
      "Examples:\n"
      "  isoforge distance point.vtp -m 0.8 --voxel-size 0.02 -b -1.5 1.5 -1 1 -1 1 -o p.vdb\n"
      "  isoforge distance line.vtp  -m 0.8 --voxel-size 0.02 -b -1.5 1.5 -1 1 -1 1 -o l.vdb\n"
      "  isoforge csg union p.vdb l.vdb --offset-a 0.5 --offset-b 0.25 -o union.vtp\n"
      "  isoforge csg difference a.vti b.vti -o a_minus_b.vti");
  cmd->callback([args, &ctx] {
    const CsgOperation op = csg_operation_from_name(args->op);
    const FileFormat out_format = format_from_path(args->out);
    const bool out_field = out_format == FileFormat::Vdb || out_format == FileFormat::VtkImageData;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    const bool sparse_a = format_from_path(args->a) == FileFormat::Vdb;
    const bool sparse_b = format_from_path(args->b) == FileFormat::Vdb;
    if (sparse_a != sparse_b) throw Error("csg: A and B must both be .vdb or both be image data");
    PolyData surface;
    if (sparse_a) {
      auto a = read_vdb_grid(args->a);
      auto b = read_vdb_grid(args->b);
      if (args->offset_a != 0 || a->getGridClass() != openvdb::GRID_LEVEL_SET)
        offset_in_place(*a, args->offset_a);
      if (args->offset_b != 0 || b->getGridClass() != openvdb::GRID_LEVEL_SET)
        offset_in_place(*b, args->offset_b);
      bar.stage("csg");
      csg_in_place(*a, *b, op);
      if (out_field) {
        if (out_format != FileFormat::Vdb) throw Error("csg: a sparse result is written as .vdb");
        bar.stage("writing");
        write_vdb(*a, args->out);
        bar.finish();
        if (!ctx.quiet)
          fmt::print(stderr, "wrote {}: {} active voxels\n", args->out, a->activeVoxelCount());
        return;
      }
      bar.stage("contouring");
      surface = offset_surfaces(*a, {0.0}).output;
    } else {
      const auto image_of = [](const std::string& path) {
        Dataset ds = read(path);
        if (auto* img = std::get_if<ImageData>(&ds)) return std::move(*img);
        throw Error("csg: " + path + " is " + std::string(dataset_type_name(ds)) +
                    ", not image data");
      };
      ImageData a = image_of(args->a), b = image_of(args->b);
      if (args->offset_a != 0) a = offset(a, args->offset_a);
      if (args->offset_b != 0) b = offset(b, args->offset_b);
      bar.stage("csg");
      ImageData r = csg(a, b, op);
      if (out_field) {
        if (out_format != FileFormat::VtkImageData)
          throw Error("csg: a dense result is written as .vti");
        bar.stage("writing");
        write(r, args->out);
        bar.finish();
        if (!ctx.quiet) fmt::print(stderr, "wrote {}: {} samples\n", args->out, r.num_points());
        return;
      }
      bar.stage("contouring");
      surface = offset_surfaces(r, {0.0}).output;
    }
    bar.stage("writing");
    write(surface, args->out);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points, {} triangles\n", args->out, surface.num_points(),
                 surface.polys.size());
    }
  });
}

void add_attractor_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string out, volume;
    std::uint64_t steps = 10'000'000, transient = 0;
    std::vector<Index> dims{200};
    std::vector<double> bounds, start{0.1, 0.1, 0.1};
    double value = 50, step = 0.01, sigma = 10, rho = 28, beta = 8.0 / 3.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "attractor",
      "The Lorenz strange attractor (Fig. 1.25): RK4 trajectory, visits counted per "
      "voxel, marching cubes at a visit value");
  cmd->add_option("-n,--steps", args->steps, "Integration steps (default 10000000)");
  cmd->add_option("--transient", args->transient, "Steps integrated before counting (default 0)");
  cmd->add_option("-d,--dims", args->dims, "Samples per axis: N or NX NY NZ (default 200)")
      ->expected(1, 3);
  cmd->add_option("-v,--value", args->value, "Contour value in visits (default 50)");
  cmd->add_option("--step", args->step, "Time step h (default 0.01)");
  cmd->add_option("--start", args->start, "Start point X Y Z (default 0.1 0.1 0.1)")->expected(3);
  cmd->add_option("-b,--bounds", args->bounds,
                  "Volume box: xmin xmax ymin ymax zmin zmax (default -30 30 -30 30 -10 60)")
      ->expected(6);
  cmd->add_option("--sigma", args->sigma, "Lorenz sigma (default 10)");
  cmd->add_option("--rho", args->rho, "Lorenz rho (default 28)");
  cmd->add_option("--beta", args->beta, "Lorenz beta (default 8/3)");
  cmd->add_option("--volume", args->volume, "Also write the visit counts (.vti .vtk)");
  cmd->add_option("-o,--output", args->out,
                  "Output surface (.vtp .vtk .ply .obj .off), or the counts if .vti")
      ->required();
  cmd->footer(
      "States outside the box are discarded (reported), not an error.\n"
      "Examples:\n"
      "  isoforge attractor -o lorenz.vtp                       (Fig. 1.25: 10M steps, 200^3, "
      "value 50)\n"
      "  isoforge attractor --steps 1000000 --dims 100 --value 20 -o small.ply\n"
      "  isoforge attractor --rho 99.96 --bounds -60 60 -120 120 0 200 -o rho100.vtp");
  cmd->callback([args, &ctx] {
    AttractorOptions o;
    o.lorenz = {args->sigma, args->rho, args->beta};
    o.value = args->value;
    TrajectoryOptions& t = o.trajectory;
    t.steps = args->steps;
    t.transient = args->transient;
    t.step = args->step;
    t.start = {args->start[0], args->start[1], args->start[2]};
    t.dims = parse_dims(args->dims, "--dims");
    if (!args->bounds.empty()) t.bounds = parse_bounds(args->bounds, "--bounds");
    const FileFormat format = format_from_path(args->out);
    if (!args->volume.empty()) (void)format_from_path(args->volume);
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("integrating");
    t.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    if (format == FileFormat::VtkImageData) {
      const auto [volume, d] = lorenz_density(o.lorenz, t);
      bar.stage("writing");
      write(volume, args->out);
      bar.finish();
      if (!ctx.quiet) {
        fmt::print(stderr,
                   "wrote {}: {} states counted, {} discarded outside the box, max {} visits\n",
                   args->out, d.counted, d.discarded, d.max_visits);
      }
      return;
    }
    const AttractorResult r = lorenz_attractor(o);
    const double ms = elapsed_ms(t0);
    bar.stage("writing");
    if (!args->volume.empty()) write(r.output.volume, args->volume);
    write(r.output.surface, args->out);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr,
                 "wrote {}: {} triangles at {:g} visits; {} states counted, {} discarded outside "
                 "the box, max {} visits, {:.0f} ms\n",
                 args->out, r.output.surface.polys.size(), o.value, r.stats.trajectory.counted,
                 r.stats.trajectory.discarded, r.stats.trajectory.max_visits, ms);
    }
  });
}

}  // namespace isoforge::cli
