// Tests of the VTK legacy reader and writer: the real files in data/, round trips of every
// dataset type in every encoding and version, small hand-written files for each feature, one
// test per class of bad input, atomic writes, and truncated real files.

#include "support/scratch.hpp"
#include "isoforge/io/vtk_legacy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "isoforge/io/io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace isoforge;

fs::path data_path(const char* name) { return fs::path(ISOFORGE_DATA_DIR) / name; }

fs::path scratch_dir(const std::string& sub) {
  const fs::path dir = fs::path(ISOFORGE_TEST_TMP) / "vtk_legacy" / isoforge::test::current_test_id() / sub;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::span<const std::byte> as_bytes(std::string_view s) {
  return std::as_bytes(std::span(s.data(), s.size()));
}

Dataset parse(std::string_view text, std::string_view name = "memory.vtk") {
  return read_vtk_legacy(as_bytes(text), name);
}

/// The message of the Error that reading `text` throws ("" and a test failure if none).
std::string read_error(std::string_view text, std::string_view name) {
  try {
    (void)parse(text, name);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "reading " << name << " did not throw";
  return {};
}

#define EXPECT_CONTAINS(haystack, needle)                                             \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos)                   \
      << "expected to find \"" << (needle) << "\" in \"" << (haystack) << "\""

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Builds binary test files: text plus big-endian values.
struct Bytes {
  std::string s;
  Bytes& text(std::string_view t) {
    s += t;
    return *this;
  }
  template <class T>
  Bytes& be(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
};

/// First difference between two datasets of the same type, for failure messages.
std::string difference(const Dataset& a, const Dataset& b) {
  if (a.index() != b.index()) return "dataset types differ";
  if (num_points(a) != num_points(b)) return "point counts differ";
  if (num_cells(a) != num_cells(b)) return "cell counts differ";
  const char* names[] = {"point data", "cell data", "field data"};
  const Attributes* as[] = {&point_data(a), &cell_data(a), &field_data(a)};
  const Attributes* bs[] = {&point_data(b), &cell_data(b), &field_data(b)};
  for (int k = 0; k < 3; ++k) {
    if (as[k]->size() != bs[k]->size()) return std::string(names[k]) + ": array counts differ";
    for (std::size_t i = 0; i < as[k]->size(); ++i) {
      const DataArray& x = (*as[k])[i];
      const DataArray& y = (*bs[k])[i];
      if (!(x == y)) {
        return std::string(names[k]) + ": array " + std::to_string(i) + " '" + x.name() +
               "' vs '" + y.name() + "' (" + std::string(scalar_type_name(x.type())) + " vs " +
               std::string(scalar_type_name(y.type())) + ", lut '" + x.lookup_table() +
               "' vs '" + y.lookup_table() + "')";
      }
    }
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      if (as[k]->active_name(role) != bs[k]->active_name(role)) {
        return std::string(names[k]) + ": active " + std::string(attribute_role_name(role)) +
               " '" + as[k]->active_name(role) + "' vs '" + bs[k]->active_name(role) + "'";
      }
    }
  }
  return "geometry differs";
}

// ---------------------------------------------------------------------------------------------
// Sample datasets for the round trips

template <class T>
std::vector<T> sample_values(std::size_t n, int seed) {
  std::vector<T> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    if constexpr (std::is_floating_point_v<T>) {
      // Values that need all their digits: thirds, both signs, magnitudes 1e-4 .. 1e4.
      const double x = (static_cast<double>(i) + 0.1 * seed + 1.0) / 3.0 * (i % 2 ? -1.0 : 1.0) *
                       std::pow(10.0, static_cast<int>(i % 9) - 4);
      v[i] = static_cast<T>(x);
    } else {
      using L = std::numeric_limits<T>;
      switch (i % 4) {
        case 0: v[i] = L::min(); break;
        case 1: v[i] = L::max(); break;
        default: v[i] = static_cast<T>(static_cast<std::int64_t>(i) * 7 - seed); break;
      }
    }
  }
  return v;
}

template <class T>
DataArray sample(std::string name, int comps, std::size_t tuples, int seed = 0) {
  return DataArray::from_vector(std::move(name), comps,
                                sample_values<T>(tuples * static_cast<std::size_t>(comps), seed));
}

/// Point data with every role, several element types, active arrays not first, odd names.
void fill_point_data(Attributes& a, std::size_t n) {
  a.add(sample<std::uint8_t>("flags", 1, n, 1));
  DataArray t = sample<float>("temperature in K", 1, n, 2);
  t.set_lookup_table("rainbow map");
  a.add(std::move(t), AttributeRole::Scalars);
  a.add(sample<double>("velocity", 3, n, 3), AttributeRole::Vectors);
  a.add(sample<std::int64_t>("ids", 1, n, 4));
  a.add(sample<std::int16_t>("i16 pair", 2, n, 5));
  a.add(sample<float>("normals", 3, n, 6), AttributeRole::Normals);
  a.add(sample<std::uint16_t>("u16", 1, n, 7));
  a.add(sample<float>("tc", 2, n, 8), AttributeRole::TCoords);
  a.add(sample<double>("stress", 9, n, 9), AttributeRole::Tensors);
  a.add(sample<std::uint64_t>("u64", 1, n, 10));
}

/// Cell data with the other types, a symmetric tensor and default lookup table.
void fill_cell_data(Attributes& a, std::size_t n) {
  a.add(sample<std::int32_t>("material", 1, n, 11), AttributeRole::Scalars);
  a.add(sample<std::int8_t>("i8", 1, n, 12));
  a.add(sample<std::uint32_t>("u32", 2, n, 13));
  a.add(sample<float>("strain", 6, n, 14), AttributeRole::Tensors);
  a.add(sample<double>("quality%", 1, n, 15));
}

void fill_field_data(Attributes& a) {
  a.add(sample<double>("TimeValue", 1, 1, 16));
  a.add(sample<float>("Properties", 1, 4, 17));
  a.add(sample<std::int32_t>("counts", 2, 3, 18));
  a.add(DataArray("empty", ScalarType::Float32, 1, 0));
}

Points sample_points(std::size_t n, ScalarType type, int seed) {
  Points p(n, type);
  const auto v = sample_values<double>(3 * n, seed);
  for (std::size_t i = 0; i < n; ++i) p.set(i, {v[3 * i], v[3 * i + 1], v[3 * i + 2]});
  return p;
}

ImageData sample_image() {
  ImageData img;
  img.dims = {4, 3, 2};
  img.origin = {0.1, -2.0 / 3.0, 3.3};
  img.spacing = {0.5, 1.0 / 7.0, 2.0};
  fill_point_data(img.point_data, img.num_points());
  fill_cell_data(img.cell_data, img.num_cells());
  fill_field_data(img.field_data);
  return img;
}

StructuredGrid sample_structured() {
  StructuredGrid sg;
  sg.dims = {3, 3, 2};
  sg.points = sample_points(18, ScalarType::Float64, 20);
  fill_point_data(sg.point_data, 18);
  // An array active in two roles is written once per role and read back as one array.
  sg.point_data.add(sample<float>("both", 3, 18, 21));
  fill_cell_data(sg.cell_data, sg.num_cells());
  fill_field_data(sg.field_data);
  return sg;
}

PolyData sample_poly() {
  PolyData pd;
  pd.points = sample_points(8, ScalarType::Float32, 22);
  pd.verts.add({0});
  pd.verts.add({1, 2, 3});
  pd.lines.add({0, 1});
  pd.lines.add({1, 2, 3, 4});
  pd.polys.add({0, 1, 2});
  pd.polys.add({0, 1, 2, 3});
  pd.polys.add({3, 4, 5, 6, 7});
  pd.strips.add({0, 1, 2, 3, 4});
  fill_point_data(pd.point_data, 8);
  fill_cell_data(pd.cell_data, pd.num_cells());
  fill_field_data(pd.field_data);
  return pd;
}

UnstructuredGrid sample_unstructured() {
  UnstructuredGrid ug;
  ug.points = sample_points(12, ScalarType::Float64, 23);
  ug.add_cell(CellType::Vertex, {0});
  ug.add_cell(CellType::PolyVertex, {1, 2, 3});
  ug.add_cell(CellType::Line, {0, 11});
  ug.add_cell(CellType::PolyLine, {1, 2, 3, 4});
  ug.add_cell(CellType::Triangle, {0, 1, 2});
  ug.add_cell(CellType::TriangleStrip, {0, 1, 2, 3});
  ug.add_cell(CellType::Polygon, {0, 1, 2, 3, 4});
  ug.add_cell(CellType::Pixel, {0, 1, 2, 3});
  ug.add_cell(CellType::Quad, {0, 1, 3, 2});
  ug.add_cell(CellType::Tetra, {0, 1, 2, 4});
  ug.add_cell(CellType::Voxel, {0, 1, 2, 3, 4, 5, 6, 7});
  ug.add_cell(CellType::Hexahedron, {4, 5, 6, 7, 8, 9, 10, 11});
  ug.add_cell(CellType::Wedge, {0, 1, 2, 3, 4, 5});
  ug.add_cell(CellType::Pyramid, {0, 1, 2, 3, 11});
  fill_point_data(ug.point_data, 12);
  fill_cell_data(ug.cell_data, ug.num_cells());
  fill_field_data(ug.field_data);
  return ug;
}

Dataset sample_dataset(int kind) {
  switch (kind) {
    case 0: return sample_image();
    case 1: {
      StructuredGrid sg = sample_structured();
      sg.point_data.set_active(AttributeRole::Vectors, "both");
      sg.point_data.set_active(AttributeRole::Normals, "both");
      return sg;
    }
    case 2: return sample_poly();
    default: return sample_unstructured();
  }
}

const char* kKindNames[] = {"ImageData", "StructuredGrid", "PolyData", "UnstructuredGrid"};

// ---------------------------------------------------------------------------------------------
// Real files

TEST(VtkLegacyRealFiles, FranCutIsATexturedTriangleMesh) {
  const Dataset ds = read_vtk_legacy(data_path("fran_cut.vtk"));
  const auto& pd = std::get<PolyData>(ds);
  EXPECT_EQ(pd.points.size(), 2205u);
  EXPECT_EQ(pd.points.type(), ScalarType::Float32);
  ASSERT_EQ(pd.polys.size(), 4224u);
  for (std::size_t c = 0; c < pd.polys.size(); ++c) ASSERT_EQ(pd.polys.cell_size(c), 3u);
  EXPECT_TRUE(pd.verts.empty() && pd.lines.empty() && pd.strips.empty());
  const DataArray* tc = pd.point_data.tcoords();
  ASSERT_NE(tc, nullptr);
  EXPECT_EQ(tc->name(), "textureCoords");
  EXPECT_EQ(tc->components(), 2);
  EXPECT_EQ(tc->tuples(), 2205u);
  EXPECT_EQ(pd.point_data.size(), 1u);
  EXPECT_TRUE(pd.cell_data.empty());  // "CELL_DATA 4224" with nothing in it
  const Bounds b = pd.bounds();
  EXPECT_NEAR(b.min.x, 0.0, 1e-3);
  EXPECT_NEAR(b.max.x, 0.106, 1e-3);
  EXPECT_NEAR(b.min.y, -0.205, 1e-3);
  EXPECT_NEAR(b.max.y, -0.051, 1e-3);
  // The first point as written in the file: "0 -0.2048 -0.090616".
  EXPECT_EQ(pd.points[0].y, static_cast<double>(-0.2048f));
  EXPECT_EQ(pd.points[0].z, static_cast<double>(-0.090616f));
}

TEST(VtkLegacyRealFiles, HelloIsFifteenTwoPointLines) {
  const Dataset ds = read_vtk_legacy(data_path("hello.vtk"));
  const auto& pd = std::get<PolyData>(ds);
  EXPECT_EQ(pd.points.size(), 22u);
  ASSERT_EQ(pd.lines.size(), 15u);
  for (std::size_t c = 0; c < 15; ++c) EXPECT_EQ(pd.lines.cell_size(c), 2u);
  EXPECT_EQ(pd.num_cells(), 15u);
  EXPECT_EQ(pd.lines.cell(14)[0], 19);
  EXPECT_EQ(pd.lines.cell(14)[1], 21);
  const Bounds b = pd.bounds();
  EXPECT_EQ(b.min.x, 0.0);
  EXPECT_EQ(b.max.x, 9.0);
  EXPECT_EQ(b.min.y, 0.0);
  EXPECT_EQ(b.max.y, 2.0);
  EXPECT_EQ(b.max.z, 0.0);
}

TEST(VtkLegacyRealFiles, IronProteinScalarsMatchTheRawBytes) {
  const fs::path path = data_path("ironProt.vtk");
  const Dataset ds = read_vtk_legacy(path);
  const auto& img = std::get<ImageData>(ds);
  EXPECT_EQ(img.dims, (Dims{68, 68, 68}));
  EXPECT_EQ(img.spacing, (Vec3{1, 1, 1}));  // from ASPECT_RATIO
  EXPECT_EQ(img.origin, (Vec3{0, 0, 0}));
  const DataArray* s = img.point_data.scalars();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->name(), "scalars");
  EXPECT_EQ(s->type(), ScalarType::UInt8);
  EXPECT_EQ(s->lookup_table(), "");  // LOOKUP_TABLE default
  ASSERT_EQ(s->tuples(), 68u * 68u * 68u);

  // Independently: the voxels are the 314432 bytes after the LOOKUP_TABLE line.
  const std::string raw = file_text(path);
  const std::string marker = "LOOKUP_TABLE default\n";
  const std::size_t start = raw.find(marker);
  ASSERT_NE(start, std::string::npos);
  const std::string_view voxels = std::string_view(raw).substr(start + marker.size(), 314432);
  ASSERT_EQ(voxels.size(), 314432u);
  const auto values = s->values<std::uint8_t>();
  ASSERT_TRUE(std::equal(values.begin(), values.end(), voxels.begin(), [](std::uint8_t a, char b) {
    return a == static_cast<std::uint8_t>(b);
  }));
  const auto [lo, hi] = std::minmax_element(voxels.begin(), voxels.end(), [](char a, char b) {
    return static_cast<std::uint8_t>(a) < static_cast<std::uint8_t>(b);
  });
  const auto range = s->range();
  EXPECT_EQ(range.first, static_cast<std::uint8_t>(*lo));
  EXPECT_EQ(range.second, static_cast<std::uint8_t>(*hi));
  EXPECT_EQ(range.first, 0.0);
  EXPECT_EQ(range.second, 255.0);
}

TEST(VtkLegacyRealFiles, OfficeIsABinaryStructuredGrid) {
  const fs::path path = data_path("office.binary.vtk");
  const Dataset ds = read_vtk_legacy(path);
  const auto& sg = std::get<StructuredGrid>(ds);
  EXPECT_EQ(sg.dims, (Dims{21, 20, 20}));
  EXPECT_EQ(sg.points.size(), 8400u);
  EXPECT_EQ(sg.num_cells(), 20u * 19u * 19u);
  const DataArray* s = sg.point_data.scalars();
  const DataArray* v = sg.point_data.vectors();
  ASSERT_NE(s, nullptr);
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(s->tuples(), 8400u);
  EXPECT_EQ(v->tuples(), 8400u);
  EXPECT_EQ(v->components(), 3);
  const auto [lo, hi] = s->range();
  EXPECT_NEAR(lo, -3.87, 0.01);
  EXPECT_NEAR(hi, 0.72, 0.01);
  EXPECT_GT(v->range(-1).second, 0.0);

  // Independently: the first point is the first 12 bytes after "POINTS 8400 float\n".
  const std::string raw = file_text(path);
  const std::string marker = "POINTS 8400 float\n";
  const std::size_t start = raw.find(marker) + marker.size();
  float xyz[3];
  for (int a = 0; a < 3; ++a) {
    char b[4];
    std::memcpy(b, raw.data() + start + 4 * a, 4);
    if (std::endian::native == std::endian::little) std::reverse(b, b + 4);
    std::memcpy(&xyz[a], b, 4);
  }
  EXPECT_EQ(sg.points[0], (Vec3{xyz[0], xyz[1], xyz[2]}));
}

TEST(VtkLegacyRealFiles, PostIsATetrahedralMeshWithFieldData) {
  const Dataset ds = read_vtk_legacy(data_path("post.vtk"));
  const auto& ug = std::get<UnstructuredGrid>(ds);
  EXPECT_EQ(ug.points.size(), 2288u);
  ASSERT_EQ(ug.num_cells(), 8750u);
  EXPECT_EQ(std::count(ug.types.begin(), ug.types.end(), CellType::Tetra), 8750);
  const DataArray* p = ug.point_data.find("Pressure");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->components(), 1);
  EXPECT_EQ(p->tuples(), 2288u);
  const auto [lo, hi] = p->range();
  EXPECT_NEAR(lo, 0.355, 0.001);
  EXPECT_NEAR(hi, 1.641, 0.001);
  EXPECT_EQ(ug.point_data.scalars(), nullptr);  // a FIELD array has no role
  const DataArray* props = ug.field_data.find("Properties");
  ASSERT_NE(props, nullptr);
  EXPECT_EQ(props->size(), 4u);
  EXPECT_EQ(ug.field_data.size(), 1u);
}

TEST(VtkLegacyRealFiles, BlowHasTrianglesQuadsAndTenTimeSteps) {
  const Dataset ds = read_vtk_legacy(data_path("blow.vtk"));
  const auto& ug = std::get<UnstructuredGrid>(ds);
  EXPECT_EQ(ug.points.size(), 687u);
  ASSERT_EQ(ug.num_cells(), 1057u);
  EXPECT_EQ(std::count(ug.types.begin(), ug.types.end(), CellType::Triangle), 928);
  EXPECT_EQ(std::count(ug.types.begin(), ug.types.end(), CellType::Quad), 129);
  int displacements = 0;
  int thicknesses = 0;
  for (const DataArray& a : ug.point_data) {
    EXPECT_EQ(a.tuples(), 687u) << a.name();
    if (a.name().starts_with("displacement")) {
      ++displacements;
      EXPECT_EQ(a.components(), 3);
    }
    if (a.name().starts_with("thickness")) {
      ++thicknesses;
      EXPECT_EQ(a.components(), 1);
    }
  }
  EXPECT_EQ(displacements, 10);
  EXPECT_EQ(thicknesses, 10);
  EXPECT_EQ(ug.point_data.size(), 20u);
  EXPECT_TRUE(ug.point_data.has("displacement9"));
  EXPECT_TRUE(ug.point_data.has("thickness9"));
  // As in VTK, the first VECTORS / SCALARS of the section are the active ones.
  EXPECT_EQ(ug.point_data.active_name(AttributeRole::Vectors), "displacement0");
  EXPECT_EQ(ug.point_data.active_name(AttributeRole::Scalars), "thickness0");
}

TEST(VtkLegacyRealFiles, RewrittenRealFilesReadBackEqual) {
  const fs::path dir = scratch_dir("rewrite");
  for (const char* name : {"hello.vtk", "fran_cut.vtk", "ironProt.vtk", "office.binary.vtk",
                           "post.vtk", "blow.vtk"}) {
    const Dataset ds = read_vtk_legacy(data_path(name));
    for (const char* version : {"4.2", "5.1"}) {
      for (bool binary : {false, true}) {
        const fs::path out = dir / name;
        write_vtk_legacy(ds, out, {binary, version, "rewritten"});
        const Dataset back = read_vtk_legacy(out);
        EXPECT_TRUE(back == ds) << name << " " << version << (binary ? " binary: " : " ascii: ")
                                << difference(ds, back);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Round trips: every dataset type x {ASCII, BINARY} x {4.2, 5.1}

class VtkLegacyRoundTrip : public ::testing::TestWithParam<std::tuple<int, bool, const char*>> {};

TEST_P(VtkLegacyRoundTrip, WriteThenReadGivesAnEqualDataset) {
  const auto [kind, binary, version] = GetParam();
  const Dataset ds = sample_dataset(kind);
  ASSERT_NO_THROW(validate(ds));
  const fs::path dir = scratch_dir(std::string(kKindNames[kind]) + (binary ? "_bin_" : "_ascii_") +
                                   version);
  const fs::path path = dir / "sample.vtk";
  const VtkLegacyWriteOptions options{binary, version, "round trip\nwith a newline"};
  write_vtk_legacy(ds, path, options);

  const Dataset back = read_vtk_legacy(path);
  ASSERT_EQ(back.index(), ds.index());
  EXPECT_TRUE(back == ds) << difference(ds, back);
  EXPECT_EQ(point_data(back).get("temperature in K").lookup_table(), "rainbow map");
  EXPECT_EQ(cell_data(back).get("material").lookup_table(), "");

  // The stream overload writes the same bytes.
  std::ostringstream stream;
  write_vtk_legacy(ds, stream, options);
  const std::string text = file_text(path);
  EXPECT_EQ(stream.str(), text);

  // Header and layout as asked for.
  const std::string header = "# vtk DataFile Version " + std::string(version) +
                             "\nround trip with a newline\n" + (binary ? "BINARY\n" : "ASCII\n");
  EXPECT_TRUE(text.starts_with(header));
  const bool has_cells = kind >= 2;
  EXPECT_EQ(text.find("OFFSETS vtktypeint64") != std::string::npos,
            has_cells && std::string(version) == "5.1");
  EXPECT_CONTAINS(text, "temperature%20in%20K");
  EXPECT_CONTAINS(text, "LOOKUP_TABLE rainbow%20map");
  EXPECT_CONTAINS(text, "quality%25");
}

INSTANTIATE_TEST_SUITE_P(
    AllTypes, VtkLegacyRoundTrip,
    ::testing::Combine(::testing::Values(0, 1, 2, 3), ::testing::Bool(),
                       ::testing::Values("4.2", "5.1")),
    [](const auto& info) {
      return std::string(kKindNames[std::get<0>(info.param)]) +
             (std::get<1>(info.param) ? "_Binary_" : "_Ascii_") +
             (std::string(std::get<2>(info.param)) == "4.2" ? "V42" : "V51");
    });

TEST(VtkLegacyWrite, BinaryArraysAndCellListsOfManySlicesAreExactBigEndian) {
  // The writer swaps binary values a 1 MiB slice at a time on all threads, and the 4.2 cell
  // list a slice of cells at a time: arrays and lists of several slices, a cell longer than a
  // slice (a polyline of 600k points), and every element type size, byte for byte.
  PolyData pd;
  const std::size_t np = 600'000;
  pd.points = Points(np);
  for (std::size_t i = 0; i < np; ++i) {
    pd.points.set(
        i, {static_cast<double>(i), -0.5 * static_cast<double>(i), 1e-3 * static_cast<double>(i)});
  }
  for (std::size_t i = 0; i + 2 < np; i += 2) {
    pd.polys.add({static_cast<Index>(i), static_cast<Index>(i + 1), static_cast<Index>(i + 2)});
  }
  std::vector<Index> line(np);
  for (std::size_t i = 0; i < np; ++i) line[i] = static_cast<Index>(np - 1 - i);
  pd.lines.add(line);
  std::vector<double> f64(np);
  std::vector<std::int16_t> i16(np);
  for (std::size_t i = 0; i < np; ++i) {
    f64[i] = std::sin(static_cast<double>(i));
    i16[i] = static_cast<std::int16_t>(i * 7919);
  }
  pd.point_data.add(DataArray::from_vector("f64", 1, f64));
  pd.point_data.add(DataArray::from_vector("i16", 1, i16));
  for (const char* version : {"4.2", "5.1"}) {
    std::ostringstream out;
    write_vtk_legacy(pd, out, {true, version, "t"});
    const std::string text = out.str();
    // The first polygon and the polyline as the layout puts them, big-endian.
    const auto be = [](auto v) {
      std::string b(sizeof v, '\0');
      for (std::size_t k = 0; k < sizeof v; ++k) {
        b[k] =
            static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * (sizeof v - 1 - k))) & 0xFF);
      }
      return b;
    };
    if (std::string(version) == "4.2") {
      std::string lines = "LINES 1 " + std::to_string(np + 1) + "\n" + be(std::int32_t(np));
      for (std::size_t i = 0; i < 5; ++i) lines += be(static_cast<std::int32_t>(np - 1 - i));
      EXPECT_NE(text.find(lines), std::string::npos) << version;
    }
    std::string f64_bytes = "f64 1 " + std::to_string(np) + " double\n";  // a FIELD array
    for (std::size_t i = 0; i < 3; ++i) f64_bytes += be(std::bit_cast<std::uint64_t>(f64[i]));
    EXPECT_NE(text.find(f64_bytes), std::string::npos) << version;
    const Dataset back = read_vtk_legacy(as_bytes(text), "big.vtk");
    EXPECT_TRUE(back == Dataset(pd)) << version << ": " << difference(pd, back);
  }
}

TEST(VtkLegacyWrite, ImageDataIsStructuredPointsWithSpacingAndOrigin) {
  ImageData img;
  img.dims = {2, 3, 1};
  img.origin = {1.5, 0, -1};
  img.spacing = {0.25, 2, 1};
  std::ostringstream out;
  write_vtk_legacy(img, out, {false, "4.2", "t"});
  EXPECT_CONTAINS(out.str(),
                  "DATASET STRUCTURED_POINTS\nDIMENSIONS 2 3 1\n"
                  "SPACING 0.25 2 1\nORIGIN 1.5 0 -1\n");
  EXPECT_EQ(out.str().find("POINT_DATA"), std::string::npos);  // nothing to write
}

TEST(VtkLegacyWrite, ClassicCellListsCountIdsAndSizes) {
  PolyData pd;
  pd.points = Points(3);
  pd.polys.add({0, 1, 2});
  std::ostringstream out;
  write_vtk_legacy(pd, out, {false, "4.2", "t"});
  EXPECT_CONTAINS(out.str(), "POLYGONS 1 4\n3 0 1 2\n");
  std::ostringstream out5;
  write_vtk_legacy(pd, out5, {false, "5.1", "t"});
  EXPECT_CONTAINS(out5.str(),
                  "POLYGONS 2 3\nOFFSETS vtktypeint64\n0 3\nCONNECTIVITY vtktypeint64\n0 1 2\n");
}

TEST(VtkLegacyWrite, RejectsWhatLegacyCannotHold) {
  PolyData pd;
  pd.points = Points(3);
  pd.point_data.add(DataArray("uv", ScalarType::Float32, 2, 3), AttributeRole::Vectors);
  std::ostringstream out;
  try {
    write_vtk_legacy(pd, out);
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "active vectors 'uv' has 2 components");
  }
  EXPECT_TRUE(out.str().empty());  // nothing written before the check

  PolyData nan_point;
  nan_point.points.push_back({0, std::nan(""), 0});
  try {
    write_vtk_legacy(nan_point, out);
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "point 0 has a non-finite coordinate");
  }

  try {
    write_vtk_legacy(PolyData{}, out, {true, "3.0", "t"});
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), "version must be \"4.2\" or \"5.1\"");
  }
}

TEST(VtkLegacyWrite, InvalidDatasetOverAGoodFileLeavesItUnchanged) {
  const fs::path dir = scratch_dir("atomic");
  const fs::path path = dir / "mesh.vtk";
  PolyData good;
  good.points = Points(3);
  good.polys.add({0, 1, 2});
  write_vtk_legacy(good, path);
  const std::string before = file_text(path);
  ASSERT_FALSE(before.empty());

  PolyData bad = good;
  bad.polys.add({0, 1, 7});  // point 7 does not exist
  try {
    write_vtk_legacy(bad, path);
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), path.string());
    EXPECT_CONTAINS(e.what(), "refers to point 7");
  }
  EXPECT_EQ(file_text(path), before);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(names, std::vector<std::string>{"mesh.vtk"});
  EXPECT_TRUE(read_vtk_legacy(path) == Dataset(good));
}

// ---------------------------------------------------------------------------------------------
// Hand-written files

std::string square_file(std::string_view version, bool offsets_layout) {
  std::string s = "# vtk DataFile Version " + std::string(version) +
                  "\nsquare\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n"
                  "0 0 0  1 0 0  1 1 0  0 1 0\n";
  if (offsets_layout) {
    s += "POLYGONS 3 6\nOFFSETS vtktypeint64\n0 3 6\nCONNECTIVITY vtktypeint64\n0 1 2 0 2 3\n";
  } else {
    s += "POLYGONS 2 8\n3 0 1 2\n3 0 2 3\n";
  }
  return s;
}

PolyData expected_square() {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({1, 0, 0});
  pd.points.push_back({1, 1, 0});
  pd.points.push_back({0, 1, 0});
  pd.polys.add({0, 1, 2});
  pd.polys.add({0, 2, 3});
  return pd;
}

TEST(VtkLegacyRead, EveryHeaderVersionFromOneToFiveOne) {
  const Dataset want = expected_square();
  for (const char* v : {"1.0", "2.0", "3.0", "4.2"}) {
    EXPECT_TRUE(parse(square_file(v, false)) == want) << v;
  }
  EXPECT_TRUE(parse(square_file("5.1", true)) == want);
  // The layout is recognised whatever the version says.
  EXPECT_TRUE(parse(square_file("5.1", false)) == want);
  EXPECT_TRUE(parse(square_file("4.2", true)) == want);

  const std::string msg = read_error(square_file("6.0", false), "future.vtk");
  EXPECT_CONTAINS(msg, "future.vtk:1: unsupported file version 6.0");
}

TEST(VtkLegacyRead, OffsetsConnectivityLayoutForUnstructuredGrids) {
  const std::string text =
      "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "POINTS 5 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n"
      "CELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n0 1 2 3 1 2 4\n"
      "CELL_TYPES 2\n10\n5\n";
  const auto ug = std::get<UnstructuredGrid>(parse(text));
  EXPECT_EQ(ug.points.type(), ScalarType::Float64);
  ASSERT_EQ(ug.num_cells(), 2u);
  EXPECT_EQ(ug.types[0], CellType::Tetra);
  EXPECT_EQ(ug.types[1], CellType::Triangle);
  EXPECT_EQ(ug.cells.offsets(), (std::vector<Index>{0, 4, 7}));
  EXPECT_EQ(ug.cells.connectivity(), (std::vector<Index>{0, 1, 2, 3, 1, 2, 4}));
}

TEST(VtkLegacyRead, RectilinearGridBecomesExplicitPoints) {
  const std::string text =
      "# vtk DataFile Version 3.0\nrect\nASCII\nDATASET RECTILINEAR_GRID\nDIMENSIONS 3 2 2\n"
      "X_COORDINATES 3 float\n0 0.5 2\nY_COORDINATES 2 double\n-1 1\n"
      "Z_COORDINATES 2 float\n0 10\n"
      "POINT_DATA 12\nSCALARS s int\nLOOKUP_TABLE default\n0 1 2 3 4 5 6 7 8 9 10 11\n";
  const auto sg = std::get<StructuredGrid>(parse(text));
  EXPECT_EQ(sg.dims, (Dims{3, 2, 2}));
  ASSERT_EQ(sg.points.size(), 12u);
  EXPECT_EQ(sg.points.type(), ScalarType::Float64);  // one axis is double
  EXPECT_EQ(sg.points[sg.point_id(1, 1, 1)], (Vec3{0.5, 1, 10}));
  EXPECT_EQ(sg.points[sg.point_id(2, 0, 0)], (Vec3{2, -1, 0}));
  EXPECT_EQ(sg.point_data.scalars()->get(10), 10.0);

  std::string all_float = text;
  all_float.replace(all_float.find("2 double"), 8, "2 float");
  EXPECT_EQ(std::get<StructuredGrid>(parse(all_float)).points.type(), ScalarType::Float32);
}

const std::string kTwoPointHeader =
    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 1 1\n"
    "VERTICES 2 4\n1 0\n1 1\n";

TEST(VtkLegacyRead, ColorScalarsAsciiAreFloatsBinaryAreBytes) {
  const auto pd = std::get<PolyData>(
      parse(kTwoPointHeader + "POINT_DATA 2\nCOLOR_SCALARS rgb 3\n0 0.5 1\n1 0 0.2\n"));
  const DataArray* c = pd.point_data.scalars();
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->name(), "rgb");
  EXPECT_EQ(c->type(), ScalarType::UInt8);
  const auto v = c->values<std::uint8_t>();
  EXPECT_EQ(std::vector<std::uint8_t>(v.begin(), v.end()),
            (std::vector<std::uint8_t>{0, 128, 255, 255, 0, 51}));

  Bytes b;
  b.text("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 2 float\n");
  for (float x : {0.f, 0.f, 0.f, 1.f, 1.f, 1.f}) b.be(x);
  b.text("\nPOINT_DATA 2\nCOLOR_SCALARS rgba 4\n");
  for (std::uint8_t x : {1, 2, 3, 4, 250, 251, 252, 253}) b.be(x);
  b.text("\n");
  const auto bin = std::get<PolyData>(parse(b.s, "colors.vtk"));
  const auto bv = bin.point_data.scalars()->values<std::uint8_t>();
  EXPECT_EQ(bin.point_data.scalars()->components(), 4);
  EXPECT_EQ(std::vector<std::uint8_t>(bv.begin(), bv.end()),
            (std::vector<std::uint8_t>{1, 2, 3, 4, 250, 251, 252, 253}));
}

TEST(VtkLegacyRead, TensorsAndSymmetricTensors) {
  const std::string text = kTwoPointHeader +
                           "POINT_DATA 2\nTENSORS t double\n"
                           "1 2 3 4 5 6 7 8 9\n-1 -2 -3 -4 -5 -6 -7 -8 -9\n"
                           "CELL_DATA 2\nTENSORS6 sym float\n1 2 3 4 5 6\n6 5 4 3 2 1\n";
  const auto pd = std::get<PolyData>(parse(text));
  const DataArray* t = pd.point_data.tensors();
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->components(), 9);
  EXPECT_EQ(t->type(), ScalarType::Float64);
  EXPECT_EQ(t->get(1, 8), -9.0);
  const DataArray* s = pd.cell_data.tensors();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->name(), "sym");
  EXPECT_EQ(s->components(), 6);
  EXPECT_EQ(s->get(1, 0), 6.0);
}

TEST(VtkLegacyRead, FieldSkipsNullArraysAndStringArrays) {
  const std::string text = kTwoPointHeader +
                           "POINT_DATA 2\nFIELD FieldData 4\n"
                           "a 1 2 float\n1.5 2.5\n"
                           "NULL_ARRAY\n"
                           "labels 1 2 string\nleft%20side\nright\n"
                           "b 2 2 int\n1 2 3 4\n";
  const auto pd = std::get<PolyData>(parse(text));
  ASSERT_EQ(pd.point_data.size(), 2u);
  EXPECT_EQ(pd.point_data[0].name(), "a");
  EXPECT_EQ(pd.point_data[0].get(1), 2.5);
  EXPECT_EQ(pd.point_data[1].name(), "b");
  EXPECT_EQ(pd.point_data[1].type(), ScalarType::Int32);
  EXPECT_EQ(pd.point_data[1].get(1, 1), 4.0);
  EXPECT_FALSE(pd.point_data.has("NULL_ARRAY"));
  EXPECT_EQ(pd.point_data.scalars(), nullptr);
}

TEST(VtkLegacyRead, MetadataBlocksAreSkipped) {
  const std::string text = kTwoPointHeader +
                           "POINT_DATA 2\nVECTORS v float\n1 2 3 4 5 6\n"
                           "METADATA\nCOMPONENT_NAMES\nx\ny\nz\n"
                           "INFORMATION 1\nNAME L2_NORM_RANGE LOCATION vtkDataArray\n"
                           "DATA 2 3.74166 8.77496\n\n"
                           "SCALARS s float\nLOOKUP_TABLE default\n7 8\n";
  const auto pd = std::get<PolyData>(parse(text));
  ASSERT_EQ(pd.point_data.size(), 2u);
  EXPECT_EQ(pd.point_data.vectors()->get(1, 2), 6.0);
  EXPECT_EQ(pd.point_data.scalars()->get(1), 8.0);

  // Also after a binary block.
  Bytes b;
  b.text("# vtk DataFile Version 5.1\nt\nBINARY\nDATASET POLYDATA\nPOINTS 1 double\n");
  for (double x : {1.0, 2.0, 3.0}) b.be(x);
  b.text("\nMETADATA\nINFORMATION 0\n\nPOINT_DATA 1\nSCALARS s short\nLOOKUP_TABLE default\n");
  b.be(std::int16_t{-7}).text("\n");
  const auto bin = std::get<PolyData>(parse(b.s));
  EXPECT_EQ(bin.points[0], (Vec3{1, 2, 3}));
  EXPECT_EQ(bin.point_data.scalars()->get(0), -7.0);
}

TEST(VtkLegacyRead, PercentEscapedNamesAreDecoded) {
  const std::string text = kTwoPointHeader +
                           "POINT_DATA 2\nSCALARS my%20temperature float 1\n"
                           "LOOKUP_TABLE heat%20map\n1 2\n"
                           "FIELD FieldData 1\nrate%25%2Fs 1 2 double\n3 4\n";
  const auto pd = std::get<PolyData>(parse(text));
  const DataArray* s = pd.point_data.scalars();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->name(), "my temperature");
  EXPECT_EQ(s->lookup_table(), "heat map");
  EXPECT_TRUE(pd.point_data.has("rate%/s"));
}

TEST(VtkLegacyRead, LookupTableSectionBecomesFieldData) {
  const std::string text = kTwoPointHeader +
                           "POINT_DATA 2\nSCALARS s float\nLOOKUP_TABLE mine\n0 1\n"
                           "LOOKUP_TABLE mine 2\n0 0 0 1\n1 0.5 0 1\n";
  const auto pd = std::get<PolyData>(parse(text));
  EXPECT_EQ(pd.point_data.scalars()->lookup_table(), "mine");
  const DataArray* lut = pd.field_data.find("LookupTable:mine");
  ASSERT_NE(lut, nullptr);
  EXPECT_EQ(lut->components(), 4);
  EXPECT_EQ(lut->tuples(), 2u);
  EXPECT_EQ(lut->get(1, 1), 0.5);
}

TEST(VtkLegacyRead, BinaryTypesIdTypeLongAndBits) {
  Bytes b;
  b.text("# vtk DataFile Version 4.2\nbinary types\nBINARY\nDATASET POLYDATA\n"
         "FIELD FieldData 1\nstamp 1 1 long\n");
  b.be(std::int64_t{-5000000000}).text("\n");
  b.text("POINTS 3 int\n");  // integer coordinates become float64
  for (std::int32_t x : {0, 0, 0, 1, 0, 0, 0, 2, 0}) b.be(x);
  b.text("\nPOLYGONS 1 4\n");
  for (std::int32_t x : {3, 0, 1, 2}) b.be(x);
  b.text("\nPOINT_DATA 3\nSCALARS ids vtkIdType\nLOOKUP_TABLE default\n");
  for (std::int32_t x : {7, -8, 9}) b.be(x);
  b.text("\nFIELD FieldData 2\nmask 1 3 bit\n");
  b.be(std::uint8_t{0xA0});  // 1 0 1
  b.text("\nbig 1 3 unsigned_long\n");
  for (std::uint64_t x : {1ull, 2ull, 18446744073709551615ull}) b.be(x);
  b.text("\n");

  const auto pd = std::get<PolyData>(parse(b.s, "types.vtk"));
  EXPECT_EQ(pd.points.type(), ScalarType::Float64);
  EXPECT_EQ(pd.points[2], (Vec3{0, 2, 0}));
  EXPECT_EQ(pd.polys.cell(0)[2], 2);
  EXPECT_EQ(pd.field_data.get("stamp").type(), ScalarType::Int64);
  EXPECT_EQ(pd.field_data.get("stamp").values<std::int64_t>()[0], -5000000000);
  const DataArray& ids = *pd.point_data.scalars();
  EXPECT_EQ(ids.type(), ScalarType::Int64);
  EXPECT_EQ(ids.values<std::int64_t>()[1], -8);
  const auto mask = pd.point_data.get("mask").values<std::uint8_t>();
  EXPECT_EQ(std::vector<std::uint8_t>(mask.begin(), mask.end()),
            (std::vector<std::uint8_t>{1, 0, 1}));
  EXPECT_EQ(pd.point_data.get("big").values<std::uint64_t>()[2], 18446744073709551615ull);
}

// Written by VTK 9.1's own vtkPolyDataWriter (SetFileVersion(51), ASCII; SetFileVersion(42),
// BINARY) from the same polydata: METADATA with COMPONENT_NAMES and INFORMATION, a string field
// array, a bit array, vtkIdType GLOBAL_IDS, COLOR_SCALARS and a lookup table.
const char kVtk9Ascii[] = R"(# vtk DataFile Version 5.1
vtk output
ASCII
DATASET POLYDATA
FIELD FieldData 2
TimeValue 1 1 double
2.5 
note 1 1 string
made%20by%20VTK

POINTS 4 float
0 0 0 1 0 0 0 1 0 
1 1 0.5 
POLYGONS 3 6
OFFSETS vtktypeint64
0 3 6 
CONNECTIVITY vtktypeint64
0 1 2 1 3 2 
CELL_DATA 2
COLOR_SCALARS rgb 3
1 0.501961 0 0.027451 0.25098 0.784314 
FIELD FieldData 1
flag 1 2 bit
1 0 
POINT_DATA 4
SCALARS height%20map float
LOOKUP_TABLE lookup_table
0 0.25 0.5 1 
LOOKUP_TABLE lookup_table 2
0 0 1 1
1 0 0 1

VECTORS velocity double
0 0 0 1 -1 0.5 2 -2 1 
3 -3 1.5 
METADATA
COMPONENT_NAMES
u
v
w
INFORMATION 1
NAME L2_NORM_RANGE LOCATION vtkDataArray
DATA 2 0 4.5 

GLOBAL_IDS gid vtkIdType
100 101 102 103 
)";

const char kVtk9Binary[] =
    "# vtk DataFile Version 4.2\n"
    "vtk output\n"
    "BINARY\n"
    "DATASET POLYDATA\n"
    "FIELD FieldData 2\n"
    "TimeValue 1 1 double\n"
    "@\004\000\000\000\000\000\000\n"
    "note 1 1 string\n"
    "\313made by VTK\n"
    "POINTS 4 float\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\077\200\000\000\000\000\000\000\000\000"
    "\000\000\000\000\000\000\077\200\000\000\000\000\000\000\077\200\000\000\077\200\000\000"
    "\077\000\000\000\n"
    "POLYGONS 2 8\n"
    "\000\000\000\003\000\000\000\000\000\000\000\001\000\000\000\002\000\000\000\003\000\000"
    "\000\001\000\000\000\003\000\000\000\002\n"
    "CELL_DATA 2\n"
    "COLOR_SCALARS rgb 3\n"
    "\377\200\000\007@\310\n"
    "FIELD FieldData 1\n"
    "flag 1 2 bit\n"
    "\200\n"
    "POINT_DATA 4\n"
    "SCALARS height%20map float\n"
    "LOOKUP_TABLE lookup_table\n"
    "\000\000\000\000>\200\000\000\077\000\000\000\077\200\000\000\n"
    "LOOKUP_TABLE lookup_table 2\n"
    "\000\000\377\377\377\000\000\377\n"
    "VECTORS velocity double\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000"
    "\000\000\077\360\000\000\000\000\000\000\277\360\000\000\000\000\000\000\077\340\000\000"
    "\000\000\000\000@\000\000\000\000\000\000\000\300\000\000\000\000\000\000\000\077\360"
    "\000\000\000\000\000\000@\010\000\000\000\000\000\000\300\010\000\000\000\000\000\000"
    "\077\370\000\000\000\000\000\000\n"
    "METADATA\n"
    "COMPONENT_NAMES\n"
    "u\n"
    "v\n"
    "w\n"
    "INFORMATION 1\n"
    "NAME L2_NORM_RANGE LOCATION vtkDataArray\n"
    "DATA 2 0 4.5 \n"
    "\n"
    "GLOBAL_IDS gid vtkIdType\n"
    "\000\000\000d\000\000\000e\000\000\000f\000\000\000g\n";

TEST(VtkLegacyRead, FilesWrittenByVtk9ReadAsVtkReadsThem) {
  const Dataset ascii = parse(kVtk9Ascii, "vtk9.vtk");
  const Dataset binary = parse(std::string_view(kVtk9Binary, sizeof kVtk9Binary - 1), "vtk9b.vtk");
  EXPECT_TRUE(ascii == binary) << difference(ascii, binary);
  for (const Dataset* ds : {&ascii, &binary}) {
    const auto& pd = std::get<PolyData>(*ds);
    EXPECT_EQ(pd.points.size(), 4u);
    EXPECT_EQ(pd.points[3], (Vec3{1, 1, 0.5}));
    ASSERT_EQ(pd.polys.size(), 2u);
    EXPECT_EQ(pd.polys.cell(1)[1], 3);

    const DataArray* h = pd.point_data.scalars();
    ASSERT_NE(h, nullptr);
    EXPECT_EQ(h->name(), "height map");
    EXPECT_EQ(h->lookup_table(), "lookup_table");
    EXPECT_EQ(h->get(1), 0.25);
    const DataArray* v = pd.point_data.vectors();
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->type(), ScalarType::Float64);
    EXPECT_EQ(v->get(3, 2), 1.5);
    const DataArray& gid = pd.point_data.get("gid");
    EXPECT_EQ(gid.type(), ScalarType::Int64);
    EXPECT_EQ(gid.get(3), 103.0);
    EXPECT_EQ(pd.point_data.size(), 3u);

    const DataArray* rgb = pd.cell_data.scalars();
    ASSERT_NE(rgb, nullptr);
    const auto c = rgb->values<std::uint8_t>();
    EXPECT_EQ(std::vector<std::uint8_t>(c.begin(), c.end()),
              (std::vector<std::uint8_t>{255, 128, 0, 7, 64, 200}));
    const DataArray& flag = pd.cell_data.get("flag");
    EXPECT_EQ(flag.get(0), 1.0);
    EXPECT_EQ(flag.get(1), 0.0);

    EXPECT_EQ(pd.field_data.get("TimeValue").get(0), 2.5);
    EXPECT_FALSE(pd.field_data.has("note"));  // string arrays are skipped
    const DataArray& lut = pd.field_data.get("LookupTable:lookup_table");
    EXPECT_EQ(lut.tuples(), 2u);
    EXPECT_EQ(lut.get(0, 2), 1.0);
    EXPECT_EQ(lut.get(1, 0), 1.0);
    EXPECT_EQ(pd.field_data.size(), 2u);
  }
}

TEST(VtkLegacyRead, KeywordsAreCaseInsensitiveAndHeaderToleratesBlankLines) {
  const std::string text =
      "# vtk DataFile Version 2.0\n\n\n  ascii\ndataset polydata\npoints 1 float\n1 2 3\n"
      "point_data 1\nscalars s float\nlookup_table default\n4\n";
  const auto pd = std::get<PolyData>(parse(text));
  EXPECT_EQ(pd.points[0], (Vec3{1, 2, 3}));
  EXPECT_EQ(pd.point_data.scalars()->get(0), 4.0);
}

// ---------------------------------------------------------------------------------------------
// Bad input: each class names the file, the place and the problem

TEST(VtkLegacyBadInput, BadMagic) {
  const std::string msg = read_error("# vtk DataFile Versoin 3.0\nt\nASCII\n", "magic.vtk");
  EXPECT_CONTAINS(msg, "magic.vtk:1:");
  EXPECT_CONTAINS(msg, "not a VTK legacy file");
  EXPECT_CONTAINS(read_error("", "empty.vtk"), "empty.vtk:1: empty file");
}

TEST(VtkLegacyBadInput, BadFormatKeyword) {
  const std::string msg = read_error("# vtk DataFile Version 3.0\nt\nASCI\n", "format.vtk");
  EXPECT_CONTAINS(msg, "format.vtk:3: expected ASCII or BINARY, found 'ASCI'");
}

TEST(VtkLegacyBadInput, UnknownDataset) {
  const std::string msg =
      read_error("# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYHEDRA\n", "dataset.vtk");
  EXPECT_CONTAINS(msg, "dataset.vtk:4: unknown DATASET type 'POLYHEDRA'");
}

TEST(VtkLegacyBadInput, UnknownKeyword) {
  const std::string geometry = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTZ 1 float\n", "kw.vtk");
  EXPECT_CONTAINS(geometry, "kw.vtk:5: unknown keyword 'POINTZ' in POLYDATA");
  const std::string attribute = read_error(
      kTwoPointHeader + "POINT_DATA 2\nSCALAR s float\nLOOKUP_TABLE default\n1 2\n", "kw2.vtk");
  EXPECT_CONTAINS(attribute, "kw2.vtk:11: unknown keyword 'SCALAR' in POINT_DATA");
  const std::string lut =
      read_error(kTwoPointHeader + "POINT_DATA 2\nSCALARS s float\n1 2\n", "lut.vtk");
  EXPECT_CONTAINS(lut, "lut.vtk:");
  EXPECT_CONTAINS(lut, "must be followed by LOOKUP_TABLE, found '2'");  // '1' = components
}

TEST(VtkLegacyBadInput, TruncatedAscii) {
  const std::string msg = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0\n1 0 0\n"
      "1 1 0\n0 1\n",
      "short.vtk");
  EXPECT_CONTAINS(msg, "short.vtk:10: unexpected end of file, expected POINTS value");
}

TEST(VtkLegacyBadInput, TruncatedBinary) {
  Bytes b;
  b.text("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 4 float\n");
  for (int i = 0; i < 7; ++i) b.be(1.0f);  // 28 of the 48 bytes
  const std::string msg = read_error(b.s, "short.bin.vtk");
  EXPECT_CONTAINS(msg, "short.bin.vtk: byte 68: truncated: POINTS needs 12 values of 4 bytes");
}

TEST(VtkLegacyBadInput, NegativeCount) {
  const std::string msg = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS -3 float\n", "neg.vtk");
  EXPECT_CONTAINS(msg, "neg.vtk:5: POINTS count -3 is negative");
  const std::string cells =
      read_error(square_file("4.2", false) + "LINES 1 -2\n", "negcells.vtk");
  EXPECT_CONTAINS(cells, "negcells.vtk:");
  EXPECT_CONTAINS(cells, "LINES size -2 is negative");
  const std::string cell =
      read_error(square_file("4.2", false) + "LINES 1 2\n-1 0\n", "negcell.vtk");
  EXPECT_CONTAINS(cell, "negcell.vtk:11: LINES: cell 0 has a negative point count -1");
}

TEST(VtkLegacyBadInput, CountLargerThanTheFile) {
  const std::string points = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1000000000 float\n0 0 0\n",
      "big.vtk");
  EXPECT_CONTAINS(points, "big.vtk:5: POINTS count 1000000000 exceeds what the remaining");
  // Image data has no point array, so a lying POINT_DATA reaches the attribute reader.
  const std::string scalars = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n"
      "DIMENSIONS 1000 1000 1000\nPOINT_DATA 1000000000\nSCALARS s double\n"
      "LOOKUP_TABLE default\n1 2 3\n",
      "bigimage.vtk");
  EXPECT_CONTAINS(scalars, "bigimage.vtk:");
  EXPECT_CONTAINS(scalars, "exceeds what the remaining");
  Bytes b;
  b.text("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\n"
         "DIMENSIONS 1000 1000 1000\nPOINT_DATA 1000000000\nSCALARS s double\n"
         "LOOKUP_TABLE default\n");
  b.be(1.0);
  const std::string binary = read_error(b.s, "bigimage.bin.vtk");
  EXPECT_CONTAINS(binary, "bigimage.bin.vtk: byte ");
  EXPECT_CONTAINS(binary, "truncated: SCALARS 's' needs 1000000000 values of 8 bytes");
}

TEST(VtkLegacyBadInput, OverflowingDimensions) {
  const std::string msg = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n"
      "DIMENSIONS 4294967296 4294967296 2\n",
      "dims.vtk");
  EXPECT_CONTAINS(msg, "dims.vtk:5: DIMENSIONS:");
  EXPECT_CONTAINS(msg, "overflow a 64-bit point count");
  const std::string zero = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 0 1 1\n",
      "zero.vtk");
  EXPECT_CONTAINS(zero, "zero.vtk:5: DIMENSIONS:");
  EXPECT_CONTAINS(zero, "must be >= 1");
}

TEST(VtkLegacyBadInput, RectilinearGridTooLargeToExpand) {
  std::string text =
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET RECTILINEAR_GRID\nDIMENSIONS 3000 3000 3000\n";
  for (const char* axis : {"X", "Y", "Z"}) {
    text += std::string(axis) + "_COORDINATES 3000 float\n";
    for (int i = 0; i < 3000; ++i) text += "0 ";
    text += "\n";
  }
  const std::string msg = read_error(text, "rect.vtk");
  EXPECT_CONTAINS(msg, "rect.vtk:");
  EXPECT_CONTAINS(msg, "27000000000 points is too large to expand");
}

TEST(VtkLegacyBadInput, CellIndexOutOfRange) {
  std::string text = square_file("4.2", false);
  text.replace(text.find("3 0 2 3"), 7, "3 0 2 7");
  const std::string msg = read_error(text, "ids.vtk");
  EXPECT_CONTAINS(msg, "ids.vtk:7: POLYGONS: cell 1 refers to point 7, outside [0, 4)");

  const std::string conn = read_error(square_file("5.1", true) + "LINES 2 2\nOFFSETS vtktypeint64\n"
                                      "0 2\nCONNECTIVITY vtktypeint64\n0 -1\n",
                                      "conn.vtk");
  EXPECT_CONTAINS(conn, "conn.vtk:12: LINES: cell 0 refers to point -1");
  const std::string offsets =
      read_error(square_file("5.1", true) +
                     "LINES 2 2\nOFFSETS vtktypeint64\n0 3\nCONNECTIVITY vtktypeint64\n0 1\n",
                 "offsets.vtk");
  EXPECT_CONTAINS(offsets, "offsets.vtk:12: LINES:");
  EXPECT_CONTAINS(offsets, "does not equal the connectivity size");
}

TEST(VtkLegacyBadInput, ClassicCellListThatDoesNotAddUp) {
  const std::string msg =
      read_error(square_file("4.2", false) + "LINES 1 4\n2 0 1\nPOINT_DATA 4\n", "sum.vtk");
  EXPECT_CONTAINS(msg, "sum.vtk:");
  EXPECT_CONTAINS(msg, "LINES");
  const std::string overrun =
      read_error(square_file("4.2", false) + "LINES 1 3\n5 0 1\n", "overrun.vtk");
  EXPECT_CONTAINS(overrun, "overrun.vtk:11: LINES: cell 0 has 5 points, more than the 2 values");
  const std::string used_up =
      read_error(square_file("4.2", false) + "LINES 2 3\n2 0 1\n", "used.vtk");
  EXPECT_CONTAINS(used_up,
                  "used.vtk:10: LINES: cell 1 starts after the declared size 3 is used up");

  // The same in binary, where reading on would run past the block (found by fuzzing).
  Bytes b;
  b.text("# vtk DataFile Version 4.2\nt\nBINARY\nDATASET POLYDATA\nPOINTS 2 float\n");
  for (int i = 0; i < 6; ++i) b.be(0.0f);
  b.text("\nLINES 2 3\n");
  const std::size_t lines_at = b.s.size() - 10;
  for (std::int32_t x : {2, 0, 1}) b.be(x);
  b.text("\n");
  EXPECT_CONTAINS(read_error(b.s, "used.bin.vtk"),
                  "used.bin.vtk: byte " + std::to_string(lines_at) +
                      ": LINES: cell 1 starts after the declared size 3 is used up");
}

const std::string kTetraHeader =
    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
    "0 0 0 1 0 0 0 1 0 0 0 1\n";

TEST(VtkLegacyBadInput, BadCellType) {
  const std::string msg =
      read_error(kTetraHeader + "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n42\n", "type.vtk");
  EXPECT_CONTAINS(msg, "type.vtk:9: CELL_TYPES: cell 0 has cell type 42");
  const std::string size =
      read_error(kTetraHeader + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n", "size.vtk");
  EXPECT_CONTAINS(size, "size.vtk:9: cell 0 is a tetra with 3 points (needs 4)");
  const std::string count =
      read_error(kTetraHeader + "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10 10\n", "count.vtk");
  EXPECT_CONTAINS(count, "count.vtk:9: CELL_TYPES lists 2 types but CELLS has 1 cells");

  Bytes b;
  b.text("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n");
  for (int i = 0; i < 3; ++i) b.be(0.0f);
  b.text("\nCELLS 1 2\n").be(std::int32_t{1}).be(std::int32_t{0});
  b.text("\nCELL_TYPES 1\n");
  const std::size_t type_offset = b.s.size();
  b.be(std::int32_t{99}).text("\n");
  const std::string bin = read_error(b.s, "type.bin.vtk");
  EXPECT_CONTAINS(bin, "type.bin.vtk: byte " + std::to_string(type_offset) +
                           ": CELL_TYPES: cell 0 has cell type 99");
}

TEST(VtkLegacyBadInput, NonFiniteCoordinate) {
  const std::string msg = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 nan 1 2\n",
      "nan.vtk");
  EXPECT_CONTAINS(msg, "nan.vtk:5: POINTS: point 1 has a non-finite coordinate (nan, 1, 2)");
  Bytes b;
  b.text("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_GRID\nDIMENSIONS 1 1 1\n"
         "POINTS 1 double\n");
  b.be(0.0).be(std::numeric_limits<double>::infinity()).be(0.0).text("\n");
  EXPECT_CONTAINS(read_error(b.s, "inf.vtk"), "point 0 has a non-finite coordinate (0, inf, 0)");
}

TEST(VtkLegacyBadInput, AttributeCountMismatch) {
  const std::string section = read_error(
      square_file("4.2", false) +
          "POINT_DATA 5\nSCALARS s float\nLOOKUP_TABLE default\n1 2 3 4 5\n",
      "count.vtk");
  EXPECT_CONTAINS(section, "count.vtk:10: POINT_DATA 5 does not match the 4 points of the dataset");
  const std::string cells = read_error(square_file("4.2", false) + "CELL_DATA 3\n", "cells.vtk");
  EXPECT_CONTAINS(cells, "cells.vtk:10: CELL_DATA 3 does not match the 2 cells");
  const std::string field = read_error(
      square_file("4.2", false) + "POINT_DATA 4\nFIELD f 1\nx 1 3 float\n1 2 3\n", "field.vtk");
  EXPECT_CONTAINS(field, "field.vtk:12: FIELD array 'x' has 3 tuples but POINT_DATA declares 4");
  const std::string grid = read_error(
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 2 2 1\n"
      "POINTS 3 float\n0 0 0 1 0 0 0 1 0\n",
      "grid.vtk");
  EXPECT_CONTAINS(grid, "grid.vtk:6: POINTS has 3 points but DIMENSIONS 2 2 1 needs 4");
}

TEST(VtkLegacyBadInput, BadValues) {
  const std::string msg = read_error(
      kTwoPointHeader + "POINT_DATA 2\nSCALARS s unsigned_char\nLOOKUP_TABLE default\n1 300\n",
      "range.vtk");
  EXPECT_CONTAINS(msg, "range.vtk:13: SCALARS 's' value '300' is out of range");
  const std::string type = read_error(
      kTwoPointHeader + "POINT_DATA 2\nVECTORS v quaternion\n", "dtype.vtk");
  EXPECT_CONTAINS(type, "dtype.vtk:11: unknown data type 'quaternion' for VECTORS 'v'");
}

TEST(VtkLegacyBadInput, MissingFile) {
  const fs::path path = scratch_dir("missing") / "nowhere.vtk";
  try {
    (void)read_vtk_legacy(path);
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_CONTAINS(e.what(), path.string());
    EXPECT_CONTAINS(e.what(), "cannot open");
  }
}

// ---------------------------------------------------------------------------------------------
// Truncated real files

/// Whether `part`, read from a truncated copy of the file that gave `full`, is what a cut at a
/// section boundary (or inside the very last number) could produce: the same geometry so far
/// and a subset of the arrays, equal except possibly in the last value.
bool plausible_prefix(const Dataset& part, const Dataset& full) {
  if (part.index() != full.index()) return false;
  if (num_points(part) != num_points(full) && num_points(part) != 0) return false;
  if (num_cells(part) > num_cells(full)) return false;
  const Attributes* ps[] = {&point_data(part), &cell_data(part)};
  const Attributes* fs_[] = {&point_data(full), &cell_data(full)};
  for (int k = 0; k < 2; ++k) {
    for (const DataArray& a : *ps[k]) {
      const DataArray* b = fs_[k]->find(a.name());
      if (b == nullptr || b->components() != a.components() || b->tuples() != a.tuples()) {
        return false;
      }
      for (std::size_t t = 0; t + 1 < a.tuples(); ++t) {
        for (int c = 0; c < a.components(); ++c) {
          if (a.get(t, c) != b->get(t, c)) return false;
        }
      }
    }
  }
  return true;
}

TEST(VtkLegacyRead, TruncatedRealFilesThrowOnlyIsoforgeErrors) {
  for (const char* name : {"hello.vtk", "fran_cut.vtk", "ironProt.vtk", "office.binary.vtk",
                           "post.vtk", "blow.vtk"}) {
    const std::vector<std::byte> bytes = read_file_bytes(data_path(name));
    const Dataset full = read_vtk_legacy(bytes, name);
    std::size_t cuts = 0;
    std::size_t rejected = 0;
    const std::size_t step = std::string_view(name) == "hello.vtk" ? 7 : 97;
    for (std::size_t len = 0; len < bytes.size(); len += step) {
      ++cuts;
      try {
        const Dataset part = read_vtk_legacy(std::span(bytes.data(), len), name);
        EXPECT_TRUE(plausible_prefix(part, full)) << name << " cut at " << len;
      } catch (const Error& e) {
        ++rejected;
        EXPECT_TRUE(std::string(e.what()).starts_with(name)) << e.what();
      }
    }
    // Nearly every cut lands inside a section, which must be rejected.
    EXPECT_GE(rejected * 10, cuts * 9) << name << ": " << rejected << " of " << cuts;
  }
}

}  // namespace

namespace {

/// An ASCII polydata of `n` points on a line (ragged lines of 1-7 numbers, some with several
/// spaces, so that the 1 MiB pieces of the parallel parser cut tokens) and n - 2 triangles.
std::string big_ascii_polydata(std::size_t n) {
  std::string s = "# vtk DataFile Version 4.2\nbig\nASCII\nDATASET POLYDATA\nPOINTS " +
                  std::to_string(n) + " double\n";
  for (std::size_t i = 0; i < 3 * n; ++i) {
    s += std::to_string(i) + ".25";  // exact in binary
    s += (i % 7 == 6) ? "\n" : (i % 3 == 0 ? "   " : " ");
  }
  s += "\nPOLYGONS " + std::to_string(n - 2) + " " + std::to_string(4 * (n - 2)) + "\n";
  for (std::size_t c = 0; c + 2 < n; ++c) {
    s += "3 " + std::to_string(c) + " " + std::to_string(c + 1) + " " + std::to_string(c + 2) +
         (c % 2 ? "\n" : "\t");
  }
  s += "\nPOINT_DATA " + std::to_string(n) + "\nSCALARS s int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i = 0; i < n; ++i) s += std::to_string(static_cast<int>(i) - 5) + "\n";
  return s;
}

/// The 1-based line of the first occurrence of `what` in `text`.
std::size_t line_of(const std::string& text, const std::string& what) {
  const std::size_t at = text.find(what);
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

}  // namespace

// Arrays of 2^16 values or more are parsed in parallel: the values are those of the text, and
// an error is reported at the line of the bad token or cell, as the serial parser does.
TEST(VtkLegacyRead, BigAsciiArraysParseInParallelWithErrorsAtTheirLines) {
  const std::size_t n = 120000;  // 360k coordinates: a few MiB of text, several pieces
  const std::string text = big_ascii_polydata(n);
  const Dataset ds = parse(text, "big.vtk");
  const auto& pd = std::get<PolyData>(ds);
  ASSERT_EQ(pd.points.size(), n);
  for (std::size_t i : {std::size_t{0}, std::size_t{77777}, n - 1}) {
    EXPECT_EQ(pd.points[i].x, static_cast<double>(3 * i) + 0.25);
    EXPECT_EQ(pd.points[i].z, static_cast<double>(3 * i + 2) + 0.25);
  }
  ASSERT_EQ(pd.polys.size(), n - 2);
  const auto last = pd.polys.cell(n - 3);
  EXPECT_EQ(std::vector<Index>(last.begin(), last.end()),
            (std::vector<Index>{static_cast<Index>(n - 3), static_cast<Index>(n - 2),
                                static_cast<Index>(n - 1)}));
  EXPECT_EQ(pd.point_data.get("s").get(n - 1), static_cast<double>(n) - 6);

  // A bad coordinate deep in the points; a cell with a negative point count.
  std::string bad = text;
  const std::string coord = " 300000.25";
  bad.replace(bad.find(coord), coord.size(), " 1.5x");
  EXPECT_CONTAINS(read_error(bad, "coord.vtk"),
                  "coord.vtk:" + std::to_string(line_of(bad, "1.5x")) + ": expected");
  bad = text;
  const std::string cell = "3 90000 90001 90002";
  bad.replace(bad.find(cell), 1, "-3");
  EXPECT_CONTAINS(read_error(bad, "cell.vtk"),
                  "cell.vtk:" + std::to_string(line_of(bad, "-3 90000 90001")) +
                      ": POLYGONS: cell 90000 has a negative point count -3");
}
