#include "isoforge/filters/colormap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The 8-bit colour of `map` at t, as a legend would round it.
Rgba8 at(Colormap map, double t) {
  const auto c = colormap_rgb(map, t);
  auto byte = [](double x) { return static_cast<std::uint8_t>(std::lround(x * 255)); };
  return {byte(c[0]), byte(c[1]), byte(c[2]), 255};
}

Rgba8 rgb(int r, int g, int b) {
  return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g),
          static_cast<std::uint8_t>(b), 255};
}

// Tuple i of a UInt8 colour array, alpha 255 when it has 3 components.
Rgba8 colour(const DataArray& a, std::size_t i) {
  Rgba8 c{0, 0, 0, 255};
  for (int k = 0; k < a.components(); ++k) c[k] = a.values<std::uint8_t>()[i * a.components() + k];
  return c;
}

void expect_near(const Rgba8& got, const Rgba8& want, int tolerance, const char* what) {
  for (int k = 0; k < 4; ++k) {
    EXPECT_LE(std::abs(int(got[k]) - int(want[k])), tolerance)
        << what << ": component " << k << " is " << int(got[k]) << ", expected " << int(want[k]);
  }
}

// CIELAB L* (D65) of an sRGB colour in [0, 1].
double lightness(const std::array<double, 3>& c) {
  auto lin = [](double x) { return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4); };
  const double y = 0.2126729 * lin(c[0]) + 0.7151522 * lin(c[1]) + 0.0721750 * lin(c[2]);
  return y > 216.0 / 24389 ? 116 * std::cbrt(y) - 16 : y * 24389.0 / 27;
}

DataArray floats(const char* name, std::vector<float> v, int components = 1) {
  return DataArray::from_vector<float>(name, components, v);
}

}  // namespace

TEST(Colormap, NamesRoundTripAndUnknownNamesListTheMaps) {
  const auto names = colormap_names();
  ASSERT_EQ(names.size(), 7u);
  EXPECT_EQ(names[0], "viridis");
  for (const Colormap m : colormaps()) EXPECT_EQ(colormap_from_name(to_string(m)), m);
  EXPECT_EQ(colormap_from_name("cool-warm"), Colormap::CoolWarm);
  expect_error([] { (void)colormap_from_name("jet"); },
               "unknown map 'jet' (the maps: viridis, plasma, inferno, cool-warm, rainbow, "
               "grayscale, black-body)");
}

// The ends of matplotlib's published tables: viridis #440154..#FDE725, plasma #0D0887..#F0F921,
// inferno #000004..#FCFFA4. Midpoints: the mean of entries 127 and 128 of the 256-entry tables
// (viridis 32.7 144.1 140.5, plasma 203.1 70.9 120.2, inferno 186.9 54.7 84.7): our table keeps
// every third entry, so t = 0.5 is interpolated, within one level.
TEST(Colormap, MatplotlibMapsAtTheirEndsAndMiddle) {
  EXPECT_EQ(at(Colormap::Viridis, 0), rgb(68, 1, 84));
  EXPECT_EQ(at(Colormap::Viridis, 1), rgb(253, 231, 37));
  EXPECT_EQ(at(Colormap::Plasma, 0), rgb(13, 8, 135));
  EXPECT_EQ(at(Colormap::Plasma, 1), rgb(240, 249, 33));
  EXPECT_EQ(at(Colormap::Inferno, 0), rgb(0, 0, 4));
  EXPECT_EQ(at(Colormap::Inferno, 1), rgb(252, 255, 164));
  expect_near(at(Colormap::Viridis, 0.5), rgb(33, 144, 140), 1, "viridis(0.5)");
  expect_near(at(Colormap::Plasma, 0.5), rgb(203, 71, 120), 1, "plasma(0.5)");
  expect_near(at(Colormap::Inferno, 0.5), rgb(187, 55, 85), 1, "inferno(0.5)");
  // Entry 51 of 256 (t = 0.2) is a sample of ours: exact (viridis 64.75 67.64 135.15).
  EXPECT_EQ(at(Colormap::Viridis, 51.0 / 255), rgb(65, 68, 135));
  // These maps are perceptually uniform with rising lightness: L* increases along them.
  for (const Colormap m : {Colormap::Viridis, Colormap::Plasma, Colormap::Inferno}) {
    double last = -1;
    for (int i = 0; i <= 100; ++i) {
      const double l = lightness(colormap_rgb(m, i / 100.0));
      EXPECT_GT(l, last) << to_string(m) << " at " << i / 100.0;
      last = l;
    }
  }
}

// Moreland's cool-warm: ends sRGB (59, 76, 192) and (180, 4, 38); the Msh interpolation passes
// through an unsaturated midpoint of magnitude 88, i.e. L* = 88, a* = b* = 0: sRGB grey 220.7.
TEST(Colormap, CoolWarmEndsAndNearWhiteMiddle) {
  EXPECT_EQ(at(Colormap::CoolWarm, 0), rgb(59, 76, 192));
  EXPECT_EQ(at(Colormap::CoolWarm, 1), rgb(180, 4, 38));
  EXPECT_EQ(at(Colormap::CoolWarm, 0.5), rgb(221, 221, 221));
  EXPECT_NEAR(lightness(colormap_rgb(Colormap::CoolWarm, 0.5)), 88, 1e-4);
  // Diverging: lightness rises to the middle and falls after it; the cool half is bluish
  // (b > r), the warm half reddish (r > b).
  double last = 0;
  for (int i = 0; i <= 100; ++i) {
    const auto c = colormap_rgb(Colormap::CoolWarm, i / 100.0);
    const double l = lightness(c);
    if (i > 0 && i <= 50) {
      EXPECT_GT(l, last) << "t = " << i / 100.0;
    } else if (i > 50) {
      EXPECT_LT(l, last) << "t = " << i / 100.0;
    }
    if (i < 50) {
      EXPECT_GT(c[2], c[0]) << "t = " << i / 100.0;
    } else if (i > 50) {
      EXPECT_GT(c[0], c[2]) << "t = " << i / 100.0;
    }
    last = l;
  }
}

// VTK's default lookup table: hue from 0 (red) to 2/3 (blue) at full saturation and value, so
// t = 1/4, 1/2, 3/4 are hues 1/6, 1/3, 1/2: yellow, green, cyan.
TEST(Colormap, RainbowRedToBlueThroughHsv) {
  EXPECT_EQ(at(Colormap::Rainbow, 0), rgb(255, 0, 0));
  EXPECT_EQ(at(Colormap::Rainbow, 0.25), rgb(255, 255, 0));
  EXPECT_EQ(at(Colormap::Rainbow, 0.5), rgb(0, 255, 0));
  EXPECT_EQ(at(Colormap::Rainbow, 0.75), rgb(0, 255, 255));
  EXPECT_EQ(at(Colormap::Rainbow, 1), rgb(0, 0, 255));
  EXPECT_EQ(at(Colormap::Rainbow, 0.125), rgb(255, 128, 0));  // hue 1/12: orange, 127.5 rounded up
}

TEST(Colormap, GrayscaleAndClampedT) {
  EXPECT_EQ(at(Colormap::Grayscale, 0), rgb(0, 0, 0));
  EXPECT_EQ(at(Colormap::Grayscale, 0.5), rgb(128, 128, 128));
  EXPECT_EQ(at(Colormap::Grayscale, 1), rgb(255, 255, 255));
  EXPECT_EQ(at(Colormap::Grayscale, -3), rgb(0, 0, 0));  // t is clamped to [0, 1]
  EXPECT_EQ(at(Colormap::Grayscale, kInf), rgb(255, 255, 255));
  expect_error([] { (void)colormap_rgb(Colormap::Grayscale, kNaN); }, "t is NaN");
}

// Moreland's black body: control colours black, (178, 34, 34), (227, 105, 5), (238, 210, 20),
// white placed at their L* / 100 and interpolated in CIELAB. His published 8-entry table (t = k/7)
// is reproduced within one level (we decode as his tables do: docs/algorithms/colormaps.md), and
// lightness rises steadily, within one L* unit of 100 t.
TEST(Colormap, BlackBodyMatchesMorelandsTableWithRisingLightness) {
  EXPECT_EQ(at(Colormap::BlackBody, 0), rgb(0, 0, 0));
  EXPECT_EQ(at(Colormap::BlackBody, 1), rgb(255, 255, 255));
  const Rgba8 table[8] = {rgb(0, 0, 0),      rgb(64, 23, 18),   rgb(126, 31, 28),
                          rgb(184, 50, 33),  rgb(219, 101, 10), rgb(228, 161, 3),
                          rgb(233, 216, 57), rgb(255, 255, 255)};
  for (int k = 0; k < 8; ++k) expect_near(at(Colormap::BlackBody, k / 7.0), table[k], 1, "black body");
  double last = -1;
  for (int i = 0; i <= 100; ++i) {
    const double l = lightness(colormap_rgb(Colormap::BlackBody, i / 100.0));
    EXPECT_NEAR(l, i, 1.0) << "t = " << i / 100.0;
    EXPECT_GT(l, last) << "t = " << i / 100.0;
    last = l;
  }
}

TEST(Colormap, LookupTablesSampleTheMapEvenly) {
  const auto t = colormap_table(Colormap::Grayscale, 5);
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[0], rgb(0, 0, 0));
  EXPECT_EQ(t[1], rgb(64, 64, 64));  // 63.75
  EXPECT_EQ(t[2], rgb(128, 128, 128));
  EXPECT_EQ(t[4], rgb(255, 255, 255));
  EXPECT_EQ(colormap_table(Colormap::Rainbow, 1)[0], rgb(0, 255, 0));  // one entry: t = 0.5
  expect_error([] { (void)colormap_table(Colormap::Viridis, 0); }, "at least 1 entry");
}

TEST(MapColors, AutoRangeIgnoresNanAndColoursItGrey) {
  const auto [out, stats] = map_colors(floats("T", {0, 5, 10, NAN, 2.5}),
                                       {.map = Colormap::Grayscale});
  EXPECT_EQ(out.name(), "Colors");
  EXPECT_EQ(out.type(), ScalarType::UInt8);
  ASSERT_EQ(out.components(), 3);
  ASSERT_EQ(out.tuples(), 5u);
  EXPECT_EQ(stats.range[0], 0);
  EXPECT_EQ(stats.range[1], 10);
  EXPECT_EQ(stats.values, 5u);
  EXPECT_EQ(stats.nan_count, 1u);
  EXPECT_EQ(stats.below_count, 0u);
  EXPECT_EQ(stats.above_count, 0u);
  EXPECT_EQ(colour(out, 0), rgb(0, 0, 0));
  EXPECT_EQ(colour(out, 1), rgb(128, 128, 128));
  EXPECT_EQ(colour(out, 2), rgb(255, 255, 255));
  EXPECT_EQ(colour(out, 3), rgb(128, 128, 128));  // the default NaN colour, mid grey
  EXPECT_EQ(colour(out, 4), rgb(64, 64, 64));     // t = 0.25: 63.75
  // The default map is viridis.
  EXPECT_EQ(colour(map_colors(floats("T", {0, 1})).output, 1), rgb(253, 231, 37));
}

TEST(MapColors, BelowAboveAndNanColours) {
  ColormapOptions o{.map = Colormap::Grayscale, .range = std::array{0.0, 1.0}};
  const DataArray a = floats("T", {-1, 0, 0.5f, 1, 2, -INFINITY, INFINITY, NAN});
  auto [clamped, s] = map_colors(a, o);
  EXPECT_EQ(s.below_count, 2u);  // -1, -inf
  EXPECT_EQ(s.above_count, 2u);  // 2, +inf
  EXPECT_EQ(s.nan_count, 1u);
  EXPECT_EQ(colour(clamped, 0), rgb(0, 0, 0));  // default: clamped to the ends of the map
  EXPECT_EQ(colour(clamped, 4), rgb(255, 255, 255));
  o.below_color = Rgba8{255, 0, 0, 255};
  o.above_color = Rgba8{0, 0, 255, 255};
  o.nan_color = Rgba8{0, 255, 0, 255};
  const DataArray out = map_colors(a, o).output;
  const Rgba8 expected[] = {rgb(255, 0, 0),     rgb(0, 0, 0),   rgb(128, 128, 128),
                            rgb(255, 255, 255), rgb(0, 0, 255), rgb(255, 0, 0),
                            rgb(0, 0, 255),     rgb(0, 255, 0)};
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(colour(out, i), expected[i]) << "tuple " << i;
}

TEST(MapColors, LogScale) {
  ColormapOptions o{.map = Colormap::Grayscale, .log_scale = true};
  // Auto range 1 .. 100: log10 puts 10 in the middle.
  auto [out, s] = map_colors(floats("p", {1, 10, 100}), o);
  EXPECT_EQ(colour(out, 0), rgb(0, 0, 0));
  EXPECT_EQ(colour(out, 1), rgb(128, 128, 128));
  EXPECT_EQ(colour(out, 2), rgb(255, 255, 255));
  // A given range: values <= 0 have no logarithm and are below it.
  o.range = std::array{1.0, 1000.0};
  o.below_color = Rgba8{9, 9, 9, 255};
  auto [out2, s2] = map_colors(floats("p", {0, -5, 0.5f, 100}), o);
  EXPECT_EQ(s2.below_count, 3u);
  EXPECT_EQ(colour(out2, 1), rgb(9, 9, 9));
  EXPECT_EQ(colour(out2, 3), rgb(170, 170, 170));  // log10(100) / log10(1000) = 2/3
  // Non-positive ranges are errors, given or found in the data.
  o.range = std::array{0.0, 10.0};
  expect_error([&] { (void)map_colors(floats("p", {1}), o); },
               "log scale needs a positive range, got [0, 10]");
  o.range.reset();
  expect_error([&] { (void)map_colors(floats("p", {-2, 0, 3}), o); },
               "'p': log scale needs positive values, but they range [-2, 3]");
}

// Four bands over [0, 1]: [0, .25) [.25, .5) [.5, .75) [.75, 1], coloured at t = 0, 1/3, 2/3, 1.
TEST(MapColors, DiscreteBands) {
  const DataArray a = floats("b", {0, 0.24f, 0.26f, 0.5f, 0.74f, 0.76f, 1});
  ColormapOptions o{.map = Colormap::Grayscale, .range = std::array{0.0, 1.0}, .bands = 4};
  const DataArray out = map_colors(a, o).output;
  const int grey[] = {0, 0, 85, 170, 170, 255, 255};
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(colour(out, i), rgb(grey[i], grey[i], grey[i])) << i;
  o.bands = 1;  // one band: the middle colour everywhere in the range, and clamped outside
  const DataArray one = map_colors(floats("b", {0, 0.3f, 1, 7}), o).output;
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(colour(one, i), rgb(128, 128, 128)) << i;
}

TEST(MapColors, MagnitudeAndComponent) {
  // Tuples (3, 4, 0), (0, 0, 0), (0, 2, NaN): magnitudes 5, 0, NaN.
  const DataArray v = floats("V", {3, 4, 0, 0, 0, 0, 0, 2, NAN}, 3);
  ColormapOptions o{.map = Colormap::Grayscale};
  auto [mag, s] = map_colors(v, o);  // Auto on a vector: the magnitude
  EXPECT_EQ(s.range[1], 5);
  EXPECT_EQ(s.nan_count, 1u);
  EXPECT_EQ(colour(mag, 0), rgb(255, 255, 255));
  EXPECT_EQ(colour(mag, 1), rgb(0, 0, 0));
  EXPECT_EQ(colour(mag, 2), rgb(128, 128, 128));
  o.source = ColorSource::Component;
  o.component = 1;  // 4, 0, 2 over the auto range [0, 4]
  auto [y, sy] = map_colors(v, o);
  EXPECT_EQ(sy.nan_count, 0u);
  EXPECT_EQ(colour(y, 0), rgb(255, 255, 255));
  EXPECT_EQ(colour(y, 2), rgb(128, 128, 128));
  // Magnitude of a scalar is its absolute value.
  ColormapOptions m{.map = Colormap::Grayscale, .source = ColorSource::Magnitude};
  EXPECT_EQ(colour(map_colors(floats("s", {-4, 2}), m).output, 0), rgb(255, 255, 255));
  o.component = 3;
  expect_error([&] { (void)map_colors(v, o); },
               "'V': component 3 is out of range (the array has 3 components)");
  o.component = -1;
  expect_error([&] { (void)map_colors(v, o); }, "component -1 is out of range");
}

TEST(MapColors, RgbaOpacityAndIntegerInput) {
  const DataArray a = DataArray::from_vector<std::int32_t>("id", 1, {10, 20, 30});
  ColormapOptions o{.map = Colormap::Rainbow, .rgba = true, .opacity = 0.5, .name = "rgba"};
  auto [out, s] = map_colors(a, o);
  EXPECT_EQ(out.name(), "rgba");
  ASSERT_EQ(out.components(), 4);
  EXPECT_EQ(colour(out, 0), (Rgba8{255, 0, 0, 128}));
  EXPECT_EQ(colour(out, 1), (Rgba8{0, 255, 0, 128}));
  EXPECT_EQ(colour(out, 2), (Rgba8{0, 0, 255, 128}));
  // Explicit colours keep their own alpha.
  o.nan_color = Rgba8{1, 2, 3, 0};
  EXPECT_EQ(colour(map_colors(floats("f", {NAN, 1}), o).output, 0), (Rgba8{1, 2, 3, 0}));
}

TEST(MapColors, ConstantEmptyAndAllNanArrays) {
  ColormapOptions o{.map = Colormap::Grayscale};
  // One value: the range is [7, 7] and every value takes the middle colour.
  auto [c, sc] = map_colors(floats("c", {7, 7}), o);
  EXPECT_EQ(sc.range[0], 7);
  EXPECT_EQ(colour(c, 1), rgb(128, 128, 128));
  // No finite value and no range given: the range is NaN; NaN and infinities still coloured.
  auto [e, se] = map_colors(floats("e", {}), o);
  EXPECT_EQ(e.tuples(), 0u);
  EXPECT_TRUE(std::isnan(se.range[0]) && std::isnan(se.range[1]));
  auto [n, sn] = map_colors(floats("n", {NAN, INFINITY, -INFINITY}), o);
  EXPECT_EQ(sn.nan_count, 1u);
  EXPECT_EQ(sn.above_count, 1u);
  EXPECT_EQ(sn.below_count, 1u);
  EXPECT_EQ(colour(n, 1), rgb(255, 255, 255));
  EXPECT_EQ(colour(n, 2), rgb(0, 0, 0));
}

TEST(MapColors, OptionErrors) {
  const DataArray a = floats("a", {1, 2});
  auto error_of = [&](ColormapOptions o, const char* text) {
    expect_error([&] { (void)map_colors(a, o); }, text);
  };
  error_of({.range = std::array{2.0, 1.0}}, "min must be below its max, got [2, 1]");
  error_of({.range = std::array{1.0, 1.0}}, "min must be below its max");
  error_of({.range = std::array{0.0, kInf}}, "the range must be finite, got [0, inf]");
  error_of({.range = std::array{kNaN, 1.0}}, "the range must be finite");
  error_of({.bands = -1}, "bands must be >= 0, got -1");
  error_of({.opacity = 1.5}, "opacity must be in [0, 1], got 1.5");
  error_of({.opacity = kNaN}, "opacity must be in [0, 1]");
  error_of({.name = ""}, "needs a name");
}

// Many values (several parallel slices): each colour is the map's colour at the value's t.
TEST(MapColors, EveryTupleIsItsOwnValuesColour) {
  const std::size_t n = 50'000;
  DataArray a("ramp", ScalarType::Float64, 1, n);
  for (std::size_t i = 0; i < n; ++i) a.set(i, 0, std::sin(static_cast<double>(i)));
  const ColormapOptions o{.map = Colormap::CoolWarm, .range = std::array{-1.0, 1.0}};
  const DataArray out = map_colors(a, o).output;
  for (std::size_t i = 0; i < n; i += 97) {
    ASSERT_EQ(colour(out, i), at(Colormap::CoolWarm, (a.get(i) + 1) / 2)) << "tuple " << i;
  }
}

TEST(AddColors, PointDataFirstThenCellData) {
  PolyData pd;
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0}}) {
    pd.points.push_back(p);
  }
  pd.polys.add({0, 1, 2});
  pd.polys.add({1, 3, 2});
  pd.point_data.add(floats("s", {0, 1, 2, 3}));
  pd.cell_data.add(floats("c", {5, 6}));
  pd.cell_data.add(floats("s", {9, 9}));  // a cell array of the same name: points win
  const ColormapStats st = add_colors(pd, "c", {.map = Colormap::Grayscale, .name = "rgb"});
  EXPECT_EQ(st.range[1], 6);
  ASSERT_TRUE(pd.cell_data.has("rgb"));
  EXPECT_FALSE(pd.point_data.has("rgb"));
  EXPECT_EQ(pd.cell_data.get("rgb").tuples(), 2u);
  EXPECT_EQ(colour(pd.cell_data.get("rgb"), 1), rgb(255, 255, 255));
  (void)add_colors(pd, "s", {.map = Colormap::Grayscale});
  ASSERT_TRUE(pd.point_data.has("Colors"));
  EXPECT_EQ(colour(pd.point_data.get("Colors"), 3), rgb(255, 255, 255));
  EXPECT_NO_THROW(pd.validate());
  expect_error([&] { (void)add_colors(pd, "nope", {}); },
               "no array 'nope' (point arrays: 's', 'Colors'; cell arrays: 'c', 's', 'rgb')");
}

TEST(AddColors, EveryDatasetType) {
  ImageData img;
  img.dims = {2, 2, 1};
  img.cell_data.add(floats("k", {3}));
  Dataset ds = img;
  (void)add_colors(ds, "k", {.map = Colormap::Rainbow, .rgba = true});
  const DataArray& c = std::get<ImageData>(ds).cell_data.get("Colors");
  EXPECT_EQ(c.components(), 4);
  EXPECT_EQ(colour(c, 0), rgb(0, 255, 0));  // one value: the middle of the map
  UnstructuredGrid ug = to_unstructured(img);
  (void)add_colors(ug, "k", {});
  EXPECT_TRUE(ug.cell_data.has("Colors"));
  StructuredGrid sg;
  sg.dims = {1, 1, 1};
  sg.points.push_back({0, 0, 0});
  sg.point_data.add(floats("p", {1}));
  (void)add_colors(sg, "p", {});
  EXPECT_TRUE(sg.point_data.has("Colors"));
  expect_error([&] { (void)add_colors(sg, "k", {}); },
               "no array 'k' (point arrays: 'p', 'Colors'; cell arrays: none)");
}
