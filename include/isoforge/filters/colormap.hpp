#pragma once
/// \file
/// Colour maps: the values of an array — a scalar, a vector's magnitude or one component — turned
/// into 8-bit RGB or RGBA colours through a named map, over a range (given, or the data's),
/// linear or logarithmic, continuous or in bands, with colours of their own for NaN and for
/// values below and above the range. The maps, their sources and their perceptual properties:
/// docs/algorithms/colormaps.md.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/data_array.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

/// The named maps. Sequential: viridis, plasma, inferno, grayscale, black-body; diverging:
/// cool-warm; rainbow is VTK's default lookup table (hue from red to blue).
enum class Colormap : std::uint8_t {
  Viridis,    ///< matplotlib's default: dark blue - green - yellow, perceptually uniform
  Plasma,     ///< blue - magenta - yellow, perceptually uniform
  Inferno,    ///< black - red - yellow - white, perceptually uniform
  CoolWarm,   ///< Moreland's diverging map, blue - light grey - red (Msh interpolation)
  Rainbow,    ///< VTK's default: HSV hue 0 (red) to 2/3 (blue), full saturation and value
  Grayscale,  ///< black to white, linear in sRGB
  BlackBody,  ///< Moreland's black body: black - red - orange - yellow - white, L* linear
};

/// An 8-bit sRGB colour and alpha (255 = opaque).
using Rgba8 = std::array<std::uint8_t, 4>;

/// Every map, in the order of the enum.
[[nodiscard]] const std::vector<Colormap>& colormaps();
/// The name of a map: "viridis", "plasma", "inferno", "cool-warm", "rainbow", "grayscale",
/// "black-body".
[[nodiscard]] const char* to_string(Colormap map);
/// The names of every map, as `to_string` gives them.
[[nodiscard]] std::vector<std::string> colormap_names();
/// The map of a name (as `to_string` gives it). \throw Error naming `name` and listing the maps.
[[nodiscard]] Colormap colormap_from_name(std::string_view name);

/// The sRGB colour of `map` at t (clamped to [0, 1]), each component in [0, 1]: what a legend
/// draws. \throw Error if t is NaN.
[[nodiscard]] std::array<double, 3> colormap_rgb(Colormap map, double t);
/// A lookup table of `n` opaque colours of `map` at t = i / (n - 1) (t = 0.5 when n = 1), each
/// component rounded to 8 bits. \throw Error if n is 0.
[[nodiscard]] std::vector<Rgba8> colormap_table(Colormap map, std::size_t n);

/// What of each tuple is coloured.
enum class ColorSource : std::uint8_t {
  Auto,       ///< the value of a one-component array, the magnitude of a longer one
  Magnitude,  ///< the Euclidean norm of the tuple
  Component,  ///< the component `ColormapOptions::component`
};

struct ColormapOptions {
  Colormap map = Colormap::Viridis;
  /// The values mapped to the ends of the map, {min, max} in data units (min < max, finite);
  /// nullopt: the smallest and largest finite values coloured (NaNs and infinities ignored).
  std::optional<std::array<double, 2>> range = std::nullopt;
  /// Map log10 of the values (the range must be positive; values <= 0 are below it).
  bool log_scale = false;
  ColorSource source = ColorSource::Auto;
  int component = 0;  ///< with ColorSource::Component: which component (0-based)
  /// 0: continuous; N >= 1: the scaled range cut into N equal bands, band k coloured at
  /// t = k / (N - 1) (so the first and last bands take the map's end colours; N = 1: t = 0.5).
  int bands = 0;
  bool rgba = false;   ///< 4 components (RGBA) instead of 3 (RGB)
  double opacity = 1;  ///< alpha of the mapped colours in RGBA output, in [0, 1]
  /// Colour of values below the range; nullopt: the map's first colour (alpha = opacity).
  std::optional<Rgba8> below_color = std::nullopt;
  /// Colour of values above the range; nullopt: the map's last colour (alpha = opacity).
  std::optional<Rgba8> above_color = std::nullopt;
  Rgba8 nan_color = {128, 128, 128, 255};  ///< colour of NaN values (mid grey)
  std::string name = "Colors";             ///< name of the output array
};

struct ColormapStats {
  /// The range used ({min, max} of `options.range`, or of the data's finite values); both NaN
  /// when none was given and no value is finite (NaNs then take the NaN colour, -inf and +inf
  /// the below and above colours).
  std::array<double, 2> range = {0, 0};
  std::size_t values = 0;       ///< tuples coloured
  std::size_t nan_count = 0;    ///< tuples whose value (or magnitude) is NaN
  std::size_t below_count = 0;  ///< tuples below the range (or <= 0 with log scale)
  std::size_t above_count = 0;  ///< tuples above the range
};

using ColormapResult = Result<DataArray, ColormapStats>;

/// Colours every tuple of `array`: a new UInt8 array named `options.name` of 3 (RGB) or 4 (RGBA)
/// components and as many tuples. \throw Error if an option is out of range or not finite (range
/// min >= max, bands < 0, opacity outside [0, 1], component outside the array's), or log scale
/// over a range that is not positive (the message gives the range).
[[nodiscard]] ColormapResult map_colors(const DataArray& array,
                                        const ColormapOptions& options = {});

/// Colours the array named `array` of `dataset` — its point array of that name, else its cell
/// array — and adds the colours to the same attributes (point or cell data), replacing an array
/// named `options.name`. \throw Error naming `array` and listing the dataset's arrays if it has
/// none of that name; as `map_colors`.
ColormapStats add_colors(Dataset& dataset, std::string_view array,
                         const ColormapOptions& options = {});
ColormapStats add_colors(ImageData& dataset, std::string_view array,
                         const ColormapOptions& options = {});
ColormapStats add_colors(StructuredGrid& dataset, std::string_view array,
                         const ColormapOptions& options = {});
ColormapStats add_colors(PolyData& dataset, std::string_view array,
                         const ColormapOptions& options = {});
ColormapStats add_colors(UnstructuredGrid& dataset, std::string_view array,
                         const ColormapOptions& options = {});

}  // namespace isoforge
