// isoforge subsample: every n-th point along i, j, k of image data or a structured grid, within
// a volume of interest.

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/subsample.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_subsample_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q;
    std::vector<Index> rate, voi;
    bool boundary = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "subsample", "Keep every n-th point along i, j, k of image data or a structured grid, "
                   "within a volume of interest (attributes carried)");
  cmd->add_option("input", args->in, "Input image data or structured grid")->required();
  add_dims_option(*cmd, "-r,--rate", args->rate, 1,
                  "Keep every I-th, J-th, K-th point (one value: the same along all three)")
      ->required();
  cmd->add_option("--voi", args->voi,
                  "Volume of interest in point indices, inclusive: i0 i1 j0 j1 k0 k1 (default: "
                  "all)")
      ->expected(6)
      ->transform(integer_in(0));
  auto* boundary_opt = cmd->add_flag(
      "--include-boundary", args->boundary,
      "Also keep the last point of the VOI along an axis the rate skips it (structured grids)");
  cmd->add_option("-o,--output", args->out, "Output: .vti (image data), .vts (grids) or .vtk")
      ->required();
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "The output has the input's type: image data keeps an even spacing (origin at the VOI's\n"
      "first point, spacing x rate); a grid keeps the selected points. Cell data comes from the\n"
      "input cell at each output cell's first point. Method: docs/algorithms/probe.md.\n"
      "Examples:\n"
      "  isoforge subsample data/combxyz.bin --q data/combq.bin --rate 2 2 2 -o comb_half.vts\n"
      "  isoforge subsample data/combxyz.bin --q data/combq.bin --rate 4 1 1 \\\n"
      "      --voi 0 56 0 32 12 12 --include-boundary -o comb_k12.vts\n"
      "  isoforge subsample data/ironProt.vtk --rate 3 -o iron_third.vti");
  cmd->callback([args, &ctx, boundary_opt, q_opt] {
    require_plot3d_input(q_opt, args->in);
    const FileFormat format = format_of(args->out);
    if (format != FileFormat::VtkImageData && format != FileFormat::VtkStructuredGrid &&
        format != FileFormat::VtkLegacy) {
      throw UsageError("-o", "subsample writes .vti (image data), .vts (structured grids) or "
                             ".vtk, not " + args->out);
    }
    SubsampleOptions o;
    const Dims r = parse_dims(args->rate, "--rate");
    o.rate = {r[0], r[1], r[2]};
    if (!args->voi.empty()) {
      Voi v{};
      for (std::size_t a = 0; a < 6; ++a) v[a] = args->voi[a];
      for (std::size_t a = 0; a < 3; ++a) {
        if (v[2 * a] > v[2 * a + 1]) {
          throw UsageError("--voi", fmt::format("{}0 {} > {}1 {}: the range is inverted",
                                                "ijk"[a], v[2 * a], "ijk"[a], v[2 * a + 1]));
        }
      }
      o.voi = v;
    }
    o.include_boundary = args->boundary;
    (void)output_format(args->out, {format}, "");  // the directory is writable

    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset input = read_input(args->in, bar, ro);
    const DatasetRef ref(input);
    if (!ref.get_if<ImageData>() && !ref.get_if<StructuredGrid>()) {
      throw Error(fmt::format("subsample: {} is {}: only image data and structured grids have "
                              "i, j, k to subsample",
                              args->in, dataset_type_name(input)));
    }
    const Dims dims = std::visit(
        [](const auto& d) -> Dims {
          if constexpr (requires { d.dims; }) {
            return d.dims;
          } else {
            return {};
          }
        },
        input);
    require_meaningful(boundary_opt, ref.get_if<StructuredGrid>() != nullptr,
                       "applies to structured grids only (image data stays evenly spaced)");
    if (o.voi) {
      for (std::size_t a = 0; a < 3; ++a) {
        if ((*o.voi)[2 * a + 1] >= dims[a]) {
          throw UsageError("--voi", fmt::format("{}1 {} is out of range: {} has {} points along "
                                                "{} (0..{})",
                                                "ijk"[a], (*o.voi)[2 * a + 1], args->in, dims[a],
                                                "ijk"[a], dims[a] - 1));
        }
      }
    }
    const bool image = ref.get_if<ImageData>() != nullptr;
    if (format != FileFormat::VtkLegacy &&
        (format == FileFormat::VtkImageData) != image) {
      throw UsageError("-o", fmt::format("{} is {}: write {} or .vtk, not {}", args->in,
                                         dataset_type_name(input), image ? ".vti" : ".vts",
                                         args->out));
    }
    bar.stage("subsampling");
    const Dataset out = subsample(input, o);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      const Dims od = std::visit(
          [](const auto& d) -> Dims {
            if constexpr (requires { d.dims; }) {
              return d.dims;
            } else {
              return {};
            }
          },
          out);
      fmt::print(stderr, "wrote {}: {} x {} x {} points ({}) of {} x {} x {}\n", args->out, od[0],
                 od[1], od[2], num_points(out), dims[0], dims[1], dims[2]);
    }
  });
}

}  // namespace isoforge::cli
