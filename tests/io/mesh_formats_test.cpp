// Tests for the PLY reader/writer, the OFF reader/writer and the OBJ writer.

#include "support/mutate.hpp"
#include "support/scratch.hpp"
#include "isoforge/io/off_obj.hpp"
#include "isoforge/io/ply.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>

#include "isoforge/io/io.hpp"

using namespace isoforge;
namespace fs = std::filesystem;
using isoforge::test::data_path;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("mesh_formats", name);
}

std::vector<std::byte> bytes_of(const std::string& s) {
  const auto* p = reinterpret_cast<const std::byte*>(s.data());
  return std::vector<std::byte>(p, p + s.size());  // (memcpy into an empty vector's null data is UB)
}

using isoforge::test::slurp;

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

/// Expects read(bytes) to throw isoforge::Error whose message contains every `parts`.
template <class Reader>
void expect_error(Reader read, const std::string& text, std::initializer_list<std::string> parts) {
  const auto b = bytes_of(text);
  try {
    (void)read(b);
    ADD_FAILURE() << "no error for input:\n" << text.substr(0, 300);
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& p : parts) {
      EXPECT_NE(msg.find(p), std::string::npos) << "message '" << msg << "' lacks '" << p << "'";
    }
  }
}

auto ply_reader() {
  return [](const std::vector<std::byte>& b) { return read_ply(b, "bad.ply"); };
}
auto off_reader() {
  return [](const std::vector<std::byte>& b) { return read_off(b, "bad.off"); };
}

/// Calls `read` on every prefix in `offsets` (and random mutations): only isoforge::Error may
/// escape. Returns how many prefixes were rejected.
template <class Reader>
std::size_t prefixes_only_throw_error(Reader read, const std::vector<std::byte>& full,
                                      const std::vector<std::size_t>& offsets) {
  std::size_t rejected = 0;
  for (std::size_t n : offsets) {
    if (n > full.size()) continue;
    const std::vector<std::byte> part(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
    rejected += test::rejects_only_with_error(read, part, "prefix " + std::to_string(n));
  }
  return rejected;
}

std::vector<std::size_t> all_offsets(std::size_t size) {
  std::vector<std::size_t> v;
  for (std::size_t i = 0; i < size; ++i) v.push_back(i);
  return v;
}

template <class Reader>
void random_mutations_only_throw_error(Reader read, const std::vector<std::byte>& base,
                                       int rounds) {
  std::mt19937 rng(12345);
  for (int r = 0; r < rounds; ++r) {
    const int edits = 1 + static_cast<int>(rng() % 4);
    (void)test::rejects_only_with_error(read, test::mutate(base, rng, edits, "0123456789-e.# \n"),
                                        "mutation round " + std::to_string(r));
  }
}

/// A small mesh with every kind of point and cell array the PLY writer maps.
PolyData attribute_mesh(ScalarType point_type) {
  PolyData m;
  m.points = Points(6, point_type);
  const double coords[6][3] = {{0, 0, 0},   {1, 0, 0},      {1, 1, 0},
                               {0, 1, 0.1}, {0.5, 2, -0.3}, {1.0 / 3.0, 2.5, 1e-7}};
  for (std::size_t i = 0; i < 6; ++i) m.points.set(i, {coords[i][0], coords[i][1], coords[i][2]});
  m.polys.add({0, 1, 2, 3});
  m.polys.add({3, 2, 4});
  m.strips.add({2, 4, 5, 3});  // two triangles when written

  DataArray normals("Normals", ScalarType::Float32, 3, 6);
  DataArray colors("Colors", ScalarType::UInt8, 4, 6);
  DataArray tc("TCoords", ScalarType::Float32, 2, 6);
  DataArray temp("temperature", ScalarType::Float64, 1, 6);
  DataArray label("label", ScalarType::Int16, 1, 6);
  DataArray vec("flow", ScalarType::Float32, 3, 6);
  for (std::size_t i = 0; i < 6; ++i) {
    const double d = static_cast<double>(i);
    normals.set(i, 0, std::sin(d));
    normals.set(i, 1, std::cos(d));
    normals.set(i, 2, 0.25 * d);
    for (int c = 0; c < 4; ++c) colors.set(i, c, static_cast<double>((37 * i + 61 * c) % 256));
    tc.set(i, 0, d / 6.0);
    tc.set(i, 1, 1.0 - d / 7.0);
    temp.set(i, 0, 273.15 + d / 3.0);
    label.set(i, 0, -1000 + 500 * d);
    for (int c = 0; c < 3; ++c) vec.set(i, c, d * 10 + c + 0.5);
  }
  m.point_data.add(std::move(normals), AttributeRole::Normals);
  m.point_data.add(std::move(colors), AttributeRole::Scalars);
  m.point_data.add(std::move(tc), AttributeRole::TCoords);
  m.point_data.add(std::move(temp));
  m.point_data.add(std::move(label));
  m.point_data.add(std::move(vec));
  DataArray region("region", ScalarType::Int32, 1, 3);
  DataArray quality("quality", ScalarType::Float32, 1, 3);
  for (std::size_t c = 0; c < 3; ++c) {
    region.set(c, 0, 7 - 3 * static_cast<double>(c));
    quality.set(c, 0, 0.125 * static_cast<double>(c + 1));
  }
  m.cell_data.add(std::move(region));
  m.cell_data.add(std::move(quality));
  return m;
}

void expect_arrays_equal(const DataArray& a, const DataArray& b, const std::string& what) {
  ASSERT_EQ(a.type(), b.type()) << what;
  ASSERT_EQ(a.components(), b.components()) << what;
  ASSERT_EQ(a.tuples(), b.tuples()) << what;
  for (std::size_t t = 0; t < a.tuples(); ++t) {
    for (int c = 0; c < a.components(); ++c) {
      EXPECT_EQ(a.get(t, c), b.get(t, c)) << what << " tuple " << t << " comp " << c;
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// PLY: the real bunny

TEST(Ply, ReadsTheStanfordBunny) {
  const PolyData m = read_ply(data_path("bunny.ply"));
  EXPECT_EQ(m.num_points(), 35947u);
  EXPECT_EQ(m.polys.size(), 69451u);
  EXPECT_EQ(m.polys.connectivity().size(), 3u * 69451u);
  for (std::size_t c = 0; c < m.polys.size(); ++c) ASSERT_EQ(m.polys.cell_size(c), 3u);
  EXPECT_TRUE(m.verts.empty());
  EXPECT_TRUE(m.lines.empty());
  EXPECT_TRUE(m.strips.empty());
  EXPECT_EQ(m.points.type(), ScalarType::Float32);
  ASSERT_TRUE(m.point_data.has("confidence"));
  ASSERT_TRUE(m.point_data.has("intensity"));
  EXPECT_EQ(m.point_data.size(), 2u);
  EXPECT_EQ(m.point_data.get("confidence").type(), ScalarType::Float32);
  EXPECT_EQ(m.point_data.get("confidence").tuples(), 35947u);
  // First vertex line: -0.0378297 0.12794 0.00447467 0.850855 0.5
  EXPECT_FLOAT_EQ(static_cast<float>(m.points[0].x), -0.0378297f);
  EXPECT_FLOAT_EQ(static_cast<float>(m.points[0].y), 0.12794f);
  EXPECT_FLOAT_EQ(static_cast<float>(m.points[0].z), 0.00447467f);
  EXPECT_FLOAT_EQ(static_cast<float>(m.point_data.get("confidence").get(0)), 0.850855f);
  EXPECT_FLOAT_EQ(static_cast<float>(m.point_data.get("intensity").get(0)), 0.5f);
  const Bounds b = m.bounds();
  EXPECT_NEAR(b.min.x, -0.0947, 1e-3);
  EXPECT_NEAR(b.max.x, 0.0610, 1e-3);
  EXPECT_NEAR(b.min.y, 0.0330, 1e-3);
  EXPECT_NEAR(b.max.y, 0.1873, 1e-3);
  EXPECT_NO_THROW(m.validate());
}

TEST(Ply, BunnyBinaryRoundTripKeepsEverything) {
  const fs::path dir = scratch("bunny");
  const PolyData m = read_ply(data_path("bunny.ply"));
  for (PlyEncoding enc : {PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian}) {
    write_ply(m, dir / "bunny.ply", {enc});
    const PolyData r = read_ply(dir / "bunny.ply");
    EXPECT_EQ(r.points, m.points);
    EXPECT_EQ(r.polys, m.polys);
    EXPECT_EQ(r.point_data, m.point_data);
  }
  EXPECT_EQ(entries(dir), 1u);
}

TEST(Ply, BinaryRecordsOfManySlicesMatchTheAsciiFile) {
  // Binary vertices and faces are encoded a 1 MiB slice at a time on all threads: a mesh of
  // several slices with point and cell properties of several types, and a polygon longer than
  // a slice (300k vertices: its count is an int), in both byte orders, reads back as the ASCII
  // file (written record by record) does, and with the mesh's points and polygons.
  const fs::path dir = scratch("slices");
  const std::size_t np = 300'000;
  PolyData m;
  m.points = Points(np);
  DataArray temp("temperature", ScalarType::Float64, 1, np);
  DataArray label("label", ScalarType::Int16, 1, np);
  DataArray colors("Colors", ScalarType::UInt8, 4, np);
  for (std::size_t i = 0; i < np; ++i) {
    const double d = static_cast<double>(i);
    m.points.set(i, {std::sin(d), std::cos(d), 1e-4 * d});
    temp.set(i, 0, 273.15 + d / 7.0);
    label.set(i, 0, static_cast<double>(static_cast<std::int16_t>(i * 37)));
    for (int c = 0; c < 4; ++c) colors.set(i, c, static_cast<double>((i + 61 * c) % 256));
  }
  m.point_data.add(std::move(temp));
  m.point_data.add(std::move(label));
  m.point_data.add(std::move(colors), AttributeRole::Scalars);
  for (std::size_t i = 0; i + 2 < np; i += 3) {
    m.polys.add({static_cast<Index>(i), static_cast<Index>(i + 1), static_cast<Index>(i + 2)});
  }
  std::vector<Index> big(np);
  for (std::size_t i = 0; i < np; ++i) big[i] = static_cast<Index>((i * 7) % np);
  m.polys.add(big);
  DataArray material("material", ScalarType::Int32, 1, m.polys.size());
  for (std::size_t f = 0; f < m.polys.size(); ++f)
    material.set(f, 0, static_cast<double>(f % 1000) - 500);
  m.cell_data.add(std::move(material));

  write_ply(m, dir / "a.ply", {PlyEncoding::Ascii});
  const PolyData ascii = read_ply(dir / "a.ply");
  EXPECT_EQ(ascii.polys, m.polys);
  for (PlyEncoding enc : {PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian}) {
    write_ply(m, dir / "b.ply", {enc});
    const PolyData r = read_ply(dir / "b.ply");
    EXPECT_EQ(r.points, m.points);
    EXPECT_EQ(r.polys, m.polys);
    EXPECT_EQ(r.point_data, ascii.point_data);
    EXPECT_EQ(r.cell_data, ascii.cell_data);
    EXPECT_EQ(r.cell_data.size(), 1u);
    EXPECT_GE(r.point_data.size(), 3u);
  }
}

TEST(Ply, TruncatedBunnyOnlyThrowsError) {
  const auto full = read_file_bytes(data_path("bunny.ply"));
  std::vector<std::size_t> offsets;
  for (std::size_t n = 0; n < 400; n += 7) offsets.push_back(n);  // inside the header
  for (std::size_t k = 1; k < 40; ++k) offsets.push_back(full.size() * k / 40);
  const std::size_t rejected = prefixes_only_throw_error(
      [](const auto& b) { return read_ply(b, "bunny.ply"); }, full, offsets);
  EXPECT_EQ(rejected, offsets.size());  // every prefix misses vertices or faces
}

// ---------------------------------------------------------------------------------------------
// PLY: round trips

class PlyRoundTrip : public ::testing::TestWithParam<std::tuple<PlyEncoding, ScalarType>> {};

TEST_P(PlyRoundTrip, KeepsPointsArraysAndFaces) {
  const auto [enc, ptype] = GetParam();
  const fs::path dir = scratch("roundtrip");
  const PolyData m = attribute_mesh(ptype);
  write_ply(m, dir / "m.ply", {enc});
  const PolyData r = read_ply(dir / "m.ply");

  EXPECT_EQ(r.points.type(), ptype);
  EXPECT_EQ(r.points, m.points);
  // Strips come back as triangles after the polys.
  ASSERT_EQ(r.polys.size(), 4u);
  EXPECT_TRUE(r.strips.empty());
  const std::vector<Index> expected_conn = {0, 1, 2, 3, 3, 2, 4, 2, 4, 5, 5, 4, 3};
  EXPECT_EQ(r.polys.connectivity(), expected_conn);

  ASSERT_NE(r.point_data.normals(), nullptr);
  EXPECT_EQ(r.point_data.normals()->name(), "Normals");
  expect_arrays_equal(*r.point_data.normals(), m.point_data.get("Normals"), "normals");
  ASSERT_NE(r.point_data.scalars(), nullptr);
  EXPECT_EQ(r.point_data.scalars()->name(), "Colors");
  expect_arrays_equal(*r.point_data.scalars(), m.point_data.get("Colors"), "colors");
  ASSERT_NE(r.point_data.tcoords(), nullptr);
  expect_arrays_equal(*r.point_data.tcoords(), m.point_data.get("TCoords"), "tcoords");
  expect_arrays_equal(r.point_data.get("temperature"), m.point_data.get("temperature"),
                      "temperature");
  expect_arrays_equal(r.point_data.get("label"), m.point_data.get("label"), "label");
  // Multi-component arrays become name_0, name_1, ...
  for (int c = 0; c < 3; ++c) {
    const DataArray& a = r.point_data.get("flow_" + std::to_string(c));
    ASSERT_EQ(a.type(), ScalarType::Float32);
    for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(a.get(i), m.point_data.get("flow").get(i, c));
  }
  // Cell arrays: the strip's value is repeated for both of its triangles.
  const DataArray& region = r.cell_data.get("region");
  ASSERT_EQ(region.type(), ScalarType::Int32);
  ASSERT_EQ(region.tuples(), 4u);
  EXPECT_EQ(region.get(0), 7);
  EXPECT_EQ(region.get(1), 4);
  EXPECT_EQ(region.get(2), 1);
  EXPECT_EQ(region.get(3), 1);
  EXPECT_EQ(r.cell_data.get("quality").get(3), 0.375);
  EXPECT_NO_THROW(r.validate());
  EXPECT_EQ(entries(dir), 1u);
}

INSTANTIATE_TEST_SUITE_P(
    AllEncodings, PlyRoundTrip,
    ::testing::Combine(::testing::Values(PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian,
                                         PlyEncoding::BinaryBigEndian),
                       ::testing::Values(ScalarType::Float32, ScalarType::Float64)));

TEST(Ply, WrittenHeadersDeclareTheEncodingAndDoubles) {
  const fs::path dir = scratch("headers");
  write_ply(attribute_mesh(ScalarType::Float64), dir / "a.ply", {PlyEncoding::Ascii});
  write_ply(attribute_mesh(ScalarType::Float32), dir / "b.ply", {PlyEncoding::BinaryBigEndian});
  const std::string a = slurp(dir / "a.ply");
  const std::string b = slurp(dir / "b.ply");
  EXPECT_NE(a.find("format ascii 1.0\n"), std::string::npos);
  EXPECT_NE(a.find("property double x\n"), std::string::npos);
  EXPECT_NE(a.find("property float nx\n"), std::string::npos);
  EXPECT_NE(a.find("property uchar alpha\n"), std::string::npos);
  EXPECT_NE(a.find("property float u\n"), std::string::npos);
  EXPECT_NE(a.find("property list uchar int vertex_indices\n"), std::string::npos);
  EXPECT_NE(b.find("format binary_big_endian 1.0\n"), std::string::npos);
  EXPECT_NE(b.find("property float x\n"), std::string::npos);
}

TEST(Ply, RefusesVertsAndLines) {
  const fs::path dir = scratch("refuse");
  PolyData m = attribute_mesh(ScalarType::Float32);
  m.lines.add({0, 1});
  m.cell_data.clear();
  try {
    write_ply(m, dir / "lines.ply");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lines.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("1 lines"), std::string::npos) << e.what();
  }
  PolyData v = attribute_mesh(ScalarType::Float32);
  v.verts.add({0});
  v.cell_data.clear();
  EXPECT_THROW(write_ply(v, dir / "verts.ply"), Error);
  EXPECT_EQ(entries(dir), 0u);
}

TEST(Ply, FailedWriteLeavesTheExistingFileAndNoTemp) {
  const fs::path dir = scratch("atomic");
  const PolyData good = attribute_mesh(ScalarType::Float32);
  write_ply(good, dir / "m.ply");
  const std::string before = slurp(dir / "m.ply");
  PolyData bad = good;
  bad.polys.add({0, 1, 99});  // out of range
  bad.cell_data.clear();
  EXPECT_THROW(write_ply(bad, dir / "m.ply"), Error);
  PolyData lines = good;
  lines.lines.add({0, 1});
  EXPECT_THROW(write_ply(lines, dir / "m.ply"), Error);
  EXPECT_EQ(slurp(dir / "m.ply"), before);
  EXPECT_EQ(entries(dir), 1u);
  EXPECT_THROW(write_ply(good, dir / "no" / "such" / "dir.ply"), Error);
}

// ---------------------------------------------------------------------------------------------
// PLY: hand-made files

TEST(Ply, AllScalarTypeNamesAndSkippedElements) {
  const std::string text =
      "ply\r\n"
      "format ascii 1.0\r\n"
      "comment every type name\r\n"
      "obj_info made by hand\r\n"
      "element face 2\r\n"
      "property uint8 flags\r\n"
      "property list uchar uint vertex_index\r\n"
      "property list uchar float texcoord\r\n"
      "element vertex 4\r\n"
      "property float32 x\r\n"
      "property float32 y\r\n"
      "property float64 z\r\n"
      "property char a\r\n"
      "property uchar b\r\n"
      "property short c\r\n"
      "property ushort d\r\n"
      "property int e\r\n"
      "property uint f\r\n"
      "property int8 g\r\n"
      "property uint16 h\r\n"
      "property int32 i\r\n"
      "property uint32 j\r\n"
      "property int16 k\r\n"
      "property double l\r\n"
      "property float m\r\n"
      "element edge 2\r\n"
      "property int vertex1\r\n"
      "property list int int more\r\n"
      "end_header\r\n"
      "9 3 0 1 2 6 0 0 1 0 1 1\r\n"
      "8 3 0 2 3 0\r\n"
      "0 0 0 -128 255 -32768 65535 -2147483648 4294967295 -1 2 3 4 5 0.5 1.5\r\n"
      "1 0 0 127 0 32767 0 2147483647 0 1 2 3 4 5 0.25 2.5\r\n"
      "1 1 0 0 0 0 0 0 0 1 2 3 4 5 0.125 3.5\r\n"
      "0 1 1e-3 0 0 0 0 0 0 1 2 3 4 5 1e300 -4.5\r\n"
      "0 3 1 2 3\r\n"
      "1 0\r\n";
  const PolyData m = read_ply(bytes_of(text), "types.ply");
  ASSERT_EQ(m.num_points(), 4u);
  EXPECT_EQ(m.points.type(), ScalarType::Float64);  // z is float64
  EXPECT_EQ(m.points[3].z, 1e-3);
  ASSERT_EQ(m.polys.size(), 2u);
  EXPECT_EQ(m.polys.connectivity(), (std::vector<Index>{0, 1, 2, 0, 2, 3}));
  const std::map<std::string, ScalarType> types = {
      {"a", ScalarType::Int8},   {"b", ScalarType::UInt8},  {"c", ScalarType::Int16},
      {"d", ScalarType::UInt16}, {"e", ScalarType::Int32},  {"f", ScalarType::UInt32},
      {"g", ScalarType::Int8},   {"h", ScalarType::UInt16}, {"i", ScalarType::Int32},
      {"j", ScalarType::UInt32}, {"k", ScalarType::Int16},  {"l", ScalarType::Float64},
      {"m", ScalarType::Float32}};
  for (const auto& [name, type] : types) {
    ASSERT_TRUE(m.point_data.has(name)) << name;
    EXPECT_EQ(m.point_data.get(name).type(), type) << name;
  }
  EXPECT_EQ(m.point_data.get("a").get(0), -128);
  EXPECT_EQ(m.point_data.get("b").get(0), 255);
  EXPECT_EQ(m.point_data.get("c").get(0), -32768);
  EXPECT_EQ(m.point_data.get("d").get(0), 65535);
  EXPECT_EQ(m.point_data.get("e").get(0), -2147483648.0);
  EXPECT_EQ(m.point_data.get("f").get(0), 4294967295.0);
  EXPECT_EQ(m.point_data.get("l").get(3), 1e300);
  EXPECT_EQ(m.point_data.get("m").get(3), -4.5);
  ASSERT_TRUE(m.cell_data.has("flags"));
  EXPECT_EQ(m.cell_data.get("flags").type(), ScalarType::UInt8);
  EXPECT_EQ(m.cell_data.get("flags").get(0), 9);
  EXPECT_EQ(m.cell_data.get("flags").get(1), 8);
  EXPECT_FALSE(m.cell_data.has("texcoord"));
  // Corner texture coordinates; the second face's list is empty: its corners stay on their
  // vertices, so no point is added.
  const DataArray* tc = m.point_data.tcoords();
  ASSERT_NE(tc, nullptr);
  EXPECT_EQ(tc->get(1, 0), 1.0);
  EXPECT_EQ(tc->get(2, 1), 1.0);
  EXPECT_EQ(tc->get(3, 0), 0.0);
}

namespace {

/// A binary PLY with a leading unknown element (with a list), faces before vertices.
std::string binary_ply(bool big) {
  std::string s = std::string("ply\nformat ") +
                  (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\n"
                  "element material 2\n"
                  "property uchar id\n"
                  "property list ushort short coeffs\n"
                  "element face 1\n"
                  "property list uchar int vertex_indices\n"
                  "property float area\n"
                  "element vertex 3\n"
                  "property float x\nproperty float y\nproperty float z\n"
                  "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                  "property float s\nproperty float t\n"
                  "end_header\n";
  auto put = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    if (big) std::reverse(b, b + sizeof(v));
    s.append(b, sizeof(v));
  };
  put(std::uint8_t{1});
  put(std::uint16_t{2});
  put(std::int16_t{-5});
  put(std::int16_t{6});
  put(std::uint8_t{2});
  put(std::uint16_t{0});
  put(std::uint8_t{3});
  put(std::int32_t{2});
  put(std::int32_t{0});
  put(std::int32_t{1});
  put(0.75f);
  for (int i = 0; i < 3; ++i) {
    put(static_cast<float>(i));
    put(static_cast<float>(i * i));
    put(-static_cast<float>(i) / 4);
    put(static_cast<std::uint8_t>(10 + i));
    put(static_cast<std::uint8_t>(20 + i));
    put(static_cast<std::uint8_t>(30 + i));
    put(0.5f * static_cast<float>(i));
    put(1.0f - 0.5f * static_cast<float>(i));
  }
  return s;
}

}  // namespace

TEST(Ply, BinaryBothEndiansWithSkippedElementsAndFacesFirst) {
  for (bool big : {false, true}) {
    const PolyData m = read_ply(bytes_of(binary_ply(big)), "bin.ply");
    ASSERT_EQ(m.num_points(), 3u);
    EXPECT_EQ(m.points[2].x, 2.0);
    EXPECT_EQ(m.points[2].y, 4.0);
    EXPECT_EQ(m.points[2].z, -0.5);
    EXPECT_EQ(m.polys.connectivity(), (std::vector<Index>{2, 0, 1}));
    EXPECT_EQ(m.cell_data.get("area").get(0), 0.75);
    const DataArray* colors = m.point_data.scalars();
    ASSERT_NE(colors, nullptr);
    EXPECT_EQ(colors->name(), "Colors");
    EXPECT_EQ(colors->components(), 3);
    EXPECT_EQ(colors->get(1, 0), 11);
    EXPECT_EQ(colors->get(2, 2), 32);
    ASSERT_NE(m.point_data.tcoords(), nullptr);
    EXPECT_EQ(m.point_data.tcoords()->get(2, 0), 1.0);
    EXPECT_EQ(m.point_data.tcoords()->get(2, 1), 0.0);
    EXPECT_EQ(m.point_data.size(), 2u);
  }
}

namespace {
/// A quad and a triangle over 5 vertices with texture coordinates per face corner (MeshLab's
/// `property list uchar float texcoord`), the list before or after the index list; vertex 1 and
/// 2 are shared with the same coordinates, vertex 3 with different ones; vertex 4 is in no face.
std::string corner_texcoord_ply(const char* format, bool texcoord_first) {
  const bool ascii = std::string(format) == "ascii";
  std::string s = std::string("ply\nformat ") + format +
                  " 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                  "property float q\nelement face 2\n";
  const std::string idx = "property list uchar int vertex_indices\n";
  const std::string tc = "property list uchar float texcoord\n";
  s += (texcoord_first ? tc + idx : idx + tc) + "property int texnumber\nend_header\n";
  const float pts[5][4] = {
      {0, 0, 0, 10}, {1, 0, 0, 11}, {1, 1, 0, 12}, {0, 1, 0, 13}, {5, 5, 5, 14}};
  struct Face {
    std::vector<int> ids;
    std::vector<float> uv;
    int tex;
  };
  const Face f[2] = {{{0, 1, 2, 3}, {0, 0, 0.5f, 0, 0.5f, 0.5f, 0, 0.5f}, 0},
                     {{1, 3, 2}, {0.5f, 0, 0.75f, 1, 0.5f, 0.5f}, 1}};
  auto put = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    s.append(b, sizeof(v));
  };
  for (const auto& p : pts) {
    if (ascii) {
      s += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + " " +
           std::to_string(p[3]) + "\n";
    } else {
      for (float v : p) put(v);
    }
  }
  // A list: its uchar count, then its items (int32 indices or float coordinates).
  auto put_list = [&](const auto& items) {
    if (ascii) {
      s += std::to_string(items.size());
      for (const auto v : items) s += " " + std::to_string(v);
      s += " ";
    } else {
      put(static_cast<std::uint8_t>(items.size()));
      for (const auto v : items) put(v);
    }
  };
  for (const Face& face : f) {
    const std::vector<std::int32_t> ids(face.ids.begin(), face.ids.end());
    const auto put_idx = [&] { put_list(ids); };
    const auto put_tc = [&] { put_list(face.uv); };
    if (texcoord_first) {
      put_tc();
      put_idx();
    } else {
      put_idx();
      put_tc();
    }
    if (ascii) {
      s += std::to_string(face.tex) + "\n";
    } else {
      put(std::int32_t{face.tex});
    }
  }
  return s;
}
}  // namespace

TEST(Ply, CornerTextureCoordinatesDuplicateThePointsWhereTheyDiffer) {
  for (const char* format : {"ascii", "binary_little_endian"}) {
    for (const bool first : {false, true}) {
      SCOPED_TRACE(std::string(format) + (first ? " texcoord first" : " indices first"));
      const std::string text = corner_texcoord_ply(format, first);
      const PolyData m = read_ply(bytes_of(text), "tc.ply");
      // Vertex 3 has (0, 0.5) in the quad and (0.75, 1) in the triangle: one copy, point 5.
      ASSERT_EQ(m.num_points(), 6u);
      EXPECT_EQ(m.polys.connectivity(), (std::vector<Index>{0, 1, 2, 3, 1, 5, 2}));
      const DataArray* tc = m.point_data.tcoords();
      ASSERT_NE(tc, nullptr);
      EXPECT_EQ(tc->name(), "TCoords");
      const double want[6][2] = {{0, 0}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}, {0, 0}, {0.75, 1}};
      for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(tc->get(i, 0), want[i][0]) << i;
        EXPECT_EQ(tc->get(i, 1), want[i][1]) << i;
      }
      // The copy carries its vertex's position and point arrays; face properties stay.
      EXPECT_EQ(m.points[5].x, 0.0);
      EXPECT_EQ(m.points[5].y, 1.0);
      EXPECT_EQ(m.point_data.get("q").get(5), 13.0);
      EXPECT_EQ(m.point_data.get("q").get(4), 14.0);
      EXPECT_EQ(m.cell_data.get("texnumber").get(1), 1.0);
      // info's summary is that of the mesh read.
      const fs::path path = scratch("corner_tc") / "tc.ply";
      std::ofstream(path, std::ios::binary) << text;
      const DatasetSummary sum = summarize_file(path);
      EXPECT_EQ(sum.points, 6u);
      EXPECT_EQ(sum.cells, 2u);
      ASSERT_EQ(sum.point_data.arrays.size(), 2u);
      EXPECT_EQ(sum.point_data.arrays[1].name, "TCoords");
    }
  }
  // A list whose length is not two per vertex is an error naming the face.
  std::string bad = corner_texcoord_ply("ascii", false);
  const std::size_t at = bad.find("3 1 3 2 6 ");
  ASSERT_NE(at, std::string::npos);
  bad.replace(at, bad.find('\n', at) - at, "3 1 3 2 4 0.5 0 0.75 1 1");
  expect_error(ply_reader(), bad, {"bad.ply:", "face 1", "'texcoord' has 4 values", "needs 6"});
}

TEST(Ply, TruncatedAndMutatedBinaryOnlyThrowsError) {
  for (bool big : {false, true}) {
    const auto full = bytes_of(binary_ply(big));
    const std::size_t rejected =
        prefixes_only_throw_error(ply_reader(), full, all_offsets(full.size()));
    EXPECT_EQ(rejected, full.size());  // every strict prefix is missing bytes
    random_mutations_only_throw_error(ply_reader(), full, 3000);
  }
  const fs::path dir = scratch("trunc");
  write_ply(attribute_mesh(ScalarType::Float64), dir / "a.ply", {PlyEncoding::Ascii});
  const auto ascii = read_file_bytes(dir / "a.ply");
  prefixes_only_throw_error(ply_reader(), ascii, all_offsets(ascii.size()));
  random_mutations_only_throw_error(ply_reader(), ascii, 3000);
}

TEST(Ply, FloatColoursAreScaledAndAlphaKept) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 1\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float red\nproperty float green\nproperty float blue\nproperty uchar alpha\n"
      "property float nx\nproperty float ny\n"  // incomplete normal: plain arrays
      "end_header\n0 0 0 1 0.5 0 200 0.1 0.2\n";
  const PolyData m = read_ply(bytes_of(text), "c.ply");
  const DataArray& c = m.point_data.get("Colors");
  EXPECT_EQ(c.components(), 4);
  EXPECT_EQ(c.get(0, 0), 255);
  EXPECT_EQ(c.get(0, 1), 128);
  EXPECT_EQ(c.get(0, 2), 0);
  EXPECT_EQ(c.get(0, 3), 200);
  EXPECT_TRUE(m.point_data.has("nx"));
  EXPECT_TRUE(m.point_data.has("ny"));
  EXPECT_EQ(m.point_data.normals(), nullptr);
}

// ---------------------------------------------------------------------------------------------
// PLY: bad input, one test per class

namespace {
const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST(PlyBad, Magic) {
  expect_error(ply_reader(), "plx\nformat ascii 1.0\n", {"bad.ply:1", "bad magic"});
}
TEST(PlyBad, Empty) {
  expect_error(ply_reader(), "", {"bad.ply", "empty"});
}
TEST(PlyBad, UnknownFormat) {
  expect_error(ply_reader(), "ply\nformat binary_middle_endian 1.0\nend_header\n",
               {"bad.ply:2", "unknown format 'binary_middle_endian'"});
}
TEST(PlyBad, UnsupportedVersion) {
  expect_error(ply_reader(), "ply\nformat ascii 2.0\nend_header\n", {"bad.ply:2", "version"});
}
TEST(PlyBad, MissingFormat) {
  expect_error(ply_reader(), "ply\nelement vertex 0\nend_header\n", {"bad.ply", "no format"});
}
TEST(PlyBad, UnknownKeyword) {
  expect_error(ply_reader(), "ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n",
               {"bad.ply:3", "unknown header keyword 'elemnt'"});
}
TEST(PlyBad, UnknownType) {
  expect_error(ply_reader(),
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
               {"bad.ply:4", "unknown property type 'float128'"});
}
TEST(PlyBad, FloatListCount) {
  expect_error(
      ply_reader(),
      "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
      {"bad.ply:4", "not an integer type"});
}
TEST(PlyBad, VertexWithoutXIsNamedInTheHeader) {
  // The body has three values a vertex: read as two, the face count came out 0 and the message
  // was "face 0 has 0 vertices".
  expect_error(ply_reader(),
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
               "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
               {"bad.ply:3", "the vertex element lacks the 'x' property (it has y, z)",
                "x, y and z are required"});
  expect_error(ply_reader(), "ply\nformat ascii 1.0\nelement vertex 1\nend_header\n0 0 0\n",
               {"bad.ply:3", "lacks the 'x' property (it has none)"});
}
TEST(PlyBad, PropertyBeforeElement) {
  expect_error(ply_reader(), "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
               {"bad.ply:3", "property before any element"});
}
TEST(PlyBad, DuplicateProperty) {
  expect_error(
      ply_reader(),
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nend_header\n",
      {"bad.ply:5", "duplicate property 'x'"});
}
TEST(PlyBad, NegativeCount) {
  expect_error(ply_reader(), "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
               {"bad.ply:3", "count -3 is negative"});
}
TEST(PlyBad, CountNotANumber) {
  expect_error(ply_reader(), "ply\nformat ascii 1.0\nelement vertex lots\nend_header\n",
               {"bad.ply:3", "not an integer"});
}
TEST(PlyBad, CountExceedsRemainingBytes) {
  expect_error(ply_reader(),
               "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
               "property float x\nproperty float y\nproperty float z\nend_header\n\x01\x02",
               {"bad.ply:3", "count 1000000000000 exceeds what the remaining 2 bytes"});
}
TEST(PlyBad, MissingEndHeader) {
  expect_error(ply_reader(), "ply\nformat ascii 1.0\nelement vertex 0\n",
               {"bad.ply", "end_header"});
}
TEST(PlyBad, TruncatedBinary) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nelement face 0\nproperty list uchar int "
      "vertex_indices\nend_header\n";
  s += std::string(20, '\0');
  // The size check reports the vertex element line, before any allocation.
  expect_error(ply_reader(), s, {"bad.ply:3", "exceeds what the remaining 20 bytes"});
  // Only a list's count is known up front: a truncated list is caught at its byte offset.
  std::string f =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int "
      "vertex_indices\nend_header\n";
  const std::size_t fh = f.size();
  f += std::string(36, '\0');
  f += '\x03';
  f += std::string(8, '\0');
  expect_error(
      ply_reader(), f,
      {"bad.ply: byte " + std::to_string(fh + 37), "list 'vertex_indices' count 3 exceeds"});
}
TEST(PlyBad, HugeBinaryListCount) {
  std::string f =
      "ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list uint int vertex_indices\n"
      "end_header\n";
  f += std::string("\xff\xff\xff\xf0", 4);
  f += std::string(16, '\0');
  expect_error(ply_reader(), f,
               {"bad.ply: byte", "count 4294967280 exceeds what the remaining 16 bytes"});
}
TEST(PlyBad, NegativeListCount) {
  expect_error(ply_reader(),
               "ply\nformat ascii 1.0\nelement face 1\nproperty list char int vertex_indices\n"
               "end_header\n-3 0 1 2\n",
               {"bad.ply:6", "count -3 is negative"});
}
TEST(PlyBad, FaceIndexOutOfRange) {
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
               {"bad.ply:13", "face 0: vertex index 3 is out of range (3 vertices)"});
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", {"vertex index -1"});
}
TEST(PlyBad, TooFewFaceVertices) {
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
               {"bad.ply:13", "face 0 has 2 vertices"});
}
TEST(PlyBad, NonFiniteCoordinate) {
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
               {"bad.ply", "vertex 1 has a non-finite coordinate"});
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n", {"vertex 2"});
}
TEST(PlyBad, BadAsciiValue) {
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
               {"bad.ply:11", "found 'zero'"});
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n",
               {"bad.ply:13", "out of range"});
}
TEST(PlyBad, TruncatedAscii) {
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1", {"bad.ply", "exceeds"});
  expect_error(ply_reader(), kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1      ",
               {"bad.ply", "end of file"});
}
TEST(PlyBad, MissingCoordinate) {
  expect_error(ply_reader(),
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float "
               "z\nend_header\n0 0\n",
               {"bad.ply:3", "the vertex element lacks the 'y' property (it has x, z)"});
}
TEST(PlyBad, FaceWithoutIndexList) {
  expect_error(ply_reader(),
               "ply\nformat ascii 1.0\nelement face 1\nproperty int a\nend_header\n1\n",
               {"bad.ply:3", "no 'vertex_indices'"});
}

// ---------------------------------------------------------------------------------------------
// OFF

TEST(Off, ReadsCommentsColoursAndCountsOnTheHeaderLine) {
  const std::string text =
      "# a comment before the header\n"
      "OFF 4 2 5 # counts here\n"
      "# vertices\n"
      "0 0 0\n"
      "1 0 0   # trailing comment\n"
      "1 1 0\n"
      "0 1 0.5\n"
      "3 0 1 2 255 0 0\n"           // per-face colour, ignored
      "4 0 2 3 1 0.1 0.2 0.3 1\n";  // quad + float colour
  const PolyData m = read_off(bytes_of(text), "c.off");
  ASSERT_EQ(m.num_points(), 4u);
  EXPECT_EQ(m.points.type(), ScalarType::Float32);
  EXPECT_EQ(m.points[3].z, 0.5);
  ASSERT_EQ(m.polys.size(), 2u);
  EXPECT_EQ(m.polys.cell_size(1), 4u);
  EXPECT_EQ(m.polys.connectivity(), (std::vector<Index>{0, 1, 2, 0, 2, 3, 1}));
  EXPECT_TRUE(m.point_data.empty());
}

TEST(Off, ReadsCoffAndNoff) {
  const PolyData c = read_off(bytes_of("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 128\n"
                                       "0 1 0 0.0 0.0 1.0 1.0\n3 0 1 2\n"),
                              "c.off");
  const DataArray* colors = c.point_data.scalars();
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->components(), 4);
  EXPECT_EQ(colors->get(1, 1), 255);
  EXPECT_EQ(colors->get(1, 3), 128);
  EXPECT_EQ(colors->get(2, 2), 255);
  const PolyData n =
      read_off(bytes_of("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 -1\n3 0 1 2\n"), "n.off");
  ASSERT_NE(n.point_data.normals(), nullptr);
  EXPECT_EQ(n.point_data.normals()->get(2, 2), -1.0);
  // A UTF-8 byte order mark before the keyword (Windows editors) is skipped; only there.
  const PolyData b =
      read_off(bytes_of("\xEF\xBB\xBFOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "b.off");
  EXPECT_EQ(b.num_points(), 3u);
  EXPECT_EQ(b.polys.size(), 1u);
  expect_error(off_reader(),
               "OFF\n\xEF\xBB\xBF"
               "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
               {"bad.off"});
}

TEST(Off, RoundTripIsExact) {
  const fs::path dir = scratch("off");
  for (ScalarType t : {ScalarType::Float32, ScalarType::Float64}) {
    PolyData m = attribute_mesh(t);
    m.point_data.clear();
    m.cell_data.clear();
    write_off(m, dir / "m.off");
    const PolyData r = read_off(dir / "m.off");
    EXPECT_EQ(r.points.type(), t);
    EXPECT_EQ(r.points, m.points);
    EXPECT_EQ(r.polys.size(), 4u);  // 2 polys + the strip's 2 triangles
    EXPECT_EQ(r.polys.connectivity(), (std::vector<Index>{0, 1, 2, 3, 3, 2, 4, 2, 4, 5, 5, 4, 3}));
  }
  EXPECT_EQ(entries(dir), 1u);
  const std::string text = slurp(dir / "m.off");
  EXPECT_EQ(text.rfind("OFF\n", 0), 0u);
}

TEST(Off, BigMeshesAreWrittenThroughTheBufferWhole) {
  // OFF and OBJ text goes out through a 4 MiB buffer: a mesh of several buffers, with a strip
  // at the end, reads back (OFF) or counts (OBJ) whole, the strip's triangles last.
  const fs::path dir = scratch("off_big");
  PolyData m;
  const std::size_t np = 400'000;
  m.points = Points(np);
  for (std::size_t i = 0; i < np; ++i) {
    const double d = static_cast<double>(i);
    m.points.set(i, {std::sin(d), std::cos(d), 1e-5 * d});
  }
  CellArray expected;
  for (std::size_t i = 0; i + 2 < np; i += 3) {
    const Index tri[3] = {static_cast<Index>(i), static_cast<Index>(i + 2),
                          static_cast<Index>(i + 1)};
    m.polys.add(tri);
    expected.add(tri);
  }
  std::vector<Index> strip(1000);
  for (std::size_t k = 0; k < strip.size(); ++k) strip[k] = static_cast<Index>(np - 1 - 2 * k);
  m.strips.add(strip);
  for (std::size_t k = 0; k + 2 < strip.size(); ++k) {
    if (k % 2 == 0)
      expected.add({strip[k], strip[k + 1], strip[k + 2]});
    else
      expected.add({strip[k + 1], strip[k], strip[k + 2]});
  }
  write_off(m, dir / "m.off");
  const PolyData r = read_off(dir / "m.off");
  EXPECT_EQ(r.points, m.points);
  EXPECT_EQ(r.polys, expected);

  write_obj(m, dir / "m.obj");
  const std::string text = slurp(dir / "m.obj");
  std::size_t vertices = 0, faces = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = text.find('\n', at);
    ASSERT_NE(end, std::string::npos) << "the file ends inside a line";
    if (text.compare(at, 2, "v ") == 0) ++vertices;
    if (text.compare(at, 2, "f ") == 0) ++faces;
    at = end + 1;
  }
  EXPECT_EQ(vertices, np);
  EXPECT_EQ(faces, expected.size());
  const auto last = expected.cell(expected.size() - 1);
  const std::string last_line = "f " + std::to_string(last[0] + 1) + " " +
                                std::to_string(last[1] + 1) + " " + std::to_string(last[2] + 1) +
                                "\n";
  EXPECT_TRUE(text.ends_with(last_line)) << last_line;
  EXPECT_EQ(entries(dir), 2u);
}

TEST(Off, RefusesLinesAndVertsAndKeepsTheOldFile) {
  const fs::path dir = scratch("off_refuse");
  PolyData m = attribute_mesh(ScalarType::Float32);
  m.cell_data.clear();
  write_off(m, dir / "m.off");
  const std::string before = slurp(dir / "m.off");
  PolyData l = m;
  l.lines.add({0, 1});
  try {
    write_off(l, dir / "m.off");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("m.off"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("1 lines"), std::string::npos);
  }
  PolyData v = m;
  v.verts.add({2});
  EXPECT_THROW(write_off(v, dir / "m.off"), Error);
  EXPECT_EQ(slurp(dir / "m.off"), before);
  EXPECT_EQ(entries(dir), 1u);
}

TEST(Off, TruncatedAndMutatedOnlyThrowError) {
  const fs::path dir = scratch("off_trunc");
  PolyData m = attribute_mesh(ScalarType::Float32);
  m.point_data.clear();
  m.cell_data.clear();
  write_off(m, dir / "m.off");
  const auto full = read_file_bytes(dir / "m.off");
  prefixes_only_throw_error(off_reader(), full, all_offsets(full.size()));
  random_mutations_only_throw_error(off_reader(), full, 3000);
  random_mutations_only_throw_error(
      off_reader(),
      bytes_of("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0\n0 1 0 0 0 1 1\n3 0 1 2\n"), 2000);
}

TEST(OffBad, Magic) {
  expect_error(off_reader(), "OBJ\n3 1 0\n", {"bad.off:1", "bad magic"});
}
TEST(OffBad, Empty) {
  expect_error(off_reader(), "  # only a comment\n", {"bad.off", "empty"});
}
TEST(OffBad, Binary) {
  expect_error(off_reader(), "OFF BINARY\n", {"bad.off:1", "binary OFF"});
}
TEST(OffBad, FourD) {
  expect_error(off_reader(), "4OFF\n", {"bad.off:1", "not supported"});
}
TEST(OffBad, NegativeCount) {
  expect_error(off_reader(), "OFF\n-3 1 0\n", {"bad.off:2", "vertex count -3 is negative"});
}
TEST(OffBad, CountExceedsBytes) {
  expect_error(off_reader(), "OFF\n99999999999 1 0\n0 0 0\n",
               {"bad.off:2", "vertex count 99999999999 exceeds"});
  expect_error(off_reader(), "OFF\n3 10000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
               {"bad.off", "exceed"});
}
TEST(OffBad, IndexOutOfRange) {
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
               {"bad.off:6", "face 0: vertex index 7 is out of range (3 vertices)"});
}
TEST(OffBad, NonFinite) {
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
               {"bad.off:4", "vertex 1 has a non-finite coordinate"});
}
TEST(OffBad, TooFewFaceVertices) {
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
               {"bad.off:6", "face 0 has 2 vertices"});
}
TEST(OffBad, Truncated) {
  // Counts that the bytes cannot hold are caught up front, on the counts line.
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1",
               {"bad.off:2", "vertex count 3 and face count 1 exceed what the remaining"});
  // Otherwise at the end of the data.
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 # pad pad pad\n",
               {"bad.off:7", "end of file, expected face vertex index"});
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 0 # pad pad pad pad pad pad pad pad\n",
               {"bad.off", "end of file, expected vertex coordinate"});
}
TEST(OffBad, TrailingGarbage) {
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\nfoo\n",
               {"bad.off:7", "unexpected data after the last face"});
}
TEST(OffBad, BadNumber) {
  expect_error(off_reader(), "OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n",
               {"bad.off:4", "found 'x'"});
}
TEST(OffBad, CoffWithoutColour) {
  expect_error(off_reader(), "COFF\n3 1 0\n0 0 0\n1 0 0 1 1 1\n0 1 0 1 1 1\n3 0 1 2\n",
               {"bad.off:3", "vertex 0: expected 3 or 4 colour values"});
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST(Obj, WritesEveryElementKind) {
  const fs::path dir = scratch("obj");
  PolyData m = attribute_mesh(ScalarType::Float64);
  m.cell_data.clear();
  m.verts.add({5});
  m.verts.add({0, 1});
  m.lines.add({0, 1, 2});
  write_obj(m, dir / "m.obj");
  EXPECT_EQ(entries(dir), 1u);

  std::istringstream in(slurp(dir / "m.obj"));
  std::map<std::string, int> counts;
  std::string line;
  std::vector<std::vector<std::string>> faces;
  double first_v[3] = {0, 0, 0};
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key.empty() || key[0] == '#') continue;
    ++counts[key];
    std::vector<std::string> rest;
    for (std::string w; ls >> w;) rest.push_back(w);
    if (key == "v" && counts[key] == 6) {
      ASSERT_EQ(rest.size(), 3u);
      for (int a = 0; a < 3; ++a) first_v[a] = std::stod(rest[static_cast<std::size_t>(a)]);
    }
    if (key == "f") faces.push_back(rest);
    if (key == "vt") {
      EXPECT_EQ(rest.size(), 2u);
    }
    if (key == "vn") {
      EXPECT_EQ(rest.size(), 3u);
    }
    if (key == "p" && counts[key] == 1) {
      EXPECT_EQ(rest, (std::vector<std::string>{"6"}));
    }
    if (key == "l") {
      EXPECT_EQ(rest, (std::vector<std::string>{"1", "2", "3"}));
    }
  }
  EXPECT_EQ(counts["v"], 6);
  EXPECT_EQ(counts["vn"], 6);
  EXPECT_EQ(counts["vt"], 6);
  EXPECT_EQ(counts["f"], 4);  // 2 polys + 2 strip triangles
  EXPECT_EQ(counts["l"], 1);
  EXPECT_EQ(counts["p"], 2);
  EXPECT_EQ(first_v[0], 1.0 / 3.0);  // float64 points written exactly
  EXPECT_EQ(first_v[2], 1e-7);
  ASSERT_EQ(faces.size(), 4u);
  EXPECT_EQ(faces[0], (std::vector<std::string>{"1/1/1", "2/2/2", "3/3/3", "4/4/4"}));
  EXPECT_EQ(faces[3], (std::vector<std::string>{"6/6/6", "5/5/5", "4/4/4"}));
}

TEST(Obj, PlainFacesWithoutNormalsOrTcoords) {
  const fs::path dir = scratch("obj_plain");
  PolyData m = attribute_mesh(ScalarType::Float32);
  m.point_data.clear();
  m.cell_data.clear();
  write_obj(m, dir / "m.obj");
  const std::string text = slurp(dir / "m.obj");
  EXPECT_NE(text.find("\nf 1 2 3 4\n"), std::string::npos);
  EXPECT_EQ(text.find("vn"), std::string::npos);
  EXPECT_EQ(text.find("vt"), std::string::npos);
  PolyData n = attribute_mesh(ScalarType::Float32);
  n.point_data.set_active(AttributeRole::TCoords, "");
  write_obj(n, dir / "n.obj");
  EXPECT_NE(slurp(dir / "n.obj").find("\nf 1//1 2//2 3//3 4//4\n"), std::string::npos);
}

TEST(Obj, InvalidMeshIsAnErrorAndKeepsTheOldFile) {
  const fs::path dir = scratch("obj_bad");
  write_obj(attribute_mesh(ScalarType::Float32), dir / "m.obj");
  const std::string before = slurp(dir / "m.obj");
  PolyData bad = attribute_mesh(ScalarType::Float32);
  bad.cell_data.clear();
  bad.lines.add({0, 42});
  try {
    write_obj(bad, dir / "m.obj");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("m.obj"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(dir / "m.obj"), before);
  EXPECT_EQ(entries(dir), 1u);
}

namespace {

/// A binary (or ASCII) PLY of an n x n grid of quads, one of them split into two triangles when
/// `mixed`; a uchar face property before the index list and a float one after it.
std::string grid_ply(int n, bool mixed, const char* format, bool big) {
  const bool ascii = std::string(format) == "ascii";
  const int nv = (n + 1) * (n + 1);
  const int nf = n * n + (mixed ? 1 : 0);
  std::string s = std::string("ply\nformat ") + format + " 1.0\nelement vertex " +
                  std::to_string(nv) +
                  "\nproperty float x\nproperty float y\nproperty float z\nproperty short t\n"
                  "element face " + std::to_string(nf) +
                  "\nproperty uchar flag\nproperty list uchar uint vertex_indices\n"
                  "property float area\nend_header\n";
  auto put = [&](auto v) {
    if (ascii) {
      s += std::to_string(+v) + ' ';
      return;
    }
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    if (big) std::reverse(b, b + sizeof(v));
    s.append(b, sizeof(v));
  };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      put(static_cast<float>(i));
      put(static_cast<float>(j));
      put(0.5f * static_cast<float>(i * j));
      put(static_cast<std::int16_t>(i - j));
      if (ascii) s += '\n';
    }
  }
  int f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i, ++f) {
      const auto v0 = static_cast<std::uint32_t>(j * (n + 1) + i);
      const std::uint32_t q[4] = {v0, v0 + 1, v0 + 1 + static_cast<std::uint32_t>(n + 1),
                                  v0 + static_cast<std::uint32_t>(n + 1)};
      put(static_cast<std::uint8_t>(f % 7));
      if (mixed && f == n * n / 2) {  // split into two triangles
        put(std::uint8_t{3});
        for (int k : {0, 1, 2}) put(q[k]);
        put(0.5f);
        if (ascii) s += '\n';
        put(static_cast<std::uint8_t>(100));
        put(std::uint8_t{3});
        for (int k : {0, 2, 3}) put(q[k]);
        put(0.5f);
      } else {
        put(std::uint8_t{4});
        for (std::uint32_t x : q) put(x);
        put(1.0f + static_cast<float>(f));
      }
      if (ascii) s += '\n';
    }
  }
  return s;
}

}  // namespace

// Binary faces of one size take a parallel path, faces of mixed sizes the per-value one: both
// read exactly what the ASCII file (always per value) holds, in both byte orders.
TEST(Ply, BinaryQuadsAndMixedFacesReadAsTheirAsciiTwin) {
  for (bool mixed : {false, true}) {
    const PolyData want = read_ply(bytes_of(grid_ply(40, mixed, "ascii", false)), "a.ply");
    ASSERT_EQ(want.polys.size(), 1600u + (mixed ? 1 : 0));
    EXPECT_EQ(want.polys.cell_size(0), 4u);
    for (bool big : {false, true}) {
      const char* format = big ? "binary_big_endian" : "binary_little_endian";
      const PolyData got = read_ply(bytes_of(grid_ply(40, mixed, format, big)), "b.ply");
      EXPECT_EQ(got.points, want.points) << format << " mixed " << mixed;
      EXPECT_EQ(got.polys.offsets(), want.polys.offsets()) << format;
      EXPECT_EQ(got.polys.connectivity(), want.polys.connectivity()) << format;
      EXPECT_EQ(got.point_data, want.point_data) << format;
      EXPECT_EQ(got.cell_data, want.cell_data) << format;
      EXPECT_EQ(got.cell_data.get("area").get(1599), mixed ? 1599.0 : 1600.0);  // (f + 1)
    }
  }
}

TEST(Ply, BinaryQuadWithAnIndexOutOfRangeIsNamed) {
  std::string s = grid_ply(4, false, "binary_little_endian", false);
  // Face 5's third index (record: flag, count, 4 x uint32, area = 22 bytes) becomes 25.
  const std::size_t faces = s.size() - 16 * 22;
  const std::uint32_t bad = 25;
  std::memcpy(&s[faces + 5 * 22 + 2 + 2 * 4], &bad, 4);
  expect_error([](const auto& b) { return read_ply(b, "bad.ply"); }, s,
               {"bad.ply", "face 5", "vertex index 25", "out of range (25 vertices)"});
}

// A file that cannot be mapped (a pipe) is read all the same.
TEST(Ply, ReadsFromAPipe) {
  const fs::path dir = scratch("pipe");
  const fs::path fifo = dir / "in.ply";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string text = grid_ply(30, true, "binary_little_endian", false);
  std::thread writer([&] {
    std::ofstream out(fifo, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
  const PolyData got = read_ply(fifo);
  writer.join();
  EXPECT_EQ(got, read_ply(bytes_of(text), "same.ply"));
}
