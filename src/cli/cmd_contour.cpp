// isoforge contour: isosurfaces / isolines of any dataset (and of OpenVDB grids, sparsely).

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/contour/connectivity.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

namespace {
// --range N: more isovalues than this cannot be told apart (and each costs a pass of work).
constexpr std::int64_t kMaxContourValues = 1'000'000;
}  // namespace

void add_contour_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, array, q, grid, normals = "none";
    std::vector<double> values, range, closest;
    bool flip = false, largest = false;
    std::int64_t largest_n = 0;
    ColorBy color_by;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("contour", "Isosurfaces (3D data) or isolines (2D data, surfaces) "
                                            "at one or more values; .vdb grids are contoured sparsely");
  cmd->add_option("input", args->in, "Input dataset (any type), or an OpenVDB .vdb file")->required();
  cmd->add_option("-v,--value", args->values, "Isovalue (repeat for several)")->check(finite_number());
  cmd->add_option("--range", args->range,
                  "N evenly spaced values from FIRST to LAST: FIRST LAST N (N at most " +
                      std::to_string(kMaxContourValues) + ")")
      ->expected(3)
      ->check(finite_number().application_index(0))
      ->check(finite_number().application_index(1))
      ->transform(integer_in(1, kMaxContourValues).application_index(2));
  cmd->add_option("-a,--array", args->array, "Point array to contour (default: the active scalars)");
  cmd->add_option("--normals", args->normals, "none, gradient (from the scalar field) or triangles")
      ->check(CLI::IsMember({"none", "gradient", "triangles"}));
  cmd->add_flag("--flip", args->flip,
                "Orient toward decreasing values (default: toward increasing, i.e. outward for "
                "implicit functions and distance fields; use --flip for CT-like data)");
  auto* largest_opt =
      cmd->add_flag("--largest", args->largest, "Keep only the largest connected surface");
  auto* largest_n_opt = cmd->add_option("--largest-n", args->largest_n,
                                        "Keep the N largest connected surfaces (N >= 1)")
                            ->transform(integer_in(1));
  auto* closest_opt = cmd->add_option("--closest", args->closest,
                                      "Keep the surface closest to the point X Y Z")
                          ->expected(3)
                          ->check(finite_number());
  auto* q_opt = add_q_option(*cmd, args->q);
  auto* grid_opt = add_grid_option(*cmd, args->grid);
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))->required();
  add_color_by_options(*cmd, args->color_by);
  cmd->footer(
      "Values at or above an isovalue count as inside its surface; NaN counts as below.\n"
      "Examples:\n"
      "  isoforge contour data/ironProt.vtk -v 128 --flip -o iron.vtp\n"
      "  isoforge contour data/headsq/quarter.nhdr -v 1150 --largest --flip --normals gradient -o skin.vtp\n"
      "  isoforge sample -f 'sphere(r=1)' -b -1.5 1.5 -1.5 1.5 -1.5 1.5 -d 64 -o sphere.vti\n"
      "  isoforge contour sphere.vti -v -0.25 -v 0 -v 0.25 -o shells.vtp\n"
      "  isoforge contour data/bunny.ply -a intensity --range 0.05 0.45 9 -o lines.vtp   (isolines on a surface)\n"
      "  isoforge contour data/combxyz.bin --q data/combq.bin -a Density -v 0.3 --color-by Velocity \\\n"
      "      --colormap cool-warm -o density.vtp                              (coloured by speed)\n"
      "  isoforge sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 1024 -o icecream.vdb\n"
      "  isoforge contour icecream.vdb -v 0 -o icecream.ply                  (sparse, no densifying)");
  cmd->callback([args, &ctx, largest_opt, largest_n_opt, closest_opt, q_opt, grid_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    require_vdb_input(grid_opt, args->in);
    exclude_each_other({largest_opt, largest_n_opt, closest_opt});
    check_color_by(args->color_by, format_of(args->out));
    if (!args->color_by.array.empty() && format_of(args->in) == FileFormat::Vdb) {
      throw UsageError("--color-by: the contour of an OpenVDB grid carries no arrays to colour");
    }
    ContourOptions o;
    o.values = args->values;
    if (!args->range.empty()) {
      const double first = args->range[0], last = args->range[1];
      const auto n = static_cast<std::int64_t>(args->range[2]);  // an integer (checked)
      require_finite_width("--range", first, last);
      if (first == last && n > 1) throw UsageError("--range: FIRST equals LAST, so N must be 1");
      for (std::int64_t i = 0; i < n; ++i) {
        o.values.push_back(n == 1 ? first : first + (last - first) * static_cast<double>(i) / static_cast<double>(n - 1));
      }
    }
    if (o.values.empty()) throw UsageError("give at least one value (-v VALUE or --range FIRST LAST N)");
    o.array = args->array;
    o.flip = args->flip;
    o.normals = args->normals == "gradient" ? ContourNormals::Gradient
                : args->normals == "triangles" ? ContourNormals::Triangles : ContourNormals::None;
    const int selections = (args->largest ? 1 : 0) + (args->largest_n > 0 ? 1 : 0) + (args->closest.empty() ? 0 : 1);
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    PolyData surface;
    if (format_of(args->in) == FileFormat::Vdb) {
      surface = vdb_commands().contour(args->in, args->grid, o, bar);
    } else {
      ReadOptions ro;
      ro.plot3d_q = args->q;
      const Dataset ds = read_input(args->in, bar, ro);
      require_color_array(args->color_by, ds, false);
      bar.stage("contouring");
      o.progress = bar.callback();
      surface = contour(ds, o).output;
      if (surface.num_points() == 0) {
        const DataArray* a = o.array.empty() ? point_data(ds).scalars() : point_data(ds).find(o.array);
        bar.finish();
        warn(fmt::format("contour: no surface at {}: {}", values_text(o.values, "value"),
                         a ? range_text(*a) : std::string("no point scalars")));
      }
    }
    std::size_t components = 0;
    if (selections == 1) {
      bar.stage("connectivity");
      ConnectivityOptions co;
      if (args->largest) {
        co.mode = ConnectivityMode::Largest;
      } else if (args->largest_n > 0) {
        co.mode = ConnectivityMode::LargestN;
        co.count = static_cast<std::size_t>(args->largest_n);
      } else {
        co.mode = ConnectivityMode::ClosestToPoint;
        co.point = {args->closest[0], args->closest[1], args->closest[2]};
      }
      ConnectivityResult r = connectivity(std::move(surface), co);
      components = r.stats.components;
      surface = std::move(r.output);
    }
    const std::string colored = apply_color_by(args->color_by, surface);
    write_output(surface, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points, {} cells", args->out, surface.num_points(), surface.num_cells());
      if (selections == 1) fmt::print(stderr, " (kept from {} connected pieces)", components);
      fmt::print(stderr, "\n");
      if (!colored.empty()) fmt::print(stderr, "  {}\n", colored);
    }
  });
}

}  // namespace isoforge::cli
