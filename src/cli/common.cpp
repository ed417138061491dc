#include "common.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <type_traits>

#include "isoforge/core/error.hpp"
#include "isoforge/core/memory.hpp"
#include "isoforge/implicit/parse.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/vtk_xml.hpp"

namespace isoforge::cli {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

CLI::Validator integer_in(std::int64_t min, std::int64_t max) {
  const std::string range =
      max == INT64_MAX ? fmt::format(">= {}", min) : fmt::format("in [{}, {}]", min, max);
  return CLI::Validator(
      [min, max, range](std::string& s) -> std::string {
        const char* b = s.data();
        const char* e = b + s.size();
        if (b != e && *b == '+') ++b;
        std::int64_t v = 0;
        const auto [p, ec] = std::from_chars(b, e, v);
        if (b == e || p != e || ec == std::errc::invalid_argument) {
          return fmt::format("must be an integer {}, got '{}'", range, s);
        }
        if (ec == std::errc::result_out_of_range || v < min || v > max) {
          return fmt::format("must be an integer {}, got {}", range, s);
        }
        s = std::to_string(v);  // what CLI11 converts: no sign, no leading zeros
        return {};
      },
      max == INT64_MAX ? fmt::format(">={}", min) : fmt::format("{}..{}", min, max));
}

CLI::Validator number_in(double lo, double hi, bool open_lo) {
  std::string range;
  if (lo == -kInf && hi == kInf) {
    range = "";
  } else if (hi == kInf) {
    range = fmt::format(" {} {}", open_lo ? ">" : ">=", lo);
  } else {
    range = fmt::format(" in {}{}, {}]", open_lo ? "(" : "[", lo, hi);
  }
  return CLI::Validator(
      [lo, hi, open_lo, range](std::string& s) -> std::string {
        const char* b = s.data();
        const char* e = b + s.size();
        if (b != e && *b == '+') ++b;
        double v = 0;
        const auto [p, ec] = std::from_chars(b, e, v);
        const bool parsed = b != e && p == e && ec == std::errc();
        if (!parsed || !std::isfinite(v) || v < lo || v > hi || (open_lo && v == lo)) {
          return fmt::format("must be a finite number{}, got '{}'", range, s);
        }
        return {};
      },
      range.empty() ? "finite" : range.substr(1));
}

CLI::Validator finite_number() {
  return number_in(-kInf, kInf);
}
CLI::Validator positive_number() {
  return number_in(0, kInf, true);
}
CLI::Validator non_negative_number() {
  return number_in(0, kInf);
}

void require_meaningful(const CLI::Option* option, bool meaningful, std::string_view why) {
  if (option->count() > 0 && !meaningful) throw UsageError(option->get_name(), std::string(why));
}

void exclude_each_other(std::initializer_list<const CLI::Option*> options) {
  std::string given;
  int n = 0;
  for (const CLI::Option* o : options) {
    if (o->count() == 0) continue;
    given += (n++ == 0 ? "" : " and ") + o->get_name();
  }
  if (n > 1) throw UsageError(given + " exclude each other");
}

void warn(std::string_view message) {
  fmt::print(stderr, "isoforge: warning: {}\n", message);
}

std::string values_text(const std::vector<double>& values, std::string_view word) {
  constexpr std::size_t kShown = 5;
  std::string s = fmt::format("{}{}", word, values.size() == 1 ? "" : "s");
  for (std::size_t i = 0; i < values.size() && i < kShown; ++i) {
    s += fmt::format("{}{:g}", i == 0 ? " " : ", ", values[i]);
  }
  if (values.size() > kShown) s += fmt::format(", ... ({} {}s)", values.size(), word);
  return s;
}

std::string range_text(const DataArray& array) {
  if (array.tuples() == 0) return fmt::format("'{}' is empty", array.name());
  const auto [lo, hi] = array.range(0);
  if (!(lo <= hi)) return fmt::format("'{}' is all NaN", array.name());
  return fmt::format("'{}' ranges {:g} .. {:g}", array.name(), lo, hi);
}

FileFormat format_of(const std::string& path) {
  try {
    return format_from_path(path);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

FileFormat output_format(const std::string& path, const std::vector<FileFormat>& allowed,
                         std::string_view extensions) {
  const FileFormat f = format_of(path);
  if (std::find(allowed.begin(), allowed.end(), f) == allowed.end()) {
    throw UsageError(path + ": this subcommand writes " + std::string(extensions) + ", not " +
                     std::string(format_name(f)));
  }
  check_xml_compression(f, path);
  check_writable(path);  // a bad output directory fails now, not after the work
  return f;
}

namespace {

// The XML compression options of the subcommand being run (one per process). Every subcommand's
// options bind to these; `options` lists them all, to tell which were given.
struct XmlCompressionCli {
  std::string compressor;  // "" = not given
  std::int64_t level = 0;  // 0 = not given
  std::string id_type;     // "" = not given
  std::vector<const CLI::Option*> compressor_opts, level_opts, id_type_opts;
};

XmlCompressionCli& xml_cli() {
  static XmlCompressionCli x;
  return x;
}

bool given(const std::vector<const CLI::Option*>& opts) {
  return std::any_of(opts.begin(), opts.end(), [](const CLI::Option* o) { return o->count() > 0; });
}

bool is_vtk_xml(FileFormat f) {
  return f == FileFormat::VtkImageData || f == FileFormat::VtkStructuredGrid ||
         f == FileFormat::VtkPolyData || f == FileFormat::VtkUnstructuredGrid;
}

}  // namespace

void add_xml_compression_options(CLI::App& app) {
  XmlCompressionCli& x = xml_cli();
  for (CLI::App* cmd : app.get_subcommands({})) {
    const bool writes = cmd->get_option_no_throw("--output") != nullptr ||
                        cmd->get_option_no_throw("output") != nullptr;
    if (!writes || cmd->get_name() == "fit") continue;  // fit -o writes a function as text
    x.compressor_opts.push_back(
        cmd->add_option("--compressor", x.compressor,
                        "VTK XML output: compressor of the binary data: zlib (default; opens "
                        "everywhere), lz4 (several times faster, larger; VTK 8.2+) or none")
            ->check(CLI::IsMember({"zlib", "lz4", "none"})));
    x.id_type_opts.push_back(
        cmd->add_option("--id-type", x.id_type,
                        "VTK XML output: integer type of the cell connectivity and offsets: auto "
                        "(default: Int32 when every id fits, half the bytes), int32 (an error when "
                        "they do not fit) or int64 (as VTK writes by default)")
            ->check(CLI::IsMember({"auto", "int32", "int64"})));
    if (const CLI::Option* own = cmd->get_option_no_throw("--level")) {
      x.level_opts.push_back(own);  // convert: Draco's --level, read through xml_level()
      continue;
    }
    x.level_opts.push_back(cmd->add_option("--level", x.level,
                                           "VTK XML output: compression level 1 (fastest) to 12 "
                                           "(smallest); default 5 for zlib, 1 for lz4")
                               ->transform(integer_in(1, 12)));
  }
}

std::string xml_option_given() {
  const XmlCompressionCli& x = xml_cli();
  if (given(x.compressor_opts)) return "--compressor";
  if (given(x.level_opts)) return "--level";
  if (given(x.id_type_opts)) return "--id-type";
  return {};
}

namespace {

// The level given: ours, or the value of a subcommand's own --level option.
std::optional<std::int64_t> xml_level() {
  for (const CLI::Option* o : xml_cli().level_opts) {
    if (o->count() > 0) return o->as<std::int64_t>();
  }
  return std::nullopt;
}

}  // namespace

void check_xml_compression(FileFormat format, const std::string& path) {
  const XmlCompressionCli& x = xml_cli();
  const std::string option = xml_option_given();
  if (option.empty()) return;
  if (!is_vtk_xml(format)) {
    throw UsageError(option + ": applies to VTK XML output (.vti .vts .vtp .vtu) only, not " +
                     path);
  }
  const bool level = given(x.level_opts);
  if (level) {
    if (x.compressor == "none") {
      throw UsageError("--level: there is no level without compression (--compressor none)");
    }
    const auto l = xml_level();
    const auto [lo, hi] = vtk_xml_level_range(x.compressor == "lz4" ? VtkXmlCompressor::Lz4
                                                                     : VtkXmlCompressor::Zlib);
    if (*l < lo || *l > hi) {
      throw UsageError(fmt::format("--level: {} output takes levels {} to {}, got {}",
                                   x.compressor.empty() ? "zlib" : x.compressor, lo, hi, *l));
    }
  }
}

void apply_xml_compression(WriteOptions& options) {
  const XmlCompressionCli& x = xml_cli();
  if (!x.compressor.empty() && given(x.compressor_opts)) {
    options.compress = x.compressor != "none";
    if (x.compressor == "lz4") options.xml_compressor = VtkXmlCompressor::Lz4;
    if (x.compressor == "zlib") options.xml_compressor = VtkXmlCompressor::Zlib;
  }
  if (const auto l = xml_level()) options.xml_level = static_cast<int>(*l);
  if (given(x.id_type_opts)) {
    options.xml_id_type = x.id_type == "int32"   ? VtkXmlIdType::Int32
                          : x.id_type == "int64" ? VtkXmlIdType::Int64
                                                 : VtkXmlIdType::Auto;
  }
}

CLI::Option* add_dims_option(CLI::App& cmd, const std::string& name, std::vector<Index>& dims,
                             Index min, const std::string& description) {
  return cmd.add_option(name, dims, description)->expected(1, 3)->transform(integer_in(min));
}

CLI::Option* add_bounds_option(CLI::App& cmd, std::vector<double>& bounds,
                               const std::string& description) {
  return cmd.add_option("-b,--bounds", bounds, description)->expected(6)->check(finite_number());
}

CLI::Option* add_q_option(CLI::App& cmd, std::string& q) {
  return cmd.add_option("--q", q, "PLOT3D solution (Q) file to read with a PLOT3D grid input");
}

void require_plot3d_input(const CLI::Option* q_option, const std::string& input) {
  require_meaningful(q_option, format_of(input) == FileFormat::Plot3d,
                     "a PLOT3D solution goes with a PLOT3D grid input (.xyz .bin), not " + input);
}

CLI::Option* add_grid_option(CLI::App& cmd, std::string& grid) {
  return cmd.add_option("--grid", grid, "OpenVDB input: name of the float grid to read");
}

void require_vdb_input(const CLI::Option* grid_option, const std::string& input) {
  require_meaningful(grid_option, format_of(input) == FileFormat::Vdb,
                     "names a grid of an OpenVDB input (.vdb), not of " + input);
}

Dataset read_input(const std::string& path, ProgressBar& bar, ReadOptions options) {
  options.progress = bar.callback();
  return read(path, options);
}

PolyData read_polydata(const std::string& path, ProgressBar& bar, std::string_view why,
                       ReadOptions options) {
  Dataset ds = read_input(path, bar, std::move(options));
  if (auto* pd = std::get_if<PolyData>(&ds)) return std::move(*pd);
  const auto colon = why.find(": ");
  throw Error(fmt::format("{}: {} is {}; {}", why.substr(0, colon), path, dataset_type_name(ds),
                          colon == std::string_view::npos ? why : why.substr(colon + 2)));
}

void write_output(DatasetRef ds, const std::filesystem::path& path, ProgressBar& bar,
                  WriteOptions options) {
  // A result whose coordinates overflowed (an option's value near the largest double, e.g. a
  // glyph factor of 1e308) could be read back by no reader: refused, nothing written.
  ds.visit([&](const auto& d) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(d)>, ImageData>) {
      if (const std::size_t bad = d.points.first_non_finite(); bad < d.points.size()) {
        const Vec3 p = d.points[bad];
        throw Error(fmt::format(
            "{}: not written: point {} of the result is ({:g}, {:g}, {:g}): it was moved or "
            "made from a NaN or infinite input value, or an option's value overflows",
            path.string(), bad, p.x, p.y, p.z));
      }
    }
  });
  bar.stage("writing");
  options.progress = bar.callback();
  if (is_vtk_xml(format_from_path(path))) apply_xml_compression(options);
  write(ds, path, options);
}

ImplicitFunction parse_function(const std::string& expression, const char* option) {
  try {
    return parse_implicit(expression);
  } catch (const Error& e) {
    throw UsageError(option, e.what());
  }
}

double finite_at(const std::vector<std::string>& v, std::size_t index, const char* option,
                 const char* what) {
  const std::string& s = v[index];
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  double x = 0;
  const auto [p, ec] = std::from_chars(b, e, x);
  if (b == e || p != e || ec != std::errc() || !std::isfinite(x)) {
    throw UsageError(option, fmt::format("{} must be a finite number, got '{}'", what, s));
  }
  return x;
}

Index integer_at(const std::vector<std::string>& v, std::size_t index, const char* option,
                 const char* what, Index min) {
  const std::string& s = v[index];
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  std::int64_t x = 0;
  const auto [p, ec] = std::from_chars(b, e, x);
  if (b == e || p != e || ec != std::errc() || x < min || x > INT32_MAX) {
    throw UsageError(option, fmt::format("{} must be an integer >= {}, got '{}'", what, min, s));
  }
  return x;
}

Vec3 vec_at(const std::vector<std::string>& v, std::size_t first, const char* option,
            const char* what) {
  return {finite_at(v, first, option, what), finite_at(v, first + 1, option, what),
          finite_at(v, first + 2, option, what)};
}

std::filesystem::path find_viewer_dir(std::string& looked_in) {
  namespace fs = std::filesystem;
  fs::path dir;
  if (const char* env = std::getenv("ISOFORGE_VIEWER_DIR"); env && *env) {
    dir = env;
  } else {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) dir = exe.parent_path().parent_path() / "share" / "isoforge" / "viewer";
  }
  looked_in = dir.empty() ? std::string("?") : dir.string();
  std::error_code ec;
  if (!dir.empty() && fs::is_regular_file(dir / "index.html", ec) &&
      fs::is_regular_file(dir / "three" / "build" / "three.module.js", ec)) {
    return dir;
  }
  return {};
}

Bounds parse_bounds(const std::vector<double>& b, const char* option, bool solid) {
  if (b.size() != 6)
    throw UsageError(std::string(option) + ": needs 6 numbers: xmin xmax ymin ymax zmin zmax");
  Bounds out;
  out.min = {b[0], b[2], b[4]};
  out.max = {b[1], b[3], b[5]};
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(out.min[a]) || !std::isfinite(out.max[a])) {
      throw UsageError(fmt::format("{}: {} {:g} .. {:g}: the bounds must be finite", option,
                                   kAxis[a], out.min[a], out.max[a]));
    }
    if (out.min[a] > out.max[a]) {
      throw UsageError(fmt::format("{}: {} {:g} .. {:g}: min must not exceed max", option, kAxis[a],
                                   out.min[a], out.max[a]));
    }
    if (!std::isfinite(out.max[a] - out.min[a])) {
      throw UsageError(fmt::format("{}: {} {:g} .. {:g} is too wide (its width overflows a double)",
                                   option, kAxis[a], out.min[a], out.max[a]));
    }
    if (solid && out.min[a] == out.max[a]) {
      throw UsageError(fmt::format("{}: {} {:g} .. {:g}: the box must have a positive extent",
                                   option, kAxis[a], out.min[a], out.max[a]));
    }
  }
  return out;
}

Dims parse_dims(const std::vector<Index>& d, const char* option) {
  if (d.size() == 1) return {d[0], d[0], d[0]};
  if (d.size() == 3) return {d[0], d[1], d[2]};
  throw UsageError(std::string(option) + ": give one number (a cube) or three");
}

GridSpec grid_from_bounds(const Bounds& bounds, const Dims& dims) {
  try {
    return GridSpec::from_bounds(bounds, dims);
  } catch (const Error& e) {
    throw UsageError("--bounds/--dims", e.what());
  }
}

void require_band_memory(const PolyData& input, const GridSpec& grid, double band,
                         std::string_view what) {
  // Bytes of one voxel of a band held in OpenVDB leaves (8³ floats, masks, node), halved fill.
  constexpr double kBytesPerVoxel = 2 * (2048.0 + 200.0) / 512.0;
  const double memory = static_cast<double>(physical_memory());
  const double voxels = static_cast<double>(grid.dims[0]) * static_cast<double>(grid.dims[1]) *
                        static_cast<double>(grid.dims[2]);
  if (memory == 0 || voxels * kBytesPerVoxel <= memory) return;  // even a full box fits
  const double h = grid.spacing.x;
  Index c = 8;  // coarse cell side, voxels
  for (int a = 0; a < 3; ++a) c = std::max<Index>(c, (grid.dims[a] + 255) / 256);
  Dims n{};
  for (int a = 0; a < 3; ++a) n[a] = (grid.dims[a] + c - 1) / c;
  std::vector<std::uint8_t> near(static_cast<std::size_t>(n[0] * n[1] * n[2]), 0);
  const auto mark = [&](Bounds b) {  // the coarse cells meeting b grown by the band
    Index lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double cell = h * static_cast<double>(c);
      lo[a] = std::clamp<Index>(
          static_cast<Index>(std::floor((b.min[a] - band - grid.origin[a]) / cell)), 0, n[a] - 1);
      hi[a] = std::clamp<Index>(
          static_cast<Index>(std::floor((b.max[a] + band - grid.origin[a]) / cell)), 0, n[a] - 1);
      if (b.max[a] + band < grid.origin[a] ||
          b.min[a] - band > grid.origin[a] + cell * static_cast<double>(n[a]))
        return;
    }
    for (Index k = lo[2]; k <= hi[2]; ++k)
      for (Index j = lo[1]; j <= hi[1]; ++j)
        for (Index i = lo[0]; i <= hi[0]; ++i)
          near[static_cast<std::size_t>(i + n[0] * (j + n[1] * k))] = 1;
  };
  const auto mark_ids = [&](std::span<const Index> ids, std::size_t first, std::size_t count) {
    Bounds b;
    for (std::size_t t = first; t < first + count; ++t)
      b.extend(input.points[static_cast<std::size_t>(ids[t])]);
    mark(b);
  };
  for (std::size_t v = 0; v < input.verts.size(); ++v) {
    const auto ids = input.verts.cell(v);
    for (std::size_t t = 0; t < ids.size(); ++t) mark_ids(ids, t, 1);
  }
  for (std::size_t l = 0; l < input.lines.size(); ++l) {  // segment by segment
    const auto ids = input.lines.cell(l);
    for (std::size_t t = 0; t + 1 < ids.size(); ++t) mark_ids(ids, t, 2);
  }
  for (const CellArray* cells : {&input.polys, &input.strips}) {
    for (std::size_t p = 0; p < cells->size(); ++p) {
      const auto ids = cells->cell(p);
      mark_ids(ids, 0, ids.size());
    }
  }
  const double cells = static_cast<double>(std::count(near.begin(), near.end(), 1));
  const double side = static_cast<double>(c);
  const double per_cell = std::min(side * side * side, 1.5 * side * side * (2 * band / h + 8));
  const double band_voxels = std::min(voxels, cells * per_cell);
  require_memory(band_voxels * kBytesPerVoxel,
                 fmt::format("{}: a narrow band of about {:.2g} voxels (within {:g} of the input, "
                             "voxel size {:g}) in a {} grid",
                             what, band_voxels, band, h, format_dims(grid.dims)));
}

Bounds grown(const Bounds& b, double pad) {
  Bounds r = b;
  r.min = b.min - Vec3{pad, pad, pad};
  r.max = b.max + Vec3{pad, pad, pad};
  return r;
}

CLI::Option* add_colormap_option(CLI::App& cmd, std::string& map) {
  return cmd.add_option("--colormap", map, "Colour map (default viridis; docs/algorithms/colormaps.md)")
      ->check(CLI::IsMember(colormap_names()));
}

CLI::Option* add_color_range_option(CLI::App& cmd, const std::string& name,
                                    std::vector<double>& range) {
  return cmd
      .add_option(name, range,
                  "Values mapped to the ends of the colour map: MIN MAX (default: the array's "
                  "range, NaNs ignored)")
      ->expected(2)
      ->check(finite_number());
}

void require_new_array_name(const Attributes& attributes, const std::string& name,
                            const char* option, const std::string& input) {
  if (attributes.find(name) != nullptr) {
    throw Error(
        fmt::format("{} already has an array '{}', which the new array would replace: give "
                    "{} another name",
                    input, name, option));
  }
}

void require_finite_width(const char* option, double lo, double hi) {
  if (!std::isfinite(hi - lo)) {
    throw UsageError(
        fmt::format("{}: {:g} .. {:g} is too wide (its width overflows a double)", option, lo, hi));
  }
}

std::optional<std::array<double, 2>> parse_color_range(const std::vector<double>& range,
                                                       const char* option, bool log) {
  if (range.empty()) return std::nullopt;
  require_finite_width(option, range[0], range[1]);
  if (!(range[0] < range[1])) {
    throw UsageError(fmt::format("{}: MIN must be below MAX, got {:g} {:g}", option, range[0],
                                 range[1]));
  }
  if (log && range[0] <= 0) {
    throw UsageError(fmt::format("{}: --log needs a positive range, got {:g} {:g}", option,
                                 range[0], range[1]));
  }
  return std::array{range[0], range[1]};
}

void add_color_by_options(CLI::App& cmd, ColorBy& color_by) {
  cmd.add_option("--color-by", color_by.array,
                 "Colour the output by this point (or cell) array: adds 8-bit RGB 'Colors' "
                 "(a vector is coloured by its magnitude)");
  color_by.map_option = add_colormap_option(cmd, color_by.map);
  color_by.range_option = add_color_range_option(cmd, "--color-range", color_by.range);
}

void check_color_by(const ColorBy& color_by, FileFormat output) {
  const bool on = !color_by.array.empty();
  require_meaningful(color_by.map_option, on, "applies with --color-by only");
  require_meaningful(color_by.range_option, on, "applies with --color-by only");
  (void)parse_color_range(color_by.range, "--color-range");
  if (on && (output == FileFormat::Obj || output == FileFormat::Off || output == FileFormat::Vdb)) {
    throw UsageError(fmt::format("--color-by: {} files do not store colours (write .vtp, .vtk or "
                                 ".ply)",
                                 format_name(output)));
  }
}

void require_color_array(const ColorBy& color_by, DatasetRef input, bool points_only) {
  if (color_by.array.empty() || point_data(input).has(color_by.array)) return;
  if (points_only) {
    throw Error(fmt::format("--color-by: no point array '{}' (point arrays: {})", color_by.array,
                            point_data(input).names()));
  }
  if (cell_data(input).has(color_by.array)) return;
  throw Error(fmt::format("--color-by: no array '{}' (point arrays: {}; cell arrays: {})",
                          color_by.array, point_data(input).names(),
                          cell_data(input).names()));
}

namespace {
template <class D>
std::string color_output(const ColorBy& color_by, D& output) {
  if (color_by.array.empty() || (num_points(output) == 0 && num_cells(output) == 0)) return {};
  ColormapOptions o;
  o.map = colormap_from_name(color_by.map);
  o.range = parse_color_range(color_by.range, "--color-range");
  const ColormapStats s = add_colors(output, color_by.array, o);
  return fmt::format("coloured by '{}' ({}, range {:g} .. {:g}{})", color_by.array, color_by.map,
                     s.range[0], s.range[1],
                     s.nan_count > 0 ? fmt::format(", {} NaN", s.nan_count) : std::string());
}
}  // namespace

std::string apply_color_by(const ColorBy& color_by, Dataset& output) {
  return color_output(color_by, output);
}
std::string apply_color_by(const ColorBy& color_by, PolyData& output) {
  return color_output(color_by, output);
}

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoforge::cli
