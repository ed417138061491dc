// isoforge probe: sample a dataset at the points of a probe (a dataset, or a generated line,
// plane or volume of points).

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/probe.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {

/// The VTK XML format of a dataset type, and whether `format` can hold it.
bool holds(FileFormat format, std::size_t type_index) {
  static const FileFormat xml[4] = {FileFormat::VtkImageData, FileFormat::VtkStructuredGrid,
                                    FileFormat::VtkPolyData, FileFormat::VtkUnstructuredGrid};
  return format == FileFormat::VtkLegacy || format == xml[type_index];
}

}  // namespace

void add_probe_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, with;
    std::vector<std::string> line, plane;
    std::vector<Index> volume;
    double tolerance = kDefaultCellTolerance, distance_tolerance = -1,
           nil = std::numeric_limits<double>::quiet_NaN();
    std::string mask = "vtkValidPointMask";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "probe", "Sample a dataset at the points of a probe: another dataset, or a line, plane or "
               "volume of points (point data interpolated, cell data copied, a validity mask)");
  cmd->add_option("input", args->in, "Input dataset to sample (any type)")->required();
  auto* with_opt = cmd->add_option("--with", args->with,
                                   "Probe dataset file: its points and structure (and type) make "
                                   "the output");
  auto* line_opt = cmd->add_option("--line", args->line,
                                   "Line probe P0 P1 N: x0 y0 z0 x1 y1 z1 and N >= 1 points "
                                   "(output .vtp .vtk)")
                       ->expected(7)
                       ->type_name("X0 Y0 Z0 X1 Y1 Z1 N");
  auto* plane_opt =
      cmd->add_option("--plane", args->plane,
                      "Plane probe ORIGIN P1 P2 NU NV: corners origin, origin->p1 (u axis, NU >= 2 "
                      "points) and origin->p2 (v axis, NV >= 2 points); output .vtp .vtk")
          ->expected(11)
          ->type_name("OX OY OZ X1 Y1 Z1 X2 Y2 Z2 NU NV");
  auto* volume_opt = add_dims_option(*cmd, "--volume", args->volume, 1,
                                     "Volume probe: N or NX NY NZ points over the input's bounds "
                                     "(image data: output .vti .vtk)");
  cmd->add_option("-o,--output", args->out, "Output file (.vtk or the VTK XML type of the probe)")
      ->required();
  cmd->add_option("--tolerance", args->tolerance,
                  "Parametric tolerance of the inside test (default 1e-9)")
      ->check(non_negative_number());
  cmd->add_option("--distance-tolerance", args->distance_tolerance,
                  "World distance within which a point is on a line or surface cell (default "
                  "1e-6 of the input's diagonal)")
      ->check(non_negative_number());
  auto* nil_opt = cmd->add_option("--nil", args->nil,
                                  "Value of the arrays at points outside the input (default NaN; "
                                  "integer arrays 0)")
                      ->check(finite_number());
  cmd->add_option("--mask-name", args->mask,
                  "Name of the 0/1 validity array (default vtkValidPointMask)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "Exactly one of --with, --line, --plane, --volume. Points outside every cell of the input\n"
      "get NaN (or --nil) and 0 in the mask; PLOT3D blanking (IBlank) is honoured. Prints how\n"
      "many points were found. Method: docs/algorithms/probe.md.\n"
      "Examples:\n"
      "  isoforge probe data/combxyz.bin --q data/combq.bin \\\n"
      "      --plane 3.7 -2.5 25.87 3.7 2.5 25.87 3.7 -2.5 30.87 50 50 -o plane.vtp\n"
      "  isoforge probe data/combxyz.bin --q data/combq.bin --line 0 0 30 16.5 0 30 200 -o line.vtp\n"
      "  isoforge probe data/combxyz.bin --q data/combq.bin --volume 60 40 30 -o comb.vti\n"
      "  isoforge probe data/post.vtk --plane -2.8 -2.8 0.5 2.8 -2.8 0.5 -2.8 2.8 0.5 80 80 \\\n"
      "      --nil -1 -o post_plane.vtk\n"
      "  isoforge probe data/combxyz.bin --q data/combq.bin --with data/combxyz.bin -o self.vts");
  cmd->callback([args, &ctx, with_opt, line_opt, plane_opt, volume_opt, nil_opt, q_opt] {
    exclude_each_other({with_opt, line_opt, plane_opt, volume_opt});
    if (with_opt->count() + line_opt->count() + plane_opt->count() + volume_opt->count() == 0) {
      throw UsageError("probe: give one of --with, --line, --plane, --volume");
    }
    require_plot3d_input(q_opt, args->in);
    if (args->mask.empty()) throw UsageError("--mask-name", "the mask array needs a name");
    const FileFormat format = format_of(args->out);
    if (line_opt->count() || plane_opt->count()) {
      if (!holds(format, 2)) throw UsageError("-o", "a line or plane probe is polygonal data: write .vtp or .vtk, not " + args->out);
    } else if (volume_opt->count()) {
      if (!holds(format, 0)) throw UsageError("-o", "a volume probe is image data: write .vti or .vtk, not " + args->out);
    }
    // The probe from the command line, checked before reading anything.
    std::optional<Dataset> generated;
    if (line_opt->count()) {
      const auto& v = args->line;
      const Vec3 p0 = vec_at(v, 0, "--line", "P0"), p1 = vec_at(v, 3, "--line", "P1");
      const Index n = integer_at(v, 6, "--line", "N", 1);
      if (p0 == p1 && n > 1) {
        throw UsageError("--line", "P0 equals P1: N points would all be the same (give N = 1)");
      }
      generated = probe_line(p0, p1, n);
    } else if (plane_opt->count()) {
      const auto& v = args->plane;
      const Vec3 o = vec_at(v, 0, "--plane", "ORIGIN"), p1 = vec_at(v, 3, "--plane", "P1"),
                 p2 = vec_at(v, 6, "--plane", "P2");
      const Index nu = integer_at(v, 9, "--plane", "NU", 2), nv = integer_at(v, 10, "--plane", "NV", 2);
      const Vec3 u = p1 - o, w = p2 - o;
      if (!(norm(cross(u, w)) > 1e-12 * std::max(dot(u, u), dot(w, w)))) {
        throw UsageError("--plane", "degenerate plane: ORIGIN->P1 and ORIGIN->P2 are parallel or of zero length");
      }
      generated = probe_plane(o, p1, p2, nu, nv);
    }
    std::optional<Dims> volume_dims;
    if (volume_opt->count()) volume_dims = parse_dims(args->volume, "--volume");
    (void)output_format(args->out, {format}, "");  // the directory is writable

    ProbeOptions o;
    o.tolerance = args->tolerance;
    o.distance_tolerance = args->distance_tolerance;
    if (nil_opt->count()) o.nil_value = args->nil;
    o.mask_name = args->mask;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset input = read_input(args->in, bar, ro);
    if (with_opt->count()) {
      generated = read_input(args->with, bar);
      if (!holds(format, generated->index())) {
        throw UsageError("-o", fmt::format("the probe {} is {}: {} cannot hold it (write .vtk or "
                                           "its VTK XML type)",
                                           args->with, dataset_type_name(*generated), args->out));
      }
    } else if (volume_dims) {
      generated = probe_volume(bounds(input), *volume_dims);
    }
    bar.stage("probing");
    o.progress = bar.callback();
    const auto [output, stats] = probe(input, *generated, o);
    write_output(output, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} ({} points), {} found in the input ({:.1f} %){}\n",
                 args->out, dataset_type_name(output), stats.points, stats.found,
                 stats.points ? 100.0 * double(stats.found) / double(stats.points) : 0.0,
                 stats.blanked ? fmt::format(", {} blanked cells skipped", stats.blanked) : "");
    }
  });
}

}  // namespace isoforge::cli
