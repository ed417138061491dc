// Tests for the Draco .drc writer and reader: round trips (counts, names, types, roles), error
// budgets checked on every file written, vertex order under sequential coding, point clouds,
// refused lines, corrupt and truncated input.

#include "isoforge/io/draco.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/detail/draco_codec.hpp"
#include "isoforge/io/io.hpp"
#include "support/expect_error.hpp"
#include "support/mutate.hpp"
#include "support/scratch.hpp"

using namespace isoforge;
namespace fs = std::filesystem;
using isoforge::test::data_path;
using isoforge::test::expect_error;

namespace {

fs::path scratch(const std::string& name) { return isoforge::test::scratch_dir("draco", name); }

PolyData bunny() { return std::get<PolyData>(read(data_path("bunny.ply"))); }

double diagonal(const PolyData& m) {
  const Bounds b = m.bounds();
  double d2 = 0;
  for (int c = 0; c < 3; ++c) d2 += (b.max[c] - b.min[c]) * (b.max[c] - b.min[c]);
  return std::sqrt(d2);
}

// The largest distance from an original point to the nearest decoded point, by brute force over a
// hash of decoded points into cells of size `cell` (independent of the writer's own matching).
// For a correct codec this is each point's error (rounding moves a point to the nearest grid
// point, and no other decoded point is nearer than that grid point).
double max_nearest_distance(const PolyData& original, const PolyData& decoded, double cell) {
  std::map<std::array<long, 3>, std::vector<std::size_t>> grid;
  const auto key = [&](const Vec3& p) {
    return std::array<long, 3>{long(std::floor(p[0] / cell)), long(std::floor(p[1] / cell)),
                               long(std::floor(p[2] / cell))};
  };
  for (std::size_t j = 0; j < decoded.points.size(); ++j) grid[key(decoded.points[j])].push_back(j);
  double worst = 0;
  std::vector<char> used(original.points.size(), original.polys.empty() ? 1 : 0);
  for (Index id : original.polys.connectivity()) used[static_cast<std::size_t>(id)] = 1;
  for (std::size_t i = 0; i < original.points.size(); ++i) {
    if (!used[i]) continue;  // points in no face: Edgebreaker does not keep them
    const Vec3 p = original.points[i];
    const auto k = key(p);
    double best = std::numeric_limits<double>::infinity();
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == grid.end()) continue;
          for (auto j : it->second) best = std::min(best, norm(p - decoded.points[j]));
        }
    worst = std::max(worst, best);
  }
  return worst;
}

// The check made on every file a test writes: the stats' measured errors are within the
// budgets asked for, the file on disk has the stated size, and reading it back gives the stated
// counts.
void check_written(const DracoStats& st, const DracoWriteOptions& o, const fs::path& path,
                   double diag) {
  ASSERT_TRUE(fs::exists(path));
  EXPECT_EQ(fs::file_size(path), st.bytes);
  EXPECT_GT(st.ratio, 0);
  ASSERT_FALSE(st.attributes.empty());
  EXPECT_EQ(st.attributes[0].max_error, st.max_position_error);
  const double pos_budget = o.max_position_error > 0 ? o.max_position_error
                                                     : o.max_position_error_relative * diag;
  if (pos_budget > 0) {
    EXPECT_LE(st.max_position_error, pos_budget) << path;
  }
  for (const auto& b : o.max_array_errors) {
    const auto it = std::find_if(st.attributes.begin(), st.attributes.end(),
                                 [&](const auto& a) { return a.name == b.name; });
    ASSERT_NE(it, st.attributes.end()) << b.name;
    EXPECT_LE(it->max_error, b.max_error) << b.name;
  }
  const PolyData back = read_draco(path);
  EXPECT_EQ(back.points.size(), st.decoded_points);
  EXPECT_EQ(back.polys.size(), st.decoded_triangles);
}

DracoStats write_checked(const PolyData& m, const fs::path& path, const DracoWriteOptions& o) {
  const DracoStats st = write_draco(m, path, o);
  check_written(st, o, path, diagonal(m));
  return st;
}

// Two triangles on a unit square, plus arrays of every kind.
PolyData square() {
  PolyData m;
  m.points.push_back({0, 0, 0});
  m.points.push_back({1, 0, 0});
  m.points.push_back({1, 1, 0});
  m.points.push_back({0, 1, 0.5});
  m.polys.add({0, 1, 2});
  m.polys.add({0, 2, 3});
  return m;
}

PolyData square_with_arrays() {
  PolyData m = square();
  m.point_data.add(DataArray::from_vector<float>("Normals", 3, {0, 0, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0}),
                   AttributeRole::Normals);
  m.point_data.add(DataArray::from_vector<std::uint8_t>("Colors", 3,
                                                        {255, 0, 0, 0, 255, 0, 0, 0, 255, 9, 8, 7}),
                   AttributeRole::Scalars);
  m.point_data.add(DataArray::from_vector<float>("TCoords", 2, {0, 0, 1, 0, 1, 1, 0, 1}),
                   AttributeRole::TCoords);
  m.point_data.add(DataArray::from_vector<double>("temperature", 1, {1.5, 2.25, -3.0, 1e3}));
  m.point_data.add(DataArray::from_vector<std::int32_t>("ids", 1, {7, -3, 100000, 42}));
  m.point_data.add(DataArray::from_vector<std::int64_t>(
      "wide", 1, {0, std::int64_t{1} << 40, -(std::int64_t{1} << 35), 5}));
  m.point_data.add(DataArray::from_vector<std::uint16_t>("labels", 2, {1, 2, 3, 4, 5, 6, 7, 8}));
  m.point_data.add(DataArray::from_vector<float>("velocity", 3,
                                                 {1, 2, 3, -1, -2, -3, 0.5f, 0.25f, 0, 9, 9, 9}));
  return m;
}

}  // namespace

TEST(Draco, SequentialKeepsCountsOrderAndFaces) {
  const PolyData m = square();
  DracoWriteOptions o;
  o.method = DracoMethod::Sequential;
  o.bits.position = 16;
  const fs::path path = scratch("s") / "square.drc";
  const DracoStats st = write_checked(m, path, o);
  EXPECT_EQ(st.points, 4u);
  EXPECT_EQ(st.triangles, 2u);
  EXPECT_EQ(st.decoded_points, 4u);
  EXPECT_EQ(st.lost_triangles, 0u);
  const PolyData back = read_draco(path);
  ASSERT_EQ(back.polys.size(), 2u);
  // Sequential coding keeps ids: the faces are the same id triples in the same order.
  EXPECT_EQ(back.polys, m.polys);
  // Largest extent 1, 16 bits: step 1/65535, every point within step·√3/2 of its original.
  const double step = 1.0 / 65535;
  EXPECT_NEAR(st.attributes[0].step, step, 1e-12);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_LE(norm(back.points[i] - m.points[i]), step * std::sqrt(3.0) / 2 * 1.0001) << i;
  }
  // Grid points of this square are exactly representable: 0, 1 and 0.5 (= 32767.5 steps, which
  // rounds to a neighbour) — the measured error is that of z = 0.5.
  EXPECT_GT(st.max_position_error, 0);
}

TEST(Draco, NamesTypesAndRolesSurviveARoundTrip) {
  const PolyData m = square_with_arrays();
  for (DracoMethod method : {DracoMethod::Sequential, DracoMethod::Edgebreaker}) {
    DracoWriteOptions o;
    o.method = method;
    o.bits.generic = 20;
    const fs::path path = scratch(method == DracoMethod::Sequential ? "seq" : "eb") / "a.drc";
    const DracoStats st = write_checked(m, path, o);
    const PolyData back = read_draco(path);
    ASSERT_EQ(back.point_data.size(), m.point_data.size());
    for (std::size_t k = 0; k < m.point_data.size(); ++k) {
      const DataArray& a = m.point_data[k];
      const DataArray* b = back.point_data.find(a.name());
      ASSERT_NE(b, nullptr) << a.name();
      EXPECT_EQ(b->type(), a.type()) << a.name();
      EXPECT_EQ(b->components(), a.components()) << a.name();
    }
    EXPECT_EQ(back.point_data.active_name(AttributeRole::Normals), "Normals");
    EXPECT_EQ(back.point_data.active_name(AttributeRole::Scalars), "Colors");
    EXPECT_EQ(back.point_data.active_name(AttributeRole::TCoords), "TCoords");
    if (method == DracoMethod::Sequential) {
      // Integer arrays are exact, including a 64-bit one spread wider than 2^24 (stored as
      // Float64 in the file, read back as Int64).
      for (const char* exact : {"Colors", "ids", "wide", "labels"}) {
        EXPECT_EQ(*back.point_data.find(exact), *m.point_data.find(exact)) << exact;
      }
      // temperature: Float64 range 1003, 20 bits: error at most 1003/(2^20-1)/2.
      const DataArray& t = back.point_data.get("temperature");
      for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_LE(std::abs(t.get(i) - m.point_data.get("temperature").get(i)),
                  1003.0 / 1048575 / 2 * 1.001);
      }
    }
    // Every array's measured error is within its grid's bound (√c·step/2), integers exact.
    for (const auto& a : st.attributes) {
      if (a.bits == 0) {
        EXPECT_EQ(a.max_error, 0) << a.name;
      }
      if (a.step > 0) {
        const int c = a.name == "Points" ? 3 : m.point_data.get(a.name).components();
        EXPECT_LE(a.max_error, a.step * std::sqrt(double(c)) / 2 * 1.001) << a.name;
      }
    }
  }
}

TEST(Draco, BunnyBudgetsAreNeverExceeded) {
  const PolyData m = bunny();
  const double diag = diagonal(m);
  std::uint64_t previous = 0;
  for (double rel : {1e-3, 1e-4, 1e-5}) {
    DracoWriteOptions o;
    o.max_position_error_relative = rel;
    const fs::path path = scratch("b") / ("bunny_" + std::to_string(rel) + ".drc");
    const DracoStats st = write_checked(m, path, o);
    EXPECT_EQ(st.decoded_triangles, st.triangles - st.lost_triangles);
    EXPECT_EQ(st.lost_triangles, st.degenerate_input_triangles);
    // Independent measure: the nearest decoded point of every original point.
    const PolyData back = read_draco(path);
    EXPECT_LE(max_nearest_distance(m, back, rel * diag), rel * diag) << rel;
    // A tighter budget never gives a smaller file.
    EXPECT_GT(st.bytes, previous) << rel;
    previous = st.bytes;
    // The step is at least the guaranteed 2e/√3 (isoforge's grid, not a power of two).
    EXPECT_GE(st.attributes[0].step, 2 * rel * diag / std::sqrt(3.0) * 0.95);
  }
  // Absolute budgets too, with the sequential method (ids kept: errors compared point by point).
  for (double e : {1e-3, 2e-5}) {
    DracoWriteOptions o;
    o.max_position_error = e;
    o.method = DracoMethod::Sequential;
    const fs::path path = scratch("abs") / ("bunny_" + std::to_string(e) + ".drc");
    const DracoStats st = write_checked(m, path, o);
    const PolyData back = read_draco(path);
    ASSERT_EQ(back.points.size(), m.points.size());
    double worst = 0;
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      worst = std::max(worst, norm(back.points[i] - m.points[i]));
    }
    EXPECT_LE(worst, e);
    EXPECT_DOUBLE_EQ(worst, st.max_position_error);
    EXPECT_EQ(back.polys, m.polys);  // sequential: the same faces, in order
  }
}

TEST(Draco, BitsGiveDracoGridAndErrorBound) {
  const PolyData m = bunny();
  const Bounds b = m.bounds();
  double extent = 0;
  for (int c = 0; c < 3; ++c) extent = std::max(extent, double(float(b.max[c]) - float(b.min[c])));
  for (int bits : {11, 14, 16}) {
    DracoWriteOptions o;
    o.bits.position = bits;
    const fs::path path = scratch("bits") / ("bunny_" + std::to_string(bits) + ".drc");
    const DracoStats st = write_checked(m, path, o);
    const double step = extent / double((1u << bits) - 1);
    EXPECT_NEAR(st.attributes[0].step, step, step * 1e-6);
    EXPECT_EQ(st.attributes[0].bits, bits);
    EXPECT_LE(st.max_position_error, step * std::sqrt(3.0) / 2 * 1.001);
    EXPECT_EQ(st.encodes, 1);
  }
}

TEST(Draco, ArrayBudgets) {
  PolyData m = bunny();
  // A smooth scalar (height) and a vector (position scaled), in Float64 and Float32.
  DataArray h("height", ScalarType::Float64, 1, m.points.size());
  DataArray v("vec", ScalarType::Float32, 3, m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    h.set(i, 0, 100 * m.points[i][1]);
    for (int c = 0; c < 3; ++c) v.set(i, c, 10 * m.points[i][c]);
  }
  m.point_data.add(std::move(h));
  m.point_data.add(std::move(v));
  for (DracoMethod method : {DracoMethod::Sequential, DracoMethod::Edgebreaker}) {
    for (double e : {1e-2, 1e-4}) {
      DracoWriteOptions o;
      o.method = method;
      o.max_position_error = 1e-4;
      o.max_array_errors = {{"height", e}, {"vec", e}};
      const fs::path path = scratch("arr") / ("b" + std::to_string(e) + ".drc");
      const DracoStats st = write_checked(m, path, o);
      const PolyData back = read_draco(path);
      EXPECT_EQ(back.point_data.get("height").type(), ScalarType::Float64);
      if (method == DracoMethod::Sequential) {
        double worst = 0;
        for (std::size_t i = 0; i < m.points.size(); ++i) {
          worst = std::max(worst, std::abs(back.point_data.get("height").get(i) -
                                           m.point_data.get("height").get(i)));
        }
        EXPECT_LE(worst, e);
        EXPECT_GT(worst, e / 4);  // the grid is sized to the budget, not finer
      }
      (void)st;
    }
  }
}

TEST(Draco, TinyValuedArraysAtTheHighestLevels) {
  // Values of order 1e-10 to 1e-17 (an isosurface's residual field) made libdraco 1.5.5's
  // constrained multi-parallelogram encoder crash at levels 9 and 10.
  PolyData m = bunny();
  for (double scale : {1e-7, 1e-10, 1e-17}) {
    PolyData a = m;
    DataArray f("F", ScalarType::Float32, 1, a.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) f.set(i, 0, scale * a.points[i][0]);
    a.point_data.add(std::move(f));
    for (int level : {9, 10}) {
      DracoWriteOptions o;
      o.level = level;
      const fs::path path = scratch("tiny") / ("l" + std::to_string(level) + ".drc");
      const DracoStats st = write_draco(a, path, o);
      EXPECT_EQ(st.attributes.size(), a.point_data.size() + 1);
      const PolyData back = read_draco(path);
      std::vector<char> used(a.points.size(), 0);
      for (Index id : a.polys.connectivity()) used[static_cast<std::size_t>(id)] = 1;
      EXPECT_EQ(back.points.size(),
                static_cast<std::size_t>(std::count(used.begin(), used.end(), 1)));
      EXPECT_EQ(back.polys.size(), a.polys.size());
      EXPECT_NE(back.point_data.find("F"), nullptr);
    }
  }
}

TEST(Draco, TinyAndOffsetArraysKeepTheirGrid) {
  // Draco takes an explicit grid through options written with six decimals: an origin or range
  // of 1e-7 arrived as 0, and every value decoded as the origin. Each array must decode within
  // half a step of its bits (Draco's own grid) or within its budget (an explicit grid).
  const PolyData m = bunny();
  const Bounds b = m.bounds();
  for (const auto& [scale, offset] : std::vector<std::pair<double, double>>{
           {1e-7, 0}, {1e-10, 0}, {1e-17, 0}, {1e-4, 0.123456789}, {-0.1, -7.654321}}) {
    PolyData a = m;
    DataArray f("F", ScalarType::Float32, 1, a.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) {
      f.set(i, 0, offset + scale * (a.points[i][0] - b.min[0]) / (b.max[0] - b.min[0]));
    }
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = 0; i < f.tuples(); ++i) {
      lo = std::min(lo, f.get(i));
      hi = std::max(hi, f.get(i));
    }
    a.point_data.add(std::move(f));
    std::ostringstream what;
    what << "scale " << scale << " offset " << offset;
    for (const bool budget : {false, true}) {
      DracoWriteOptions o;
      o.method = DracoMethod::Sequential;  // keeps the order: values compare point by point
      const double allowed = budget ? (hi - lo) / 1000 : (hi - lo) / 255 / 2 * 1.001;
      if (budget) o.max_array_errors = {{"F", allowed}};
      const fs::path path = scratch("tiny_grid") / "f.drc";
      const DracoStats st = write_draco(a, path, o);
      const PolyData back = read_draco(path);
      ASSERT_EQ(back.points.size(), a.points.size()) << what.str();
      double worst = 0;
      for (std::size_t i = 0; i < a.points.size(); ++i) {
        worst = std::max(worst,
                         std::abs(back.point_data.get("F").get(i) - a.point_data.get("F").get(i)));
      }
      EXPECT_LE(worst, allowed + 4 * std::numeric_limits<float>::epsilon() * std::abs(offset))
          << what.str() << (budget ? " (budget)" : " (bits)");
      EXPECT_DOUBLE_EQ(worst, st.attributes.back().max_error) << what.str();
    }
  }
}

TEST(Draco, NormalsBudget) {
  PolyData m = bunny();
  DataArray n("Normals", ScalarType::Float32, 3, m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const Vec3 p = m.points[i] - Vec3{-0.03, 0.1, 0};
    const Vec3 u = p / norm(p);
    for (int c = 0; c < 3; ++c) n.set(i, c, u[c]);
  }
  m.point_data.add(std::move(n), AttributeRole::Normals);
  DracoWriteOptions o;
  o.method = DracoMethod::Sequential;
  o.max_position_error_relative = 1e-4;
  o.max_array_errors = {{"Normals", 1e-3}};
  const fs::path path = scratch("n") / "n.drc";
  const DracoStats st = write_checked(m, path, o);
  const auto& na = *std::find_if(st.attributes.begin(), st.attributes.end(),
                                 [](const auto& a) { return a.name == "Normals"; });
  EXPECT_GE(na.bits, 8);
  const PolyData back = read_draco(path);
  double worst = 0;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    double e2 = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = back.point_data.get("Normals").get(i, c) - m.point_data.get("Normals").get(i, c);
      e2 += d * d;
    }
    worst = std::max(worst, std::sqrt(e2));
  }
  EXPECT_LE(worst, 1e-3);
  EXPECT_DOUBLE_EQ(worst, na.max_error);
}

TEST(Draco, PointCloud) {
  PolyData m;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2, 3);
  DataArray s("s", ScalarType::Float32, 1, 0);
  for (int i = 0; i < 1000; ++i) {
    m.points.push_back({u(rng), u(rng), 0.1 * u(rng)});
    m.verts.add({i});
    const double v = u(rng);
    s.push_back(std::span<const double>(&v, 1));
  }
  m.point_data.add(std::move(s));
  for (DracoMethod method : {DracoMethod::Sequential, DracoMethod::Edgebreaker}) {
    DracoWriteOptions o;
    o.method = method;
    o.max_position_error = 1e-3;
    o.max_array_errors = {{"s", 1e-3}};
    const fs::path path = scratch(method == DracoMethod::Sequential ? "seq" : "kd") / "pc.drc";
    const DracoStats st = write_checked(m, path, o);
    EXPECT_EQ(st.triangles, 0u);
    const PolyData back = read_draco(path);
    EXPECT_EQ(back.points.size(), 1000u);
    EXPECT_EQ(back.verts.size(), 1000u);
    EXPECT_TRUE(back.polys.empty());
    ASSERT_TRUE(back.point_data.has("s"));
    EXPECT_LE(max_nearest_distance(m, back, 1e-3), 1e-3);
    if (method == DracoMethod::Sequential) {
      for (std::size_t i = 0; i < 1000; ++i) EXPECT_LE(norm(back.points[i] - m.points[i]), 1e-3);
    }
  }
}

TEST(Draco, QuadsAndStripsAreTriangulated) {
  PolyData m = square();
  m.polys = CellArray();
  m.polys.add({0, 1, 2, 3});  // one quad: two triangles
  m.points.push_back({2, 0, 0});
  m.points.push_back({2, 1, 0});
  m.strips.add({1, 4, 2, 5});  // a strip of two triangles
  DracoWriteOptions o;
  o.method = DracoMethod::Sequential;
  const fs::path path = scratch("q") / "q.drc";
  const DracoStats st = write_checked(m, path, o);
  EXPECT_EQ(st.triangles, 4u);
  const PolyData back = read_draco(path);
  ASSERT_EQ(back.polys.size(), 4u);
  // Fan of the quad, then the strip with every other triangle flipped (consistent orientation).
  const std::vector<std::vector<Index>> want = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}, {2, 4, 5}};
  for (std::size_t f = 0; f < 4; ++f) {
    const auto c = back.polys.cell(f);
    EXPECT_EQ(std::vector<Index>(c.begin(), c.end()), want[f]) << f;
  }
}

TEST(Draco, DegenerateInputFacesAreCountedAndExplained) {
  PolyData m = square();
  m.polys.add({1, 1, 3});  // repeated point: Edgebreaker drops it
  DracoWriteOptions o;
  o.max_position_error = 1e-3;
  const fs::path path = scratch("d") / "d.drc";
  const DracoStats st = write_checked(m, path, o);
  EXPECT_EQ(st.triangles, 3u);
  EXPECT_EQ(st.degenerate_input_triangles, 1u);
  EXPECT_EQ(st.lost_triangles, 1u);
  EXPECT_EQ(st.decoded_triangles, 2u);
  EXPECT_NE(st.note.find("degenerate in the input"), std::string::npos) << st.note;
}

TEST(Draco, LinesAndMixedCellsAreRefused) {
  PolyData m = square();
  m.lines.add({0, 1});
  expect_error([&] { (void)encode_draco(m); }, "Draco has no lines");
  PolyData v = square();
  v.verts.add({0});
  expect_error([&] { (void)encode_draco(v); }, "not both");
}

TEST(Draco, OptionsAreValidated) {
  const PolyData m = square();
  const auto with = [&](auto set, const std::string& text) {
    DracoWriteOptions o;
    set(o);
    expect_error([&] { (void)encode_draco(m, o, "out.drc"); }, text);
  };
  with([](DracoWriteOptions& o) { o.bits.position = 0; }, "position quantization bits");
  with([](DracoWriteOptions& o) { o.bits.normal = 31; }, "normal quantization bits");
  with([](DracoWriteOptions& o) { o.level = 11; }, "compression level");
  with([](DracoWriteOptions& o) { o.max_position_error = -1; }, "finite and >= 0");
  with([](DracoWriteOptions& o) { o.max_position_error = NAN; }, "finite");
  with([](DracoWriteOptions& o) {
    o.max_position_error = 1;
    o.max_position_error_relative = 1;
  }, "not both");
  with([](DracoWriteOptions& o) { o.max_array_errors = {{"nope", 1}}; }, "not a point array");
  with([](DracoWriteOptions& o) { o.max_array_errors = {{"x", 0}}; }, "> 0");
  PolyData a = square_with_arrays();
  DracoWriteOptions o;
  o.max_array_errors = {{"ids", 1}};
  expect_error([&] { (void)encode_draco(a, o, "out.drc"); }, "integer arrays are stored exactly");
}

TEST(Draco, DispatchByExtension) {
  const PolyData m = square_with_arrays();
  const fs::path path = scratch("io") / "m.drc";
  WriteOptions wo;
  wo.draco.method = DracoMethod::Sequential;
  write(m, path, wo);
  const Dataset back = read(path);
  ASSERT_TRUE(std::holds_alternative<PolyData>(back));
  EXPECT_EQ(std::get<PolyData>(back).polys, m.polys);
  EXPECT_EQ(format_from_path("x.DRC"), FileFormat::Draco);
  ImageData img;
  expect_error([&] { write(img, scratch("io") / "i.drc", wo); }, "polygonal data only");
}

TEST(Draco, CodecReportsAttributeIdsAndDecodedMesh) {
  const PolyData m = square_with_arrays();
  const io_detail::DracoEncodedMesh e = io_detail::encode_draco_mesh(m, {});
  ASSERT_EQ(e.attributes.size(), 1 + m.point_data.size());
  EXPECT_EQ(e.attributes[0].kind, io_detail::DracoKind::Position);
  const auto kind_of = [&](const std::string& n) {
    return std::find_if(e.attributes.begin(), e.attributes.end(),
                        [&](const auto& a) { return a.name == n; })->kind;
  };
  EXPECT_EQ(kind_of("Normals"), io_detail::DracoKind::Normal);
  EXPECT_EQ(kind_of("Colors"), io_detail::DracoKind::Color);
  EXPECT_EQ(kind_of("TCoords"), io_detail::DracoKind::TexCoord);
  EXPECT_EQ(kind_of("ids"), io_detail::DracoKind::Generic);
  // The ids are the ones a decoder sees.
  const auto d = io_detail::decode_draco_mesh(
      std::span<const std::byte>(reinterpret_cast<const std::byte*>(e.bytes.data()), e.bytes.size()),
      "mem");
  for (const auto& a : e.attributes) {
    const auto it = std::find_if(d.attributes.begin(), d.attributes.end(),
                                 [&](const auto& b) { return b.name == a.name; });
    ASSERT_NE(it, d.attributes.end()) << a.name;
    EXPECT_EQ(it->unique_id, a.unique_id) << a.name;
  }
  EXPECT_EQ(e.decoded.points.size(), e.stats.decoded_points);
  EXPECT_EQ(e.decoded.polys.size(), 2u);
  // Skipping an array leaves it out.
  io_detail::DracoRoles r;
  r.skip = {"ids"};
  EXPECT_EQ(io_detail::encode_draco_mesh(m, {}, r).attributes.size(), m.point_data.size());
}

TEST(Draco, CorruptAndTruncatedInputGiveErrors) {
  PolyData m = bunny();
  m.point_data.add(DataArray::from_vector<float>("s", 1, std::vector<float>(m.points.size(), 1)));
  const auto [bytes8, st] = encode_draco(m, {});
  const std::vector<std::byte> bytes(reinterpret_cast<const std::byte*>(bytes8.data()),
                                     reinterpret_cast<const std::byte*>(bytes8.data()) + bytes8.size());
  const auto read = [](const std::vector<std::byte>& b) { return read_draco(b, "x.drc"); };
  // Every truncation is an Error naming the file (never a crash or another exception).
  int rejected = 0, tried = 0;
  for (std::size_t n = 0; n < bytes.size(); n += std::max<std::size_t>(1, bytes.size() / 97)) {
    const std::vector<std::byte> part(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    ++tried;
    rejected += test::rejects_only_with_error(read, part, "prefix " + std::to_string(n));
  }
  EXPECT_EQ(rejected, tried);
  expect_error([&] { (void)read(std::vector<std::byte>(bytes.begin(), bytes.begin() + 3)); },
               "x.drc: not a Draco file");
  // Random damage: an Error or a valid mesh, nothing else.
  std::mt19937 rng(11);
  for (int k = 0; k < 200; ++k) {
    (void)test::rejects_only_with_error(read, test::mutate(bytes, rng, 1 + k % 4, std::string_view("\0\1\2\377", 4)),
                                        "mutation " + std::to_string(k));
  }
  // A header that claims 2^31 - 1 points in 15 bytes is refused before Draco allocates them
  // (a point cloud, sequential, no metadata, then the int32 count).
  std::vector<std::byte> lying;
  for (int b : {0x44, 0x52, 0x41, 0x43, 0x4f, 2, 3, 0, 0, 0, 0, 0xff, 0xff, 0xff, 0x7f}) {  // "DRACO" 2.3
    lying.push_back(static_cast<std::byte>(b));
  }
  expect_error([&] { (void)read(lying); }, "x.drc: corrupt Draco data: 2147483647 points in 15 bytes");
  // A missing file names the path.
  expect_error([] { (void)read_draco(fs::path("/nonexistent/x.drc")); }, "/nonexistent/x.drc");
}
