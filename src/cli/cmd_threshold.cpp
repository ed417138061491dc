// isoforge threshold: the cells whose values of one array lie in a range (vtkThreshold).

#include <fmt/core.h>

#include <limits>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/threshold.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_threshold_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, array, q;
    std::vector<double> between;
    double above = 0, below = 0;
    std::int64_t component = 0;
    bool magnitude = false, all_points = false, any_point = false, overlap = false,
         cell_data = false, ids = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("threshold", "Extract the cells whose values of an array lie in "
                                              "a range; output is an unstructured grid");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("-a,--array", args->array, "Point or cell array to threshold")->required();
  auto* between_opt = cmd->add_option("--between", args->between, "Keep values in [LO, HI]")
                          ->expected(2)
                          ->check(finite_number());
  auto* above_opt =
      cmd->add_option("--above", args->above, "Keep values >= LO")->check(finite_number());
  auto* below_opt =
      cmd->add_option("--below", args->below, "Keep values <= HI")->check(finite_number());
  auto* all_opt = cmd->add_flag("--all-points", args->all_points,
                                "Point array: keep a cell when all its points pass (default)");
  auto* any_opt = cmd->add_flag("--any-point", args->any_point,
                                "Point array: keep a cell when at least one of its points passes");
  auto* overlap_opt = cmd->add_flag(
      "--overlap", args->overlap,
      "Point array: keep a cell when the range of its points' values meets the range");
  auto* component_opt =
      cmd->add_option("--component", args->component, "Threshold component K of a vector (0-based)")
          ->transform(integer_in(0, std::numeric_limits<int>::max()));
  auto* magnitude_opt =
      cmd->add_flag("--magnitude", args->magnitude, "Threshold the magnitude of a vector");
  cmd->add_flag("--cell-data", args->cell_data,
                "Use the cell array ARRAY even if a point array has that name");
  cmd->add_flag("--ids", args->ids, "Add OriginalPointIds / OriginalCellIds arrays");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out, "Output (.vtu or .vtk)")->required();
  cmd->footer(
      "A NaN value never passes. Without --component or --magnitude a vector's component 0 is used.\n"
      "Examples:\n"
      "  isoforge threshold data/post.vtk -a Pressure --between 0.8 1.2 -o mid.vtu\n"
      "  isoforge threshold data/combxyz.bin --q data/combq.bin -a Density --above 0.5 --any-point -o dense.vtu\n"
      "  isoforge threshold data/office.binary.vtk -a vectors --magnitude --above 0.1 -o fast.vtu\n"
      "  isoforge threshold data/ironProt.vtk -a scalars --between 200 255 --overlap --ids -o high.vtk\n"
      "  isoforge surface dense.vtu -o dense.vtp");
  cmd->callback([args, &ctx, between_opt, above_opt, below_opt, all_opt, any_opt, overlap_opt,
                 component_opt, magnitude_opt, q_opt] {
    (void)output_format(args->out, {FileFormat::VtkUnstructuredGrid, FileFormat::VtkLegacy},
                        ".vtu .vtk (an unstructured grid)");
    require_plot3d_input(q_opt, args->in);
    exclude_each_other({between_opt, above_opt, below_opt});
    exclude_each_other({all_opt, any_opt, overlap_opt});
    exclude_each_other({component_opt, magnitude_opt});
    if (between_opt->count() + above_opt->count() + below_opt->count() == 0) {
      throw UsageError("a range is required: --between LO HI, --above LO or --below HI");
    }
    if (args->array.empty()) throw UsageError("--array: the array needs a name");
    ThresholdOptions o;
    if (between_opt->count() > 0) {
      if (args->between[0] > args->between[1]) {
        throw UsageError(fmt::format("--between: LO {:g} is above HI {:g}", args->between[0],
                                     args->between[1]));
      }
      o.lower = args->between[0];
      o.upper = args->between[1];
    } else if (above_opt->count() > 0) {
      o.lower = args->above;
    } else {
      o.upper = args->below;
    }
    o.array = args->array;
    o.component = args->magnitude ? -1 : static_cast<int>(args->component);
    o.mode = args->any_point ? ThresholdMode::AnyPoint
             : args->overlap ? ThresholdMode::Overlap
                             : ThresholdMode::AllPoints;
    o.association =
        args->cell_data ? ThresholdArrayAssociation::Cells : ThresholdArrayAssociation::Auto;
    o.original_ids = args->ids;

    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    const bool on_points = !args->cell_data && point_data(ds).has(args->array);
    for (const CLI::Option* opt : {all_opt, any_opt, overlap_opt}) {
      require_meaningful(opt, on_points || !cell_data(ds).has(args->array),
                         "applies to a point array; '" + args->array + "' is cell data");
    }
    bar.stage("thresholding");
    o.progress = bar.callback();
    auto [out, stats] = threshold(ds, o);
    if (out.num_cells() == 0) {
      bar.finish();
      const Attributes& where = stats.point_array ? point_data(ds) : cell_data(ds);
      DataArray values = where.get(args->array);
      std::string text = range_text(values);
      if (values.components() > 1) {
        const auto [lo, hi] = values.range(o.component);
        text = fmt::format("'{}' {} ranges {:g} .. {:g}", args->array,
                           o.component < 0 ? std::string("magnitude")
                                           : fmt::format("component {}", o.component),
                           lo, hi);
      }
      warn(fmt::format("threshold: no cell has {} in [{:g}, {:g}]: {} over {}",
                       stats.point_array ? "its point values" : "its value", o.lower, o.upper,
                       text, args->in));
    }
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} of {} cells, {} points ({} array '{}')\n", args->out,
                 stats.cells_kept, stats.cells_in, stats.points_kept,
                 stats.point_array ? "point" : "cell", args->array);
    }
  });
}

}  // namespace isoforge::cli
