// isoforge colormap: colour an array of any dataset through a colour map, adding 8-bit RGB(A).

#include <fmt/core.h>

#include <charconv>
#include <limits>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/colormap.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {

// "R,G,B" or "R,G,B,A", integers in [0, 255] (alpha 255 when not given). \throw UsageError.
Rgba8 parse_color(const std::string& text, const char* option) {
  Rgba8 c{0, 0, 0, 255};
  std::size_t n = 0;
  const char* p = text.data();
  const char* end = p + text.size();
  bool ok = p != end;
  while (ok && p != end) {
    int v = -1;
    const auto [q, ec] = std::from_chars(p, end, v);
    ok = ec == std::errc() && q != p && v >= 0 && v <= 255 && n < 4;
    if (!ok) break;
    c[n++] = static_cast<std::uint8_t>(v);
    p = q;
    if (p != end) {
      ok = *p == ',' && p + 1 != end;
      ++p;
    }
  }
  if (!ok || n < 3) {
    throw UsageError(fmt::format("{}: expected R,G,B or R,G,B,A with integers 0..255, got '{}'",
                                 option, text));
  }
  return c;
}

}  // namespace

void add_colormap_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, array, map = "viridis", name = "Colors", nan_color, below_color,
                                    above_color;
    std::vector<double> range;
    bool log = false, magnitude = false, rgba = false;
    std::int64_t component = 0, bands = 0;
    double opacity = 1;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "colormap", "Colour an array through a colour map: adds an 8-bit RGB(A) array 'Colors' "
                  "(point or cell data, as the array) to any dataset");
  cmd->add_option("input", args->in, "Input dataset (any type)")->required();
  cmd->add_option("-a,--array", args->array,
                  "Point or cell array to colour (a scalar; a vector by its magnitude)")
      ->required();
  cmd->add_option("-o,--output", args->out,
                  "Output: .vtk .vti .vts .vtp .vtu, or .ply for surfaces")
      ->required();
  add_colormap_option(*cmd, args->map);
  add_color_range_option(*cmd, "--range", args->range);
  cmd->add_flag("--log", args->log, "Logarithmic scale (the range must be positive)");
  auto* component_opt =
      cmd->add_option("--component", args->component, "Colour component K of a vector (0-based)")
          ->transform(integer_in(0, std::numeric_limits<int>::max()));
  auto* magnitude_opt =
      cmd->add_flag("--magnitude", args->magnitude,
                    "Colour the magnitude (the default for vectors; |value| of a scalar)");
  cmd->add_option("--bands", args->bands, "N discrete colour bands instead of a continuous map")
      ->transform(integer_in(1, std::numeric_limits<int>::max()));
  cmd->add_flag("--rgba", args->rgba, "Write RGBA (4 components) instead of RGB");
  auto* opacity_opt = cmd->add_option("--opacity", args->opacity,
                                      "Alpha of the mapped colours with --rgba, in [0, 1]")
                          ->check(number_in(0, 1));
  cmd->add_option("--name", args->name, "Name of the colour array (default Colors)");
  cmd->add_option("--nan-color", args->nan_color, "Colour of NaN values: R,G,B[,A] (default 128,128,128)");
  cmd->add_option("--below-color", args->below_color,
                  "Colour of values below the range: R,G,B[,A] (default: the map's first colour)");
  cmd->add_option("--above-color", args->above_color,
                  "Colour of values above the range: R,G,B[,A] (default: the map's last colour)");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "Maps: viridis, plasma, inferno (perceptually uniform), cool-warm (diverging), rainbow\n"
      "(VTK's default, red to blue), grayscale, black-body; see docs/algorithms/colormaps.md.\n"
      "The colours go to the point data when ARRAY is a point array, else to the cell data.\n"
      "Prints the range used and the counts of NaN, below-range and above-range values.\n"
      "Examples:\n"
      "  isoforge colormap data/bunny.ply -a intensity --colormap plasma -o bunny.ply\n"
      "  isoforge colormap data/combxyz.bin --q data/combq.bin -a Density --colormap cool-warm -o comb.vts\n"
      "  isoforge colormap data/combxyz.bin --q data/combq.bin -a Velocity --bands 8 -o speed.vts\n"
      "  isoforge colormap data/post.vtk -a Pressure --log --range 0.4 1.6 --rgba --opacity 0.5 -o post.vtu\n"
      "  isoforge colormap data/fran_cut.vtk -a textureCoords --component 1 --colormap black-body \\\n"
      "      --name v_colors -o fran.vtp");
  cmd->callback([args, &ctx, component_opt, magnitude_opt, opacity_opt, q_opt] {
    // The formats that store colours (OBJ and OFF as written here do not).
    static const std::vector<FileFormat> kWritable = {
        FileFormat::VtkLegacy,   FileFormat::VtkImageData,        FileFormat::VtkStructuredGrid,
        FileFormat::VtkPolyData, FileFormat::VtkUnstructuredGrid, FileFormat::Ply};
    (void)output_format(args->out, kWritable, ".vtk .vti .vts .vtp .vtu .ply");
    require_plot3d_input(q_opt, args->in);
    exclude_each_other({component_opt, magnitude_opt});
    require_meaningful(opacity_opt, args->rgba, "applies to --rgba output only");
    if (args->name.empty()) throw UsageError("--name: the colour array needs a name");
    ColormapOptions o;
    o.map = colormap_from_name(args->map);
    o.range = parse_color_range(args->range, "--range", args->log);
    o.log_scale = args->log;
    o.source = component_opt->count() > 0 ? ColorSource::Component
               : args->magnitude          ? ColorSource::Magnitude
                                          : ColorSource::Auto;
    o.component = static_cast<int>(args->component);
    o.bands = static_cast<int>(args->bands);
    o.rgba = args->rgba;
    o.opacity = args->opacity;
    o.name = args->name;
    if (!args->nan_color.empty()) o.nan_color = parse_color(args->nan_color, "--nan-color");
    if (!args->below_color.empty()) o.below_color = parse_color(args->below_color, "--below-color");
    if (!args->above_color.empty()) o.above_color = parse_color(args->above_color, "--above-color");

    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    Dataset ds = read_input(args->in, bar, ro);
    const bool on_points = point_data(ds).has(args->array);
    require_new_array_name(on_points ? point_data(ds) : cell_data(ds), o.name, "--name", args->in);
    const ColormapStats s = add_colors(ds, args->array, o);
    write_output(ds, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: '{}' ({}, {} {} colours) from '{}' by {}{}\n", args->out,
                 o.name, o.rgba ? "RGBA" : "RGB", s.values, on_points ? "point" : "cell",
                 args->array, args->map, o.log_scale ? " (log scale)" : "");
      fmt::print(stderr, "  range {:g} .. {:g}{}; {} NaN, {} below and {} above the range\n",
                 s.range[0], s.range[1], o.range ? " (given)" : " (of the data)", s.nan_count,
                 s.below_count, s.above_count);
    }
  });
}

}  // namespace isoforge::cli
