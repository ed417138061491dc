// Tests for the PLOT3D grid + solution reader.

#include "support/mutate.hpp"
#include "support/scratch.hpp"
#include "isoforge/io/plot3d.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "isoforge/io/io.hpp"

using namespace isoforge;
namespace fs = std::filesystem;
using isoforge::test::data_path;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("plot3d", name);
}

void write_bytes(const fs::path& p, const std::vector<std::byte>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// Builds PLOT3D binary files in the test (independently of the reader).
class Writer {
 public:
  explicit Writer(bool big) : big_(big) {}
  template <class T>
  Writer& put(T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_ != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
    for (unsigned char c : b) bytes_.push_back(static_cast<std::byte>(c));
    return *this;
  }
  Writer& real(double v, bool dbl) { return dbl ? put(v) : put(static_cast<float>(v)); }
  std::vector<std::byte>& bytes() { return bytes_; }

 private:
  bool big_;
  std::vector<std::byte> bytes_;
};

struct Spec {
  Dims dims{4, 3, 2};
  bool big = false;
  bool ngrid = false;
  bool dbl = false;
  bool iblank = false;
};

double coord(int axis, Index i, Index j, Index k) {
  if (axis == 0) return static_cast<double>(i) + 0.5 * static_cast<double>(j);
  if (axis == 1) return 2.0 * static_cast<double>(j) - 0.25 * static_cast<double>(k);
  return 3.0 * static_cast<double>(k) + 0.125 * static_cast<double>(i);
}

/// iblank: point (1, 1, 1) blanked (0), point (0, 0, 0) = 2 (a boundary flag, still valid).
std::int32_t iblank_of(Index i, Index j, Index k) {
  if (i == 1 && j == 1 && k == 1) return 0;
  if (i == 0 && j == 0 && k == 0) return 2;
  return 1;
}

std::vector<std::byte> make_xyz(const Spec& s) {
  Writer w(s.big);
  if (s.ngrid) w.put(std::int32_t{1});
  for (Index d : s.dims) w.put(static_cast<std::int32_t>(d));
  for (int a = 0; a < 3; ++a) {
    for (Index k = 0; k < s.dims[2]; ++k)
      for (Index j = 0; j < s.dims[1]; ++j)
        for (Index i = 0; i < s.dims[0]; ++i) w.real(coord(a, i, j, k), s.dbl);
  }
  if (s.iblank) {
    for (Index k = 0; k < s.dims[2]; ++k)
      for (Index j = 0; j < s.dims[1]; ++j)
        for (Index i = 0; i < s.dims[0]; ++i) w.put(iblank_of(i, j, k));
  }
  return w.bytes();
}

/// Q values: density 1 + id/8 (point 5 has density 0), momentum (id, -id, 2 id), energy 10 id.
double q_value(int var, std::size_t id) {
  const double d = static_cast<double>(id);
  switch (var) {
    case 0:
      return id == 5 ? 0.0 : 1.0 + d / 8.0;
    case 1:
      return d;
    case 2:
      return -d;
    case 3:
      return 2.0 * d;
    default:
      return 10.0 * d;
  }
}

std::vector<std::byte> make_q(const Spec& s, Dims dims) {
  Writer w(s.big);
  if (s.ngrid) w.put(std::int32_t{1});
  for (Index d : dims) w.put(static_cast<std::int32_t>(d));
  for (double v : {0.5, 10.0, 1.0e6, 2.5}) w.real(v, s.dbl);
  const std::size_t n = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
  for (int var = 0; var < 5; ++var) {
    for (std::size_t i = 0; i < n; ++i) w.real(q_value(var, i), s.dbl);
  }
  return w.bytes();
}

std::uint32_t be32(const std::vector<std::byte>& b, std::size_t off) {
  return (std::to_integer<std::uint32_t>(b[off]) << 24) |
         (std::to_integer<std::uint32_t>(b[off + 1]) << 16) |
         (std::to_integer<std::uint32_t>(b[off + 2]) << 8) |
         std::to_integer<std::uint32_t>(b[off + 3]);
}
float be_float(const std::vector<std::byte>& b, std::size_t off) {
  const std::uint32_t u = be32(b, off);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

void expect_error_with(const std::function<void()>& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& p : parts) {
      EXPECT_NE(msg.find(p), std::string::npos) << "message '" << msg << "' lacks '" << p << "'";
    }
  }
}

void check_grid(const StructuredGrid& g, const Spec& s) {
  ASSERT_EQ(g.dims, s.dims);
  EXPECT_EQ(g.points.type(), s.dbl ? ScalarType::Float64 : ScalarType::Float32);
  for (Index k = 0; k < s.dims[2]; ++k)
    for (Index j = 0; j < s.dims[1]; ++j)
      for (Index i = 0; i < s.dims[0]; ++i) {
        const Vec3 p = g.points[static_cast<std::size_t>(g.point_id(i, j, k))];
        for (int a = 0; a < 3; ++a) ASSERT_EQ(p[a], coord(a, i, j, k)) << i << " " << j << " " << k;
      }
  EXPECT_NO_THROW(g.validate());
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The real combustor

TEST(Plot3d, ReadsTheCombustor) {
  const StructuredGrid g = read_plot3d(data_path("combxyz.bin"), data_path("combq.bin"));
  EXPECT_EQ(g.dims, (Dims{57, 33, 25}));
  ASSERT_EQ(g.num_points(), 47025u);
  EXPECT_EQ(g.num_cells(), 56u * 32u * 24u);
  EXPECT_EQ(g.points.type(), ScalarType::Float32);
  const Bounds b = g.bounds();
  EXPECT_NEAR(b.min.x, 0.0, 0.01);
  EXPECT_NEAR(b.max.x, 16.51, 0.01);
  EXPECT_NEAR(b.min.y, -5.66, 0.01);
  EXPECT_NEAR(b.max.y, 5.66, 0.01);
  EXPECT_NEAR(b.min.z, 23.33, 0.01);
  EXPECT_NEAR(b.max.z, 36.19, 0.01);

  // Coordinates against the raw big-endian bytes, read independently.
  const auto raw = read_file_bytes(data_path("combxyz.bin"));
  ASSERT_EQ(raw.size(), 564312u);
  EXPECT_EQ(be32(raw, 0), 57u);
  for (std::size_t id : {0u, 1234u, 47024u}) {
    const Vec3 p = g.points[id];
    EXPECT_EQ(static_cast<float>(p.x), be_float(raw, 12 + 4 * id));
    EXPECT_EQ(static_cast<float>(p.y), be_float(raw, 12 + 4 * (47025 + id)));
    EXPECT_EQ(static_cast<float>(p.z), be_float(raw, 12 + 4 * (2 * 47025 + id)));
  }

  const DataArray* density = g.point_data.scalars();
  ASSERT_NE(density, nullptr);
  EXPECT_EQ(density->name(), "Density");
  EXPECT_EQ(density->type(), ScalarType::Float32);
  const auto [dmin, dmax] = density->range();
  EXPECT_NEAR(dmin, 0.198, 0.001);
  EXPECT_NEAR(dmax, 0.710, 0.001);
  const auto [emin, emax] = g.point_data.get("StagnationEnergy").range();
  EXPECT_EQ(emin, 0.0);
  EXPECT_EQ(emax, 0.0);
  const DataArray* momentum = g.point_data.vectors();
  ASSERT_NE(momentum, nullptr);
  EXPECT_EQ(momentum->name(), "Momentum");
  EXPECT_EQ(momentum->components(), 3);
  double max_abs = 0;
  for (int c = 0; c < 3; ++c) {
    const auto [lo, hi] = momentum->range(c);
    max_abs = std::max({max_abs, std::abs(lo), std::abs(hi)});
  }
  EXPECT_GT(max_abs, 300.0);
  EXPECT_LT(max_abs, 420.0);
  // Density against the Q file's bytes: header 12 + 4 reals.
  const auto q = read_file_bytes(data_path("combq.bin"));
  EXPECT_EQ(static_cast<float>(density->get(777)), be_float(q, 28 + 4 * 777));
  EXPECT_EQ(static_cast<float>(momentum->get(777, 2)), be_float(q, 28 + 4 * (3 * 47025 + 777)));

  for (const char* f : {"FreeStreamMach", "AngleOfAttack", "ReynoldsNumber", "Time"}) {
    ASSERT_TRUE(g.field_data.has(f)) << f;
    EXPECT_EQ(g.field_data.get(f).tuples(), 1u);
    EXPECT_EQ(g.field_data.get(f).get(0), 0.0);
  }

  // Derived quantities.
  const DataArray& vel = g.point_data.get("Velocity");
  const DataArray& pres = g.point_data.get("Pressure");
  for (std::size_t id : {0u, 100u, 23456u, 47024u}) {
    const double rho = density->get(id);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(vel.get(id, c) * rho, momentum->get(id, c),
                  1e-4 * (1 + std::abs(momentum->get(id, c))));
    }
  }
  const std::size_t id = 31415;
  const double rho = density->get(id);
  double m2 = 0;
  for (int c = 0; c < 3; ++c) m2 += momentum->get(id, c) * momentum->get(id, c);
  const double expected_p = 0.4 * (0.0 - 0.5 * m2 / rho);
  EXPECT_NEAR(pres.get(id), expected_p, 1e-5 * std::abs(expected_p));
  EXPECT_NO_THROW(g.validate());
}

TEST(Plot3d, CombustorGridOnlyAndForcedByteOrder) {
  const StructuredGrid g = read_plot3d(data_path("combxyz.bin"));
  EXPECT_EQ(g.num_points(), 47025u);
  EXPECT_TRUE(g.point_data.empty());
  Plot3dOptions big;
  big.byte_order = Plot3dByteOrder::Big;
  EXPECT_EQ(read_plot3d(data_path("combxyz.bin"), {}, big).points, g.points);
  Plot3dOptions little;
  little.byte_order = Plot3dByteOrder::Little;
  expect_error_with([&] { (void)read_plot3d(data_path("combxyz.bin"), {}, little); },
                    {"combxyz.bin", "byte 0",
                     "file size 564312 bytes matches no PLOT3D grid layout", "little endian"});
}

TEST(Plot3d, TruncatedCombustorIsAlwaysAnError) {
  const auto xyz = read_file_bytes(data_path("combxyz.bin"));
  const auto q = read_file_bytes(data_path("combq.bin"));
  for (std::size_t k = 0; k < 60; ++k) {
    const std::size_t n = k < 20 ? k : xyz.size() * k / 60;
    std::vector<std::byte> part(xyz.begin(), xyz.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THROW((void)read_plot3d(part, "combxyz.bin", {}, ""), Error) << n;
    const std::size_t m = k < 20 ? k : q.size() * k / 60;
    std::vector<std::byte> qpart(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(m));
    EXPECT_THROW((void)read_plot3d(xyz, "combxyz.bin", qpart, "combq.bin"), Error) << m;
  }
  // One byte short and one byte long.
  std::vector<std::byte> shorter(xyz.begin(), xyz.end() - 1);
  expect_error_with([&] { (void)read_plot3d(shorter, "combxyz.bin", {}, ""); },
                    {"combxyz.bin: byte 0", "564311 bytes", "big endian: dims 57 x 33 x 25",
                     "564312 (float32)", "752412 (float32 + iblank)"});
  std::vector<std::byte> qlonger = q;
  qlonger.push_back(std::byte{0});
  expect_error_with([&] { (void)read_plot3d(xyz, "combxyz.bin", qlonger, "combq.bin"); },
                    {"combq.bin: byte 0", "Q file size 940529", "940528 (float32)"});
}

// ---------------------------------------------------------------------------------------------
// Hand-made files

TEST(Plot3d, LittleEndianFloat32) {
  Spec s;
  const StructuredGrid g = read_plot3d(make_xyz(s), "le.xyz", {}, "");
  check_grid(g, s);
  EXPECT_FALSE(g.point_data.has("IBlank"));
}

TEST(Plot3d, BigEndianWithIblank) {
  Spec s;
  s.big = true;
  s.iblank = true;
  const StructuredGrid g = read_plot3d(make_xyz(s), "ib.xyz", {}, "");
  check_grid(g, s);
  const DataArray& ib = g.point_data.get("IBlank");
  EXPECT_EQ(ib.type(), ScalarType::Int32);
  EXPECT_EQ(ib.get(static_cast<std::size_t>(g.point_id(1, 1, 1))), 0);
  EXPECT_EQ(ib.get(0), 2);
  EXPECT_EQ(ib.get(static_cast<std::size_t>(g.point_id(3, 2, 1))), 1);
  const DataArray& valid = g.cell_data.get("Valid");
  EXPECT_EQ(valid.type(), ScalarType::UInt8);
  ASSERT_EQ(valid.tuples(), 3u * 2u * 1u);
  // Cells (ci, cj, 0) touching point (1, 1, 1): ci in {0, 1}, cj in {0, 1}.
  for (Index cj = 0; cj < 2; ++cj) {
    for (Index ci = 0; ci < 3; ++ci) {
      const bool touches = ci <= 1;
      EXPECT_EQ(valid.get(static_cast<std::size_t>(ci + 3 * cj)), touches ? 0 : 1)
          << ci << " " << cj;
    }
  }
}

TEST(Plot3d, GridCountHeaderAndFloat64WithQ) {
  for (bool big : {false, true}) {
    Spec s;
    s.ngrid = true;
    s.dbl = true;
    s.big = big;
    s.dims = {3, 4, 5};
    const auto xyz = make_xyz(s);
    const auto q = make_q(s, s.dims);
    const StructuredGrid g = read_plot3d(xyz, "ng.xyz", q, "ng.q");
    check_grid(g, s);
    const DataArray& rho = g.point_data.get("Density");
    EXPECT_EQ(rho.type(), ScalarType::Float64);
    EXPECT_EQ(rho.get(7), 1.0 + 7.0 / 8.0);
    EXPECT_EQ(g.point_data.get("Momentum").get(7, 1), -7.0);
    EXPECT_EQ(g.point_data.get("StagnationEnergy").get(7), 70.0);
    EXPECT_EQ(g.field_data.get("FreeStreamMach").get(0), 0.5);
    EXPECT_EQ(g.field_data.get("AngleOfAttack").get(0), 10.0);
    EXPECT_EQ(g.field_data.get("ReynoldsNumber").get(0), 1.0e6);
    EXPECT_EQ(g.field_data.get("Time").get(0), 2.5);
    const DataArray& vel = g.point_data.get("Velocity");
    EXPECT_DOUBLE_EQ(vel.get(7, 0), 7.0 / (1.0 + 7.0 / 8.0));
    EXPECT_DOUBLE_EQ(vel.get(7, 2), 14.0 / (1.0 + 7.0 / 8.0));
    // Density 0: zero velocity, pressure (gamma - 1) e, no NaN.
    EXPECT_EQ(vel.get(5, 0), 0.0);
    EXPECT_EQ(vel.get(5, 1), 0.0);
    EXPECT_DOUBLE_EQ(g.point_data.get("Pressure").get(5), 0.4 * 50.0);
    const double r = 1.0 + 7.0 / 8.0;
    const double v2 = (49.0 + 49.0 + 196.0) / (r * r);
    EXPECT_NEAR(g.point_data.get("Pressure").get(7), 0.4 * (70.0 - 0.5 * r * v2), 1e-12);
  }
}

TEST(Plot3d, QWithoutGridCountAndCustomGamma) {
  Spec s;
  Spec qs = s;
  qs.ngrid = true;  // the Q file may carry a grid count even when the grid does not
  Plot3dOptions o;
  o.gamma = 1.3;
  const StructuredGrid g = read_plot3d(make_xyz(s), "a.xyz", make_q(qs, s.dims), "a.q", o);
  const double r = 1.0 + 3.0 / 8.0;
  const double v2 = (9.0 + 9.0 + 36.0) / (r * r);
  EXPECT_NEAR(g.point_data.get("Pressure").get(3), 0.3 * (30.0 - 0.5 * r * v2), 1e-5);
  EXPECT_EQ(g.point_data.get("Density").type(), ScalarType::Float32);
}

TEST(Plot3d, FilesOnDiskAndMissingFiles) {
  const fs::path dir = scratch("disk");
  Spec s;
  s.iblank = true;
  write_bytes(dir / "g.xyz", make_xyz(s));
  write_bytes(dir / "g.q", make_q(s, s.dims));
  const StructuredGrid g = read_plot3d(dir / "g.xyz", dir / "g.q");
  check_grid(g, s);
  EXPECT_TRUE(g.point_data.has("Pressure"));
  EXPECT_THROW((void)read_plot3d(dir / "missing.xyz"), Error);
  expect_error_with([&] { (void)read_plot3d(dir / "g.xyz", dir / "missing.q"); }, {"missing.q"});
  write_bytes(dir / "empty.q", {});
  expect_error_with([&] { (void)read_plot3d(dir / "g.xyz", dir / "empty.q"); },
                    {"empty.q", "truncated"});
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(Plot3dBad, SizeMatchesNoLayout) {
  auto b = make_xyz(Spec{});
  b.resize(b.size() + 4);
  expect_error_with(
      [&] { (void)read_plot3d(b, "odd.xyz", {}, ""); },
      {"odd.xyz: byte 0", "matches no PLOT3D grid layout", "dims 4 x 3 x 2", "300 (float32)",
       "396 (float32 + iblank)", "588 (float64)", "684 (float64 + iblank)"});
}

TEST(Plot3dBad, TruncatedHeader) {
  const auto b = make_xyz(Spec{});
  std::vector<std::byte> part(b.begin(), b.begin() + 8);
  expect_error_with([&] { (void)read_plot3d(part, "short.xyz", {}, ""); },
                    {"short.xyz: byte 0", "truncated", "needs 12 bytes"});
}

TEST(Plot3dBad, NegativeAndOverflowingDims) {
  Writer w(false);
  w.put(std::int32_t{-4}).put(std::int32_t{3}).put(std::int32_t{2});
  for (int i = 0; i < 10; ++i) w.put(0.0f);
  expect_error_with([&] { (void)read_plot3d(w.bytes(), "neg.xyz", {}, ""); },
                    {"neg.xyz", "dims -4 x 3 x 2 (not a valid point count)"});
  Writer o(true);
  o.put(std::int32_t{2147483647}).put(std::int32_t{2147483647}).put(std::int32_t{2147483647});
  expect_error_with([&] { (void)read_plot3d(o.bytes(), "huge.xyz", {}, ""); },
                    {"huge.xyz", "matches no PLOT3D grid layout"});
}

TEST(Plot3dBad, QDimensionsMismatch) {
  Spec s;
  const auto q = make_q(s, Dims{4, 3, 3});
  expect_error_with([&] { (void)read_plot3d(make_xyz(s), "grid.xyz", q, "sol.q"); },
                    {"sol.q: byte 0", "Q file dimensions 4 x 3 x 3",
                     "do not match the grid file grid.xyz", "(4 x 3 x 2)"});
}

TEST(Plot3dBad, QSizeMismatch) {
  Spec s;
  auto q = make_q(s, s.dims);
  q.resize(q.size() - 4);
  expect_error_with([&] { (void)read_plot3d(make_xyz(s), "grid.xyz", q, "sol.q"); },
                    {"sol.q: byte 0", "matches no layout for dims 4 x 3 x 2"});
}

TEST(Plot3dBad, NonFiniteCoordinate) {
  Spec s;
  auto b = make_xyz(s);
  // y of point 5 (i=1, j=1, k=0): offset 12 + 4 * (24 + 5).
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(b.data() + 12 + 4 * 29, &nan, 4);
  expect_error_with(
      [&] { (void)read_plot3d(b, "nan.xyz", {}, ""); },
      {"nan.xyz: byte 128", "point 5 (i, j, k = 1, 1, 0) has a non-finite y coordinate"});
}

TEST(Plot3dBad, EmptyQWithAName) {
  expect_error_with([&] { (void)read_plot3d(make_xyz(Spec{}), "g.xyz", {}, "g.q"); },
                    {"g.q", "truncated"});
}

TEST(Plot3dBad, NonFiniteGamma) {
  Plot3dOptions o;
  o.gamma = std::nan("");
  expect_error_with([&] { (void)read_plot3d(make_xyz(Spec{}), "g.xyz", {}, "", o); },
                    {"g.xyz", "gamma"});
}

TEST(Plot3dBad, TruncationsAndMutationsOnlyThrowError) {
  Spec s;
  s.iblank = true;
  s.ngrid = true;
  const auto xyz = make_xyz(s);
  const auto q = make_q(s, s.dims);
  // The file is 16 + 24 * 16 = 400 bytes. A few prefixes are themselves valid layouts: 304 is
  // the grid without its IBLANK block, and read without the grid count the header says 1 x 4 x 3
  // (12 points), which fits 12 + 12 * {12, 16, 24, 28} = 156, 204, 300, 348 bytes.
  const std::vector<std::size_t> valid_prefixes = {156, 204, 300, 304, 348};
  for (std::size_t n = 0; n < xyz.size(); ++n) {
    std::vector<std::byte> part(xyz.begin(), xyz.begin() + static_cast<std::ptrdiff_t>(n));
    if (std::find(valid_prefixes.begin(), valid_prefixes.end(), n) != valid_prefixes.end()) {
      EXPECT_NO_THROW((void)read_plot3d(part, "t.xyz", {}, "")) << n;
    } else {
      EXPECT_THROW((void)read_plot3d(part, "t.xyz", {}, ""), Error) << n;
    }
  }
  for (std::size_t n = 0; n < q.size(); ++n) {
    std::vector<std::byte> part(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THROW((void)read_plot3d(xyz, "t.xyz", part, "t.q"), Error) << n;
  }
  std::mt19937 rng(7);
  for (int r = 0; r < 3000; ++r) {
    auto b = xyz;
    auto c = q;
    for (int e = 0; e < 3; ++e) {
      b[rng() % 16] = static_cast<std::byte>(rng() % 256);
      c[rng() % 16] = static_cast<std::byte>(rng() % 256);
      b[rng() % b.size()] = static_cast<std::byte>(rng() % 256);
    }
    const auto read = [&](const auto& bytes) { return read_plot3d(bytes, "m.xyz", c, "m.q"); };
    (void)test::rejects_only_with_error(read, b, "mutation " + std::to_string(r));
  }
}
