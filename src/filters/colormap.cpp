// Colour maps: lookup tables and transfer functions from values to 8-bit colours.
//
// K. Moreland, "Diverging Color Maps for Scientific Visualization", Advances in Visual Computing
//   (ISVC 2009), LNCS 5876, 92-103: the cool-warm map and its interpolation in Msh (polar CIELAB)
//   with a white midpoint and the hue spin of unsaturated ends.
// K. Moreland, "Why We Use Bad Color Maps and What You Can Do About It", Human Vision and
//   Electronic Imaging 2016: the black-body map (control colours placed at their CIELAB lightness,
//   interpolated in CIELAB, so L* grows about linearly; decoded as his published tables are).
// S. van der Walt, N. Smith, "A Better Default Colormap for Matplotlib", SciPy 2015: viridis,
//   plasma, inferno (sampled tables in colormap_tables.cpp, CC0).
// sRGB and CIELAB conversions: IEC 61966-2-1 (sRGB transfer curve, D65 primaries), CIE 15 (L*a*b*).

#include "isoforge/filters/colormap.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "colormap_tables.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/srgb.hpp"

namespace isoforge {

namespace {

using Rgb = std::array<double, 3>;

// ---- sRGB <-> CIELAB (D65) ----


constexpr double kWhite[3] = {0.95047, 1.0, 1.08883};  // D65 reference white, Y = 1
constexpr double kDelta = 6.0 / 29;                      // CIE: the knee of L*'s cube root

double lab_f(double t) {
  return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29;
}
double lab_f_inverse(double t) {
  return t > kDelta ? t * t * t : 3 * kDelta * kDelta * (t - 4.0 / 29);
}

struct Lab {
  double l, a, b;
};

Lab rgb_to_lab(const Rgb& c) {
  const double r = srgb_to_linear(c[0]), g = srgb_to_linear(c[1]), b = srgb_to_linear(c[2]);
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  const double fx = lab_f(x / kWhite[0]), fy = lab_f(y / kWhite[1]), fz = lab_f(z / kWhite[2]);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

// Linear-light sRGB of CIE XYZ (D65), clamped per channel to the gamut, then sRGB-encoded.
Rgb xyz_to_rgb(double x, double y, double z) {
  const double r = 3.2404542 * x - 1.5371385 * y - 0.4985314 * z;
  const double g = -0.9692660 * x + 1.8760108 * y + 0.0415560 * z;
  const double b = 0.0556434 * x - 0.2040259 * y + 1.0572252 * z;
  return {linear_to_srgb(std::clamp(r, 0.0, 1.0)), linear_to_srgb(std::clamp(g, 0.0, 1.0)),
          linear_to_srgb(std::clamp(b, 0.0, 1.0))};
}

Rgb lab_to_rgb(const Lab& lab) {
  const double fy = (lab.l + 16) / 116, fx = fy + lab.a / 500, fz = fy - lab.b / 200;
  return xyz_to_rgb(kWhite[0] * lab_f_inverse(fx), kWhite[1] * lab_f_inverse(fy),
                    kWhite[2] * lab_f_inverse(fz));
}

// L*a*b* read against the D50 white and adapted to D65 (Bradford): how Moreland's published
// black-body tables decode their interpolated colours (his conversion library's default white for
// L*a*b* is D50, while his control colours were encoded against D65's). Reproducing it gives his
// tables' colours (docs/algorithms/colormaps.md).
Rgb lab_d50_to_rgb(const Lab& lab) {
  constexpr double kD50[3] = {0.96422, 1.0, 0.82521};
  const double fy = (lab.l + 16) / 116, fx = fy + lab.a / 500, fz = fy - lab.b / 200;
  const double x = kD50[0] * lab_f_inverse(fx), y = kD50[1] * lab_f_inverse(fy),
               z = kD50[2] * lab_f_inverse(fz);
  // Bradford chromatic adaptation D50 -> D65.
  return xyz_to_rgb(0.9555766 * x - 0.0230393 * y + 0.0631636 * z,
                    -0.0282895 * x + 1.0099416 * y + 0.0210077 * z,
                    0.0122982 * x - 0.0204830 * y + 1.3299098 * z);
}

Rgb bytes_to_rgb(int r, int g, int b) { return {r / 255.0, g / 255.0, b / 255.0}; }

// ---- cool-warm: Moreland's Msh interpolation ----

struct Msh {
  double m, s, h;  // magnitude (= |Lab|), saturation (angle from the L* axis), hue (radians)
};

Msh lab_to_msh(const Lab& c) {
  const double m = std::sqrt(c.l * c.l + c.a * c.a + c.b * c.b);
  return {m, m > 0 ? std::acos(std::clamp(c.l / m, -1.0, 1.0)) : 0, std::atan2(c.b, c.a)};
}
Lab msh_to_lab(const Msh& c) {
  return {c.m * std::cos(c.s), c.m * std::sin(c.s) * std::cos(c.h),
          c.m * std::sin(c.s) * std::sin(c.h)};
}

// Moreland: a saturation this small counts as unsaturated (grey); ends whose hues differ by
// more than 60 degrees get a white midpoint; the midpoint's magnitude is at least 88 (L* = 88).
constexpr double kUnsaturated = 0.05;
constexpr double kMidpointMagnitude = 88;

// The hue of an unsaturated colour of magnitude `m_unsat` next to the saturated colour `c`:
// spun away from c's hue so that the interpolation does not pass through a hue of its own.
double adjust_hue(const Msh& c, double m_unsat) {
  if (c.m >= m_unsat) return c.h;
  const double spin = c.s * std::sqrt(m_unsat * m_unsat - c.m * c.m) / (c.m * std::sin(c.s));
  return c.h > -std::numbers::pi / 3 ? c.h + spin : c.h - spin;
}

double angle_difference(double a, double b) {
  double d = std::fabs(a - b);
  while (d > std::numbers::pi) d = std::fabs(d - 2 * std::numbers::pi);
  return d;
}

Rgb diverging(const Msh& low, const Msh& high, double t) {
  Msh a = low, b = high;
  if (a.s > kUnsaturated && b.s > kUnsaturated && angle_difference(a.h, b.h) > std::numbers::pi / 3) {
    const double mid = std::max({a.m, b.m, kMidpointMagnitude});
    if (t < 0.5) {
      b = {mid, 0, 0};
      t = 2 * t;
    } else {
      a = {mid, 0, 0};
      t = 2 * t - 1;
    }
  }
  if (a.s < kUnsaturated && b.s > kUnsaturated) {
    a.h = adjust_hue(b, a.m);
  } else if (b.s < kUnsaturated && a.s > kUnsaturated) {
    b.h = adjust_hue(a, b.m);
  }
  const Msh c{a.m + t * (b.m - a.m), a.s + t * (b.s - a.s), a.h + t * (b.h - a.h)};
  return lab_to_rgb(msh_to_lab(c));
}

struct CoolWarmEnds {
  Msh cool, warm;
};
const CoolWarmEnds& cool_warm_ends() {
  // Moreland's recommended end colours (the paper's Table: sRGB 59 76 192 and 180 4 38).
  static const CoolWarmEnds ends{lab_to_msh(rgb_to_lab(bytes_to_rgb(59, 76, 192))),
                                 lab_to_msh(rgb_to_lab(bytes_to_rgb(180, 4, 38)))};
  return ends;
}

// ---- black body: control colours at their lightness, interpolated in CIELAB ----

struct LabKnot {
  double t;
  Lab lab;
};
const std::vector<LabKnot>& black_body_knots() {
  static const std::vector<LabKnot> knots = [] {
    // Moreland's control colours: black, red, orange, yellow, white.
    const Rgb colours[] = {bytes_to_rgb(0, 0, 0), bytes_to_rgb(178, 34, 34),
                           bytes_to_rgb(227, 105, 5), bytes_to_rgb(238, 210, 20),
                           bytes_to_rgb(255, 255, 255)};
    std::vector<LabKnot> k;
    for (const Rgb& c : colours) {
      const Lab lab = rgb_to_lab(c);
      k.push_back({lab.l / 100, lab});
    }
    k.front().t = 0;  // L* of black and white are 0 and 100 up to rounding: pin the ends
    k.back().t = 1;
    return k;
  }();
  return knots;
}

Rgb black_body(double t) {
  const auto& k = black_body_knots();
  std::size_t i = 1;
  while (i + 1 < k.size() && t > k[i].t) ++i;
  const double f = (t - k[i - 1].t) / (k[i].t - k[i - 1].t);
  const Lab& a = k[i - 1].lab;
  const Lab& b = k[i].lab;
  return lab_d50_to_rgb({a.l + f * (b.l - a.l), a.a + f * (b.a - a.a), a.b + f * (b.b - a.b)});
}

// ---- sampled tables, rainbow, grayscale ----

Rgb sampled(const double (&table)[colormap_tables::kSampledEntries][3], double t) {
  const double x = t * static_cast<double>(colormap_tables::kSampledEntries - 1);
  const auto i = std::min(static_cast<std::size_t>(x), colormap_tables::kSampledEntries - 2);
  const double f = x - static_cast<double>(i);
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = table[i][k] + f * (table[i + 1][k] - table[i][k]);
  return c;
}

// VTK's default lookup table: hue 0 .. 2/3, saturation 1, value 1 (HSV to RGB).
Rgb rainbow(double t) {
  const double h = t * 4;  // hue * 6 for hue = t * 2/3: sectors red-yellow-green-cyan-blue
  const auto sector = std::min(static_cast<int>(h), 3);
  const double f = h - sector;
  switch (sector) {
    case 0: return {1, f, 0};
    case 1: return {1 - f, 1, 0};
    case 2: return {0, 1, f};
    default: return {0, 1 - f, 1};
  }
}

Rgb evaluate(Colormap map, double t) {  // t in [0, 1]
  switch (map) {
    case Colormap::Viridis: return sampled(colormap_tables::kViridis, t);
    case Colormap::Plasma: return sampled(colormap_tables::kPlasma, t);
    case Colormap::Inferno: return sampled(colormap_tables::kInferno, t);
    case Colormap::CoolWarm: return diverging(cool_warm_ends().cool, cool_warm_ends().warm, t);
    case Colormap::Rainbow: return rainbow(t);
    case Colormap::Grayscale: return {t, t, t};
    case Colormap::BlackBody: return black_body(t);
  }
  return {t, t, t};
}

std::uint8_t to_byte(double c) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255));
}

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// The value of tuple i that is coloured.
struct ScalarSource {
  const DataArray& array;
  ColorSource mode;
  int component;
  [[nodiscard]] double value(std::size_t i) const {
    if (mode == ColorSource::Component) return array.get(i, component);
    double sum = 0;
    for (int c = 0; c < array.components(); ++c) {
      const double v = array.get(i, c);
      sum += v * v;
    }
    return std::sqrt(sum);  // NaN if any component is
  }
};

std::string fmt_range(double lo, double hi) { return fmt::format("[{}, {}]", lo, hi); }

}  // namespace

const std::vector<Colormap>& colormaps() {
  static const std::vector<Colormap> all = {Colormap::Viridis,  Colormap::Plasma,
                                            Colormap::Inferno,  Colormap::CoolWarm,
                                            Colormap::Rainbow,  Colormap::Grayscale,
                                            Colormap::BlackBody};
  return all;
}

const char* to_string(Colormap map) {
  switch (map) {
    case Colormap::Viridis: return "viridis";
    case Colormap::Plasma: return "plasma";
    case Colormap::Inferno: return "inferno";
    case Colormap::CoolWarm: return "cool-warm";
    case Colormap::Rainbow: return "rainbow";
    case Colormap::Grayscale: return "grayscale";
    case Colormap::BlackBody: return "black-body";
  }
  return "?";
}

std::vector<std::string> colormap_names() {
  std::vector<std::string> names;
  for (const Colormap m : colormaps()) names.emplace_back(to_string(m));
  return names;
}

Colormap colormap_from_name(std::string_view name) {
  for (const Colormap m : colormaps()) {
    if (name == to_string(m)) return m;
  }
  std::string list;
  for (const auto& n : colormap_names()) list += (list.empty() ? "" : ", ") + n;
  throw Error(fmt::format("colormap: unknown map '{}' (the maps: {})", name, list));
}

std::array<double, 3> colormap_rgb(Colormap map, double t) {
  if (std::isnan(t)) throw Error("colormap_rgb: t is NaN");
  return evaluate(map, std::clamp(t, 0.0, 1.0));
}

std::vector<Rgba8> colormap_table(Colormap map, std::size_t n) {
  if (n == 0) throw Error("colormap_table: the table needs at least 1 entry, got 0");
  std::vector<Rgba8> table(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.5 : static_cast<double>(i) / static_cast<double>(n - 1);
    const Rgb c = evaluate(map, t);
    table[i] = {to_byte(c[0]), to_byte(c[1]), to_byte(c[2]), 255};
  }
  return table;
}

ColormapResult map_colors(const DataArray& array, const ColormapOptions& o) {
  const std::string what = "colormap: '" + array.name() + "'";
  if (o.name.empty()) throw Error("colormap: the output array needs a name");
  if (o.bands < 0) throw Error(fmt::format("colormap: bands must be >= 0, got {}", o.bands));
  if (!(o.opacity >= 0 && o.opacity <= 1)) {
    throw Error(fmt::format("colormap: opacity must be in [0, 1], got {}", o.opacity));
  }
  if (o.source == ColorSource::Component &&
      (o.component < 0 || o.component >= array.components())) {
    throw Error(fmt::format("{}: component {} is out of range (the array has {} component{})",
                            what, o.component, array.components(),
                            array.components() == 1 ? "" : "s"));
  }
  if (o.range) {
    const auto [lo, hi] = *o.range;
    if (!std::isfinite(lo) || !std::isfinite(hi)) {
      throw Error("colormap: the range must be finite, got " + fmt_range(lo, hi));
    }
    if (!(lo < hi)) {
      throw Error("colormap: the range's min must be below its max, got " + fmt_range(lo, hi));
    }
    if (o.log_scale && lo <= 0) {
      throw Error("colormap: log scale needs a positive range, got " + fmt_range(lo, hi));
    }
  }

  const std::size_t n = array.tuples();
  const ColorSource mode = o.source == ColorSource::Auto
                               ? (array.components() == 1 ? ColorSource::Component
                                                          : ColorSource::Magnitude)
                               : o.source;
  const ScalarSource source{array, mode, mode == ColorSource::Component ? o.component : 0};
  std::vector<double> values(n);
  double data_lo = std::numeric_limits<double>::infinity(), data_hi = -data_lo;
  for (std::size_t i = 0; i < n; ++i) {
    values[i] = source.value(i);
    if (std::isfinite(values[i])) {
      data_lo = std::min(data_lo, values[i]);
      data_hi = std::max(data_hi, values[i]);
    }
  }
  double lo = kNoValue, hi = kNoValue;
  if (o.range) {
    lo = (*o.range)[0];
    hi = (*o.range)[1];
  } else if (data_lo <= data_hi) {
    lo = data_lo;
    hi = data_hi;
    if (o.log_scale && lo <= 0) {
      throw Error(fmt::format("{}: log scale needs positive values, but they range {} "
                              "(give a positive range)",
                              what, fmt_range(lo, hi)));
    }
  }

  ColormapStats stats;
  stats.range = {lo, hi};
  stats.values = n;
  for (const double v : values) {
    if (std::isnan(v)) {
      ++stats.nan_count;
    } else if (v < lo || (std::isnan(lo) && v < 0)) {  // no range: -inf is below, +inf above
      ++stats.below_count;
    } else if (v > hi || (std::isnan(hi) && v > 0)) {
      ++stats.above_count;
    }
  }

  const int comps = o.rgba ? 4 : 3;
  const auto alpha = static_cast<std::uint8_t>(std::lround(o.opacity * 255));
  auto end_colour = [&](double t) {
    const Rgb c = evaluate(o.map, t);
    return Rgba8{to_byte(c[0]), to_byte(c[1]), to_byte(c[2]), alpha};
  };
  const Rgba8 below = o.below_color ? *o.below_color : end_colour(o.bands == 1 ? 0.5 : 0.0);
  const Rgba8 above = o.above_color ? *o.above_color : end_colour(o.bands == 1 ? 0.5 : 1.0);
  const bool log = o.log_scale;
  const double scaled_lo = log ? std::log10(lo) : lo;
  const double scaled_span = (log ? std::log10(hi) : hi) - scaled_lo;

  DataArray out = DataArray::uninitialized(o.name, ScalarType::UInt8, comps, n);
  std::span<std::uint8_t> bytes = out.values<std::uint8_t>();
  parallel_for_range(n, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double v = values[i];
      Rgba8 colour;
      if (std::isnan(v)) {
        colour = o.nan_color;
      } else if (v < lo || (std::isnan(lo) && v < 0)) {
        colour = below;
      } else if (v > hi || (std::isnan(hi) && v > 0)) {
        colour = above;
      } else {
        // In the range: t in [0, 1]; a one-value range maps to the middle of the map.
        double t = scaled_span > 0 ? ((log ? std::log10(v) : v) - scaled_lo) / scaled_span : 0.5;
        t = std::clamp(t, 0.0, 1.0);
        if (o.bands > 0) {
          const int k = std::min(static_cast<int>(t * o.bands), o.bands - 1);
          t = o.bands == 1 ? 0.5 : static_cast<double>(k) / (o.bands - 1);
        }
        const Rgb c = evaluate(o.map, t);
        colour = {to_byte(c[0]), to_byte(c[1]), to_byte(c[2]), alpha};
      }
      std::copy_n(colour.begin(), comps, bytes.begin() + static_cast<std::ptrdiff_t>(i * comps));
    }
  });
  return {std::move(out), stats};
}

namespace {

ColormapStats add_colors_to(Attributes& points, Attributes& cells, std::string_view array,
                            const ColormapOptions& options) {
  Attributes* where = points.has(array) ? &points : cells.has(array) ? &cells : nullptr;
  if (!where) {
    throw Error(fmt::format("colormap: no array '{}' (point arrays: {}; cell arrays: {})", array,
                            points.names(), cells.names()));
  }
  auto [colours, stats] = map_colors(where->get(array), options);
  where->add(std::move(colours));
  return stats;
}

}  // namespace

ColormapStats add_colors(Dataset& dataset, std::string_view array,
                         const ColormapOptions& options) {
  return add_colors_to(point_data(dataset), cell_data(dataset), array, options);
}
ColormapStats add_colors(ImageData& dataset, std::string_view array,
                         const ColormapOptions& options) {
  return add_colors_to(dataset.point_data, dataset.cell_data, array, options);
}
ColormapStats add_colors(StructuredGrid& dataset, std::string_view array,
                         const ColormapOptions& options) {
  return add_colors_to(dataset.point_data, dataset.cell_data, array, options);
}
ColormapStats add_colors(PolyData& dataset, std::string_view array,
                         const ColormapOptions& options) {
  return add_colors_to(dataset.point_data, dataset.cell_data, array, options);
}
ColormapStats add_colors(UnstructuredGrid& dataset, std::string_view array,
                         const ColormapOptions& options) {
  return add_colors_to(dataset.point_data, dataset.cell_data, array, options);
}

}  // namespace isoforge
