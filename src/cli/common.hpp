#pragma once
// Helpers shared by several subcommands: exit codes, usage errors, argument checks and
// conversion and small geometry/timing helpers.

#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/filters/colormap.hpp"
#include "isoforge/implicit/function.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

/// Exit codes of the isoforge command (documented in README.md and `isoforge --help`).
inline constexpr int kExitOk = 0;        ///< success (also --help, --version)
inline constexpr int kExitError = 1;     ///< the work failed: bad input file, cannot write, ...
inline constexpr int kExitUsage = 2;     ///< the command line is wrong: unknown, missing,
                                         ///< malformed, out-of-range or contradictory options
inline constexpr int kExitInternal = 3;  ///< an internal error (a bug: please report it)

/// A mistake on the command line found after parsing (a contradictory or meaningless option, a
/// bad function expression): main reports it like CLI11's own errors, with kExitUsage.
using UsageError = CLI::ValidationError;

/// CLI11 validator for `->transform()` (it rewrites the value): a decimal integer in [min, max],
/// e.g. "--steps: must be an integer >= 1, got '-5'". The value is rewritten without sign and
/// leading zeros, because CLI11 itself would read "010" as octal and wrap "-5" into a huge
/// unsigned number.
[[nodiscard]] CLI::Validator integer_in(std::int64_t min, std::int64_t max = INT64_MAX);

/// CLI11 check: a finite number (no NaN, no infinity) in [lo, hi] (`open_lo`: lo excluded), e.g.
/// "--shrink: must be a finite number in [0, 1], got 'nan'".
[[nodiscard]] CLI::Validator number_in(double lo, double hi, bool open_lo = false);
/// CLI11 check: any finite number.
[[nodiscard]] CLI::Validator finite_number();
/// CLI11 check: a finite number > 0.
[[nodiscard]] CLI::Validator positive_number();
/// CLI11 check: a finite number >= 0.
[[nodiscard]] CLI::Validator non_negative_number();

/// \throw UsageError "OPTION: WHY" when `option` was given on the command line although it does
/// nothing here (`meaningful` false), e.g. "--normals: applies to dense output only, not .vdb".
void require_meaningful(const CLI::Option* option, bool meaningful, std::string_view why);
/// \throw UsageError when two or more of `options` were given ("--a and --b exclude each other").
void exclude_each_other(std::initializer_list<const CLI::Option*> options);

/// Prints "isoforge: warning: MESSAGE" on stderr (also with --quiet: a warning is not chatter).
void warn(std::string_view message);
/// "value 5", "values 1, 2, 3" or "values 1, 2, 3, ... (100 values)", with `word` for "value".
[[nodiscard]] std::string values_text(const std::vector<double>& values, std::string_view word);
/// What an array holds, for a warning: "'Scalars' ranges 0 .. 1200" (component 0), "'F' is all
/// NaN", "'F' is empty".
[[nodiscard]] std::string range_text(const DataArray& array);

/// The format of a file named on the command line (by its extension). \throw UsageError naming
/// the path when the extension is not known.
[[nodiscard]] FileFormat format_of(const std::string& path);

/// The format of an output file, which must be one of `allowed`. \throw UsageError naming the
/// path and the `extensions` this subcommand writes (e.g. ".vtp .vtk .ply .obj .off"); Error if
/// its directory does not exist or is not writable (checked before any work). Also checks the
/// XML compression options against the format (check_xml_compression).
[[nodiscard]] FileFormat output_format(const std::string& path,
                                       const std::vector<FileFormat>& allowed,
                                       std::string_view extensions);
/// The polygonal-data formats (.vtp .vtk .ply .obj .off) and their extensions, for surfaces.
inline const std::vector<FileFormat> kSurfaceFormats = {FileFormat::VtkPolyData,
                                                        FileFormat::VtkLegacy, FileFormat::Ply,
                                                        FileFormat::Obj, FileFormat::Off};
inline constexpr std::string_view kSurfaceExtensions = ".vtp .vtk .ply .obj .off";

/// Adds "-d,--dims"-style option: N (a cube) or NX NY NZ samples, each an integer >= `min`.
CLI::Option* add_dims_option(CLI::App& cmd, const std::string& name, std::vector<Index>& dims,
                             Index min, const std::string& description);
/// Adds a "-b,--bounds" option: six finite numbers xmin xmax ymin ymax zmin zmax.
CLI::Option* add_bounds_option(CLI::App& cmd, std::vector<double>& bounds,
                               const std::string& description);

/// Adds "--q FILE": the PLOT3D solution read with a PLOT3D grid input.
CLI::Option* add_q_option(CLI::App& cmd, std::string& q);
/// \throw UsageError if --q was given but `input` is not a PLOT3D grid file.
void require_plot3d_input(const CLI::Option* q_option, const std::string& input);
/// Adds "--grid NAME": the float grid to read from an OpenVDB input.
CLI::Option* add_grid_option(CLI::App& cmd, std::string& grid);
/// \throw UsageError if --grid was given but `input` is not a .vdb file.
void require_vdb_input(const CLI::Option* grid_option, const std::string& input);

/// Adds "--compressor zlib|lz4|none", "--level N" (VTK XML output compression) and "--id-type
/// auto|int32|int64" once to every
/// subcommand of `app` that writes datasets (those with an -o/--output or `output` option, but
/// `fit`, which writes text); a subcommand that has its own --level (convert: Draco) keeps it, and
/// its value serves both. Call once, after the subcommands are added. output_format() then
/// refuses the options for a non-XML output, and write_output() applies them.
void add_xml_compression_options(CLI::App& app);
/// \throw UsageError when --compressor/--level/--id-type were given and `format` (of `path`) is
/// not VTK XML, when --level is out of the compressor's range, or is given with --compressor none.
void check_xml_compression(FileFormat format, const std::string& path);
/// The --compressor/--level/--id-type given, applied to write options (unchanged when not given).
void apply_xml_compression(WriteOptions& options);
/// The first of --compressor, --level and --id-type given on the command line ("" if none).
[[nodiscard]] std::string xml_option_given();

/// `read(path, options)` reporting to `bar`'s current stage.
[[nodiscard]] Dataset read_input(const std::string& path, ProgressBar& bar,
                                 ReadOptions options = {});
/// `read_input` of a file that must hold polygonal data. \throw Error "<why>: <path> is <type>"
/// otherwise, e.g. why = "decimate: only polygonal data can be decimated".
[[nodiscard]] PolyData read_polydata(const std::string& path, ProgressBar& bar,
                                     std::string_view why, ReadOptions options = {});
/// `write(ds, path, options)` as the stage "writing" of `bar`.
/// The viewer's files (index.html and three.js): $ISOFORGE_VIEWER_DIR, else
/// ../share/isoforge/viewer from the program's directory (the layout of both the build tree and
/// an install). Empty when they are not there; `looked_in` is then the place searched ("?" when
/// the program's directory is unknown), for messages.
[[nodiscard]] std::filesystem::path find_viewer_dir(std::string& looked_in);

void write_output(DatasetRef ds, const std::filesystem::path& path, ProgressBar& bar,
                  WriteOptions options = {});

/// The function expression given to `option` (see docs/implicit.md). \throw UsageError naming
/// the option, the column and the problem.
[[nodiscard]] ImplicitFunction parse_function(const std::string& expression, const char* option);

/// Value `index` of an option's string values: a finite number. \throw UsageError naming
/// `option` and `what`.
double finite_at(const std::vector<std::string>& v, std::size_t index, const char* option,
                 const char* what);
/// Value `index`: an integer ≥ min (and at most 2^31 − 1). \throw UsageError.
Index integer_at(const std::vector<std::string>& v, std::size_t index, const char* option,
                 const char* what, Index min);
/// Values first .. first + 2: a finite point. \throw UsageError.
Vec3 vec_at(const std::vector<std::string>& v, std::size_t first, const char* option,
            const char* what);

/// "--bounds xmin xmax ymin ymax zmin zmax" → Bounds: finite, min ≤ max (min < max along every
/// axis with `solid`, for a box that must have a volume). \throw UsageError naming `option`.
Bounds parse_bounds(const std::vector<double>& values, const char* option, bool solid = false);
/// "--dims N" or "--dims NX NY NZ" → Dims. \throw UsageError naming `option`.
Dims parse_dims(const std::vector<Index>& values, const char* option);

/// `GridSpec::from_bounds(bounds, dims)`. \throw UsageError naming --bounds/--dims when they do
/// not make a grid (e.g. 64 samples along an axis of zero extent).
[[nodiscard]] GridSpec grid_from_bounds(const Bounds& bounds, const Dims& dims);

/// Refuses at once a sparse distance band that cannot fit in memory. The band's leaves are
/// estimated on a coarse grid (cells of at least 8 voxels, at most 256 a side): the cells within
/// `band` of a primitive (its box grown by `band`) are counted, each holding about 1.5 c² (2 band
/// / h + 8) voxels of band (a surface crossing it), at most c³. \throw Error "<what>: a narrow
/// band of about N voxels ... needs X; this machine has Y".
void require_band_memory(const PolyData& input, const GridSpec& grid, double band,
                         std::string_view what);

/// `b` grown by `pad` on every side.
Bounds grown(const Bounds& b, double pad);

/// "--colormap NAME": one of the colour maps (colormap_names()), viridis by default.
CLI::Option* add_colormap_option(CLI::App& cmd, std::string& map);
/// \throw Error when `attributes` (the input's) already hold an array `name`, which the new array
/// would replace: the commands keep every array of their input.
void require_new_array_name(const Attributes& attributes, const std::string& name,
                            const char* option, const std::string& input);

/// \throw UsageError naming `option` when `hi - lo` overflows a double (±1e308 given as a range):
/// every use of a range divides by its width or steps along it.
void require_finite_width(const char* option, double lo, double hi);

/// A colour-map range option `name` taking MIN MAX (two finite numbers).
CLI::Option* add_color_range_option(CLI::App& cmd, const std::string& name,
                                    std::vector<double>& range);
/// The range given to `option` (nullopt when not given). \throw UsageError naming `option` when
/// MIN is not below MAX, or when `log` and MIN is not positive.
std::optional<std::array<double, 2>> parse_color_range(const std::vector<double>& range,
                                                       const char* option, bool log = false);

/// "--color-by ARRAY [--colormap NAME] [--color-range MIN MAX]" of the subcommands that write a
/// mesh: the output gets a point (or cell) array "Colors" of 8-bit RGB (isoforge colormap does
/// the rest). The range option is --color-range because contour's --range means isovalues.
struct ColorBy {
  std::string array;            ///< "" = no colouring
  std::string map = "viridis";  ///< --colormap
  std::vector<double> range;    ///< --color-range (empty: the output's own range)
  CLI::Option* map_option = nullptr;
  CLI::Option* range_option = nullptr;
};
/// Adds the three options to `cmd`, filling `color_by`.
void add_color_by_options(CLI::App& cmd, ColorBy& color_by);
/// Checks them before any work. \throw UsageError for --colormap or --color-range without
/// --color-by, a range whose MIN is not below MAX, or an `output` format that stores no colours
/// (OBJ, OFF, OpenVDB).
void check_color_by(const ColorBy& color_by, FileFormat output);
/// After reading `input`: \throw Error naming the array and listing the arrays when --color-by
/// names none of `input`'s point arrays (nor cell arrays, unless `points_only`: the subcommand
/// drops cell data).
void require_color_array(const ColorBy& color_by, DatasetRef input, bool points_only);
/// Colours `output` by --color-by (nothing when it was not given or `output` is empty).
/// Returns what was done, for the summary ("coloured by 'T' (viridis, range 0 .. 1)"), or "".
/// \throw Error as add_colors.
std::string apply_color_by(const ColorBy& color_by, Dataset& output);
std::string apply_color_by(const ColorBy& color_by, PolyData& output);

/// Milliseconds since `t0`.
double elapsed_ms(std::chrono::steady_clock::time_point t0);

}  // namespace isoforge::cli
