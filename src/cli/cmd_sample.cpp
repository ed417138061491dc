// isoforge sample: an implicit function sampled onto a dense volume (.vti/.vtk) or into an
// OpenVDB narrow-band level set (.vdb).

#include <fmt/core.h>

#include <cmath>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

namespace {
// OpenVDB's index coordinates are 32-bit signed integers.
constexpr double kMaxVdbSamples = 2147483647.0;
}  // namespace

void add_sample_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string function, out;
    std::vector<double> bounds;
    std::vector<Index> dims{64};
    bool normals = false;
    double half_width = 3, voxel_size = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("sample", "Sample an implicit function onto a volume (.vti, .vtk) "
                                           "or into an OpenVDB narrow-band level set (.vdb)");
  cmd->add_option("-f,--function", args->function, "Function expression (see docs/implicit.md)")->required();
  add_bounds_option(*cmd, args->bounds, "Sampled box: xmin xmax ymin ymax zmin zmax")->required();
  auto* dims_opt = add_dims_option(*cmd, "-d,--dims", args->dims, 1,
                                   "Samples per axis: N or NX NY NZ (default 64)");
  auto* normals_opt =
      cmd->add_flag("--normals", args->normals, "Dense: also store unit gradients as point normals");
  auto* half_width_opt =
      cmd->add_option("--half-width", args->half_width,
                      "Sparse: narrow band half width in voxels (default 3)")
          ->check(positive_number());
  auto* voxel_size_opt =
      cmd->add_option("--voxel-size", args->voxel_size,
                      "Sparse: voxel size (default: the largest extent / (largest dims - 1))")
          ->check(positive_number());
  cmd->add_option("-o,--output", args->out, "Output: .vti or .vtk (dense), .vdb (sparse)")->required();
  cmd->footer(
      "Examples:\n"
      "  isoforge sample -f 'sphere(r=1)' -b -1.5 1.5 -1.5 1.5 -1.5 1.5 -d 64 -o sphere.vti\n"
      "  isoforge sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 256 -o icecream.vti\n"
      "  isoforge sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 1024 -o icecream.vdb\n"
      "  isoforge sample -f 'difference(box(), sphere(r=1.2))' -b -1 1 -1 1 -1 1 -o cut.vti");
  cmd->callback([args, &ctx, dims_opt, normals_opt, half_width_opt, voxel_size_opt] {
    const FileFormat format =
        output_format(args->out, {FileFormat::VtkImageData, FileFormat::VtkLegacy, FileFormat::Vdb},
                      ".vti .vtk (dense) or .vdb (sparse)");
    const bool sparse = format == FileFormat::Vdb;
    require_meaningful(normals_opt, !sparse, "applies to dense output (.vti .vtk), not to .vdb");
    require_meaningful(half_width_opt, sparse, "applies to sparse output (.vdb) only");
    require_meaningful(voxel_size_opt, sparse, "applies to sparse output (.vdb) only");
    exclude_each_other({dims_opt, voxel_size_opt});
    const ImplicitFunction f = parse_function(args->function, "--function");
    const Bounds b = parse_bounds(args->bounds, "--bounds");
    const Dims dims = parse_dims(args->dims, "--dims");
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    if (sparse) {
      double h = args->voxel_size;
      if (voxel_size_opt->count() == 0) {
        int axis = 0;
        for (int a = 1; a < 3; ++a) if (dims[a] > dims[axis]) axis = a;
        if (dims[axis] < 2) throw UsageError("--dims: need at least 2 samples along some axis");
        h = (b.max[axis] - b.min[axis]) / static_cast<double>(dims[axis] - 1);
        if (!(h > 0)) {
          throw UsageError("--bounds: the box has zero extent along axis " + std::to_string(axis) +
                           ", the axis with the most samples");
        }
      }
      GridSpec g;
      g.origin = b.min;
      g.spacing = {h, h, h};
      for (int a = 0; a < 3; ++a) {
        const double n = std::ceil((b.max[a] - b.min[a]) / h - 1e-9) + 1;
        if (!(n < kMaxVdbSamples)) {
          throw UsageError(fmt::format(
              "--voxel-size: the box spans {:.3g} voxels along axis {}; OpenVDB indices stop at "
              "{}", n, a, kMaxVdbSamples));
        }
        g.dims[a] = static_cast<Index>(n);
      }
      bar.stage("sampling");
      const VdbGridStats stats =
          vdb_commands().sample(f, g, args->half_width, args->out, bar, [&](const VdbGridStats& s) {
            if (s.active_voxels != 0) return;
            const Interval iv = f.bound(b);
            bar.finish();
            warn(
                fmt::format("sample: the band is empty: F = 0 does not come within {:g} voxels "
                            "of the box (F is bounded by {:g} .. {:g} over it)",
                            args->half_width, iv.lo, iv.hi));
          });
      bar.finish();
      if (!ctx.quiet) {
        fmt::print(stderr, "wrote {}: {} x {} x {} voxels of size {:g}, {} active, {:.1f} MB tree\n",
                   args->out, g.dims[0], g.dims[1], g.dims[2], h, stats.active_voxels,
                   static_cast<double>(stats.memory_bytes) / 1e6);
      }
      return;
    }
    SampleOptions o;
    o.normals = args->normals;
    bar.stage("sampling");
    o.progress = bar.callback();
    const ImageData img = sample_image(f, grid_from_bounds(b, dims), o);
    write_output(img, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      auto [lo, hi] = img.point_data.scalars()->range();
      fmt::print(stderr, "wrote {}: {} x {} x {} samples, F in [{:.6g}, {:.6g}]\n", args->out,
                 dims[0], dims[1], dims[2], lo, hi);
    }
  });
}

}  // namespace isoforge::cli
