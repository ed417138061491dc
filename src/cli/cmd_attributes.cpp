// isoforge elevation, warp, gradient and calc: attribute transformations and warping of any
// dataset.

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/calculator.hpp"
#include "isoforge/filters/elevation.hpp"
#include "isoforge/filters/gradient.hpp"
#include "isoforge/filters/warp.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {

// The formats that hold any dataset type as it is (PLY: polygonal data only).
const std::vector<FileFormat> kDatasetFormats = {
    FileFormat::VtkLegacy,   FileFormat::VtkImageData,        FileFormat::VtkStructuredGrid,
    FileFormat::VtkPolyData, FileFormat::VtkUnstructuredGrid, FileFormat::Ply};
constexpr std::string_view kDatasetExtensions = ".vtk .vti .vts .vtp .vtu, or .ply for surfaces";

Vec3 vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

CLI::Option* add_vec3_option(CLI::App& cmd, const std::string& name, std::vector<double>& v,
                             const std::string& description) {
  return cmd.add_option(name, v, description)->expected(3)->check(finite_number());
}

}  // namespace

void add_elevation_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, name = "Elevation";
    std::vector<double> low, high, range{0, 1};
    bool no_clamp = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "elevation", "Add a point scalar from each point's position along a direction "
                   "(vtkElevationFilter)");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  auto* low_opt = add_vec3_option(*cmd, "--low", args->low,
                                  "Point X Y Z where the value is the range's first (default: the "
                                  "bounds' centre at their lowest z)");
  auto* high_opt = add_vec3_option(*cmd, "--high", args->high,
                                   "Point X Y Z where the value is the range's last (default: the "
                                   "bounds' centre at their highest z)");
  cmd->add_option("--range", args->range, "Values at the low and high points: A B (default 0 1)")
      ->expected(2)
      ->check(finite_number());
  cmd->add_flag("--no-clamp", args->no_clamp,
                "Extrapolate beyond the low and high points instead of clamping to the range");
  cmd->add_option("--name", args->name, "Name of the new point array (default Elevation)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kDatasetExtensions))->required();
  cmd->footer(
      "The value is A + (B - A) t, t the position of the point projected on the line from the low\n"
      "to the high point (0 at low, 1 at high). Every array of the input is kept.\n"
      "Examples:\n"
      "  isoforge elevation data/bunny.ply -o bunny_height.vtp\n"
      "  isoforge elevation data/office.binary.vtk --low 0 0 0 --high 0 0 2.7 --range 0 100 -o office.vts\n"
      "  isoforge elevation data/post.vtk --low 0 0 0 --high 1 0 0 --no-clamp --name x -o post.vtu");
  cmd->callback([args, &ctx, low_opt, high_opt, q_opt] {
    (void)output_format(args->out, kDatasetFormats, kDatasetExtensions);
    require_plot3d_input(q_opt, args->in);
    if (args->name.empty()) throw UsageError("--name: the array needs a name");
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    Dataset ds = read_input(args->in, bar, ro);
    const Bounds b = bounds(ds);
    const Vec3 centre = b.empty() ? Vec3{} : (b.min + b.max) / 2;
    ElevationOptions o;
    o.low_point = low_opt->count() ? vec3(args->low) : Vec3{centre.x, centre.y, b.min.z};
    o.high_point = high_opt->count() ? vec3(args->high) : Vec3{centre.x, centre.y, b.max.z};
    if (!low_opt->count() && !high_opt->count() && !(b.max.z > b.min.z)) {
      throw UsageError(fmt::format("{} is flat in z: give --low and --high", args->in));
    }
    if (o.low_point == o.high_point) throw UsageError("--low and --high must be different points");
    for (int c = 0; c < 3; ++c)
      require_finite_width("--low/--high", o.low_point[c], o.high_point[c]);
    require_finite_width("--range", args->range[0], args->range[1]);
    o.range = {args->range[0], args->range[1]};
    o.clamp = !args->no_clamp;
    o.name = args->name;
    require_new_array_name(point_data(ds), o.name, "--name", args->in);
    bar.stage("elevation");
    o.progress = bar.callback();
    point_data(ds).add(elevation(ds, o), AttributeRole::Scalars);
    write_output(ds, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: point scalar '{}' from {:g} at ({:g}, {:g}, {:g}) to {:g} at ({:g}, {:g}, {:g})\n",
                 args->out, o.name, o.range[0], o.low_point.x, o.low_point.y, o.low_point.z,
                 o.range[1], o.high_point.x, o.high_point.y, o.high_point.z);
    }
  });
}

void add_warp_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, by = "vector", array, normals;
    std::vector<double> direction;
    double scale = 1;
    bool displacement = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "warp", "Move the points by a vector array, or along normals or a direction by a scalar "
              "(vtkWarpVector, vtkWarpScalar); image data becomes a structured grid");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("--by", args->by, "vector (default) or scalar")
      ->check(CLI::IsMember({"vector", "scalar"}));
  cmd->add_option("-a,--array", args->array,
                  "The point array (default: the active vectors, or scalars with --by scalar)");
  cmd->add_option("-s,--scale", args->scale, "Scale factor (default 1; negative reverses)")
      ->check(finite_number());
  auto* dir_opt = add_vec3_option(*cmd, "--direction", args->direction,
                                  "With --by scalar: move along this direction X Y Z (not zero) "
                                  "instead of the point normals");
  auto* normals_opt = cmd->add_option(
      "--normals", args->normals, "With --by scalar: the normals array (default: the active normals)");
  auto* disp_opt = cmd->add_flag(
      "--displacement", args->displacement,
      "With --by vector: also add the point scalar 'Displacement' = vector . normal, the motion "
      "along the normals (a displacement plot; needs point normals)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out,
                  "Output: " + std::string(kDatasetExtensions) + " (.vts for image data)")
      ->required();
  cmd->footer(
      "Every array of the input is kept; cells are unchanged.\n"
      "Examples:\n"
      "  isoforge warp data/blow.vtk -a displacement5 -o blow_deformed.vtu\n"
      "  isoforge warp data/office.binary.vtk --scale 0.5 -o office_warped.vts\n"
      "  isoforge warp data/office.binary.vtk --by scalar --direction 0 0 1 --scale 0.2 -o office_up.vts");
  cmd->callback([args, &ctx, dir_opt, normals_opt, disp_opt, q_opt] {
    (void)output_format(args->out, kDatasetFormats, kDatasetExtensions);
    require_plot3d_input(q_opt, args->in);
    const bool by_scalar = args->by == "scalar";
    require_meaningful(dir_opt, by_scalar, "applies to --by scalar only");
    require_meaningful(normals_opt, by_scalar, "applies to --by scalar only");
    require_meaningful(disp_opt, !by_scalar, "applies to --by vector only");
    exclude_each_other({dir_opt, normals_opt});
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    bar.stage("warping");
    Dataset out;
    std::string what;
    if (by_scalar) {
      WarpScalarOptions o;
      o.scalars = args->array;
      o.scale = args->scale;
      if (dir_opt->count()) o.direction = vec3(args->direction);
      o.normals = args->normals;
      o.progress = bar.callback();
      out = warp_by_scalar(ds, o);
      what = dir_opt->count() ? "along the direction" : "along the normals";
    } else {
      WarpVectorOptions o;
      o.vectors = args->array;
      o.scale = args->scale;
      o.progress = bar.callback();
      out = warp_by_vector(ds, o);
      if (args->displacement) {
        DisplacementOptions d;
        d.vectors = args->array;
        point_data(out).add(displacement(ds, d));
      }
      what = "by the vectors";
    }
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} ({} points) moved {} x {:g}\n", args->out,
                 dataset_type_name(out), num_points(out), what, args->scale);
    }
  });
}

void add_gradient_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, array, name = "Gradient";
    bool divergence = false, vorticity = false, no_gradient = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "gradient", "Add the gradient of a point array, and for vectors the divergence and the "
                  "vorticity (vtkGradientFilter)");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("-a,--array", args->array, "The point array (default: the active scalars)");
  auto* name_opt = cmd->add_option("--name", args->name, "Name of the gradient array (default Gradient)");
  cmd->add_flag("--divergence", args->divergence, "Also add 'Divergence' (3-component arrays)");
  cmd->add_flag("--vorticity", args->vorticity, "Also add 'Vorticity', the curl (3-component arrays)");
  cmd->add_flag("--no-gradient", args->no_gradient,
                    "Leave the gradient out (with --divergence and/or --vorticity)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kDatasetExtensions))->required();
  cmd->footer(
      "An array of N components gets a gradient of 3N (d/dx, d/dy, d/dz of each component).\n"
      "Image data and structured grids use central differences (one-sided on the boundary);\n"
      "other datasets average the derivatives of the cells around each point. Method:\n"
      "docs/algorithms/attributes.md.\n"
      "Examples:\n"
      "  isoforge gradient data/headsq/quarter.nhdr -o head_gradient.vti\n"
      "  isoforge gradient data/office.binary.vtk -a vectors --vorticity --divergence -o office.vts\n"
      "  isoforge gradient data/combxyz.bin --q data/combq.bin -a Velocity --vorticity --no-gradient -o comb.vts");
  cmd->callback([args, &ctx, name_opt, q_opt] {
    (void)output_format(args->out, kDatasetFormats, kDatasetExtensions);
    require_plot3d_input(q_opt, args->in);
    require_meaningful(name_opt, !args->no_gradient, "the gradient is left out (--no-gradient)");
    if (args->no_gradient && !args->divergence && !args->vorticity) {
      throw UsageError("--no-gradient: nothing left to compute; add --divergence or --vorticity");
    }
    if (args->name.empty()) throw UsageError("--name: the array needs a name");
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    Dataset ds = read_input(args->in, bar, ro);
    if (!args->no_gradient) require_new_array_name(point_data(ds), args->name, "--name", args->in);
    bar.stage("gradient");
    GradientOptions o;
    o.array = args->array;
    o.gradient_name = args->name;
    o.compute_gradient = !args->no_gradient;
    o.divergence = args->divergence;
    o.vorticity = args->vorticity;
    o.progress = bar.callback();
    GradientResult r = gradient(ds, o);
    std::string added;
    auto add = [&](DataArray a) {
      added += (added.empty() ? "'" : ", '") + a.name() + "'";
      point_data(ds).add(std::move(a));
    };
    if (o.compute_gradient) add(std::move(r.gradient));
    if (r.divergence) add(std::move(*r.divergence));
    if (r.vorticity) add(std::move(*r.vorticity));
    write_output(ds, args->out, bar);
    bar.finish();
    if (!ctx.quiet) fmt::print(stderr, "wrote {}: added point arrays {}\n", args->out, added);
  });
}

void add_calc_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q;
    std::vector<std::string> expressions;
    bool cells = false, single = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "calc", "Add arrays computed from expressions over a dataset's arrays and coordinates "
              "(ParaView's Calculator)");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("-e,--expression", args->expressions,
                  "NAME = EXPRESSION (repeatable; later ones may use earlier results)")
      ->required();
  cmd->add_flag("--cells", args->cells, "Evaluate over the cell arrays (one value per cell)");
  cmd->add_flag("--float", args->single, "Store results as Float32 (default Float64)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kDatasetExtensions))->required();
  cmd->footer(
      "Operands: numbers, pi, array names (\"quoted\" if they hold other characters), A[i] for\n"
      "component i, coords and coordsX/Y/Z (points only), vectors [a, b, c]. Operators + - * / ^;\n"
      "functions abs sqrt exp log log10 sin cos tan asin acos atan sinh cosh tanh floor ceil,\n"
      "min max atan2 pow, and mag norm dot cross of vectors. A scalar result has 1 component, a\n"
      "vector 3. An existing array of the same name is replaced. Method and measurements:\n"
      "docs/algorithms/calculator.md.\n"
      "Examples:\n"
      "  isoforge calc data/office.binary.vtk -e 'speed = mag(vectors)' -o office_speed.vts\n"
      "  isoforge calc data/combxyz.bin --q data/combq.bin -e 'p = Density * coordsZ' \\\n"
      "      -e 'up = dot(Momentum, [0, 0, 1]) / Density' -o comb_calc.vts\n"
      "  isoforge calc data/blow.vtk -e 'd = displacement5 - displacement0' -e 'n = mag(d)' \\\n"
      "      --float -o blow_diff.vtu");
  cmd->callback([args, &ctx, q_opt] {
    (void)output_format(args->out, kDatasetFormats, kDatasetExtensions);
    require_plot3d_input(q_opt, args->in);
    // NAME = EXPRESSION, checked before reading anything.
    std::vector<std::pair<std::string, std::string>> parts;
    for (const std::string& e : args->expressions) {
      const std::size_t eq = e.find('=');
      if (eq == std::string::npos) {
        throw UsageError("-e", fmt::format("'{}': write NAME = EXPRESSION", e));
      }
      std::string name = e.substr(0, eq);
      name.erase(0, name.find_first_not_of(" \t"));
      name.erase(name.find_last_not_of(" \t") + 1);
      if (name.empty()) throw UsageError("-e", fmt::format("'{}': the result needs a name", e));
      const std::size_t start = e.find_first_not_of(" \t", eq + 1);
      if (start == std::string::npos) {
        throw UsageError("-e", fmt::format("'{}': the expression is empty", e));
      }
      parts.emplace_back(name, e.substr(start));
    }
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    Dataset ds = read_input(args->in, bar, ro);
    CalculatorOptions o;
    o.cells = args->cells;
    o.type = args->single ? ScalarType::Float32 : ScalarType::Float64;
    std::string added;
    for (const auto& [name, expression] : parts) {
      bar.stage("calculating " + name);
      o.progress = bar.callback();
      DataArray a;
      try {
        a = calculate(ds, name, expression, o);
      } catch (const Cancelled&) {
        throw;
      } catch (const Error& e) {
        // The column counts in the expression, shown after the name.
        throw Error(fmt::format("calc: {} = '{}': {}", name, expression, e.what()));
      }
      added += fmt::format("{}'{}' ({} component{})", added.empty() ? "" : ", ", name,
                           a.components(), a.components() == 1 ? "" : "s");
      (args->cells ? cell_data(ds) : point_data(ds)).add(std::move(a));
    }
    write_output(ds, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: added {} arrays {}\n", args->out,
                 args->cells ? "cell" : "point", added);
    }
  });
}

}  // namespace isoforge::cli
