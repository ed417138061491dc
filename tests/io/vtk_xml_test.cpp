// Tests for the VTK XML reader and writer (.vti .vts .vtp .vtu): the real Torso.vtp file, round
// trips of every dataset type in every encoding, hand-written files for each format feature,
// cross-checks against VTK's own Python readers/writers (skipped without python3-vtk), and one
// test per class of bad input.

#include "support/scratch.hpp"
#include "isoforge/io/vtk_xml.hpp"

#include <gtest/gtest.h>
#include <lz4.h>
#include <lzma.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/detail/vtk_xml_block.hpp"
#include "isoforge/io/io.hpp"
#include "support/sample_datasets.hpp"

using namespace isoforge;
namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// helpers
// ---------------------------------------------------------------------------------------------

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("vtk_xml", name);
}

using isoforge::test::slurp;

void spit(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

Dataset read_string(const std::string& s, std::string_view name = "test.vtp") {
  return read_vtk_xml(std::as_bytes(std::span(s.data(), s.size())), name);
}

std::string write_string(const Dataset& ds, VtkXmlEncoding enc, bool compress) {
  std::ostringstream out;
  write_vtk_xml(ds, out, VtkXmlWriteOptions{enc, compress});
  return out.str();
}

/// Reading `content` must throw isoforge::Error whose message contains every part.
void expect_read_error(const std::string& content, std::string_view name,
                       std::initializer_list<std::string_view> parts) {
  SCOPED_TRACE(std::string(name));
  try {
    (void)read_string(content, name);
    ADD_FAILURE() << "no error reading " << name;
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(name), std::string::npos) << "message '" << m << "' does not name the file";
    for (std::string_view p : parts) {
      EXPECT_NE(m.find(p), std::string::npos) << "message '" << m << "' lacks '" << p << "'";
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "non-isoforge exception: " << e.what();
  }
}

/// Reading must either succeed or throw isoforge::Error; nothing else may escape.
void expect_error_or_ok(const std::string& content, const std::string& what) {
  try {
    (void)read_string(content, "fuzz.vtu");
  } catch (const Error&) {
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": non-isoforge exception: " << e.what();
  } catch (...) {
    ADD_FAILURE() << what << ": unknown exception";
  }
}

// ---- binary encodings for hand-written files ----

std::string b64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 3 <= in.size(); i += 3) {
    const auto v = (static_cast<std::uint32_t>(static_cast<unsigned char>(in[i])) << 16) |
                   (static_cast<std::uint32_t>(static_cast<unsigned char>(in[i + 1])) << 8) |
                   static_cast<unsigned char>(in[i + 2]);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const auto v = static_cast<std::uint32_t>(static_cast<unsigned char>(in[i])) << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const auto v = (static_cast<std::uint32_t>(static_cast<unsigned char>(in[i])) << 16) |
                   (static_cast<std::uint32_t>(static_cast<unsigned char>(in[i + 1])) << 8);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

struct Enc {
  bool h64 = false;        ///< UInt64 headers
  bool big = false;        ///< BigEndian
  bool z = false;          ///< zlib blocks
  bool separate = false;   ///< base64: header and data encoded as separate padded streams
  std::size_t block = 16;  ///< uncompressed block size when z
};

template <class T>
std::string raw_bytes(const std::vector<T>& v, bool big) {
  std::string s(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  if (big) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      std::reverse(s.begin() + static_cast<std::ptrdiff_t>(i * sizeof(T)),
                   s.begin() + static_cast<std::ptrdiff_t>((i + 1) * sizeof(T)));
    }
  }
  return s;
}

std::string word(std::uint64_t v, const Enc& e) {
  if (e.h64) return raw_bytes(std::vector<std::uint64_t>{v}, e.big);
  return raw_bytes(std::vector<std::uint32_t>{static_cast<std::uint32_t>(v)}, e.big);
}

/// A valid zlib stream holding `raw` in stored (uncompressed) deflate blocks: any inflater
/// accepts it, and the test needs no zlib of its own.
std::string zlib(const std::string& raw) {
  std::string out = "\x78\x01";
  std::size_t pos = 0;
  do {
    const std::size_t len = std::min<std::size_t>(raw.size() - pos, 65535);
    const bool last = pos + len == raw.size();
    out += static_cast<char>(last ? 1 : 0);
    out += static_cast<char>(len & 0xff);
    out += static_cast<char>(len >> 8);
    out += static_cast<char>(~len & 0xff);
    out += static_cast<char>((~len >> 8) & 0xff);
    out += raw.substr(pos, len);
    pos += len;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  const std::uint32_t adler = (b << 16) | a;
  for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((adler >> shift) & 0xff);
  return out;
}

/// Header and body of one array payload (as in an appended raw section).
std::pair<std::string, std::string> payload(const std::string& data, const Enc& e) {
  if (!e.z) return {word(data.size(), e), data};
  const std::size_t nb = (data.size() + e.block - 1) / e.block;
  std::string header = word(nb, e) + word(e.block, e) + word(data.size() % e.block, e);
  std::string body;
  for (std::size_t b = 0; b < nb; ++b) {
    const std::string c = zlib(data.substr(b * e.block, e.block));
    header += word(c.size(), e);
    body += c;
  }
  return {header, body};
}

std::string appended_payload(const std::string& data, const Enc& e) {
  auto [h, b] = payload(data, e);
  return h + b;
}

std::string inline_payload(const std::string& data, const Enc& e) {
  auto [h, b] = payload(data, e);
  if (e.separate) return b64(h) + b64(b);  // as VTK writes compressed arrays
  return b64(h + b);                       // as VTK writes uncompressed arrays
}

std::string root_attrs(const Enc& e) {
  std::string s = std::string(" version=\"1.0\" byte_order=\"") +
                  (e.big ? "BigEndian" : "LittleEndian") + "\" header_type=\"" +
                  (e.h64 ? "UInt64" : "UInt32") + "\"";
  if (e.z) s += " compressor=\"vtkZLibDataCompressor\"";
  return s;
}

/// A tiny ascii triangle file; `mutate` is applied to the text.
const char* kTriangle = R"(<?xml version="1.0"?>
<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">
  <PolyData>
    <Piece NumberOfPoints="3" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="1">
      <PointData Scalars="s">
        <DataArray type="Float32" Name="s" format="ascii">1 2 3</DataArray>
      </PointData>
      <Points>
        <DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray>
      </Points>
      <Polys>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
      </Polys>
    </Piece>
  </PolyData>
</VTKFile>
)";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const std::size_t p = s.find(from);
  EXPECT_NE(p, std::string::npos) << "test bug: '" << from << "' not found";
  if (p != std::string::npos) s.replace(p, from.size(), to);
  return s;
}

// ---- rich sample datasets: every scalar type, roles, field data ----

void add_all_types(Attributes& a, std::size_t n, const std::string& prefix) {
  DataArray i8(prefix + "i8", ScalarType::Int8, 1, n);
  DataArray u8(prefix + "u8", ScalarType::UInt8, 2, n);
  DataArray i16(prefix + "i16", ScalarType::Int16, 1, n);
  DataArray u16(prefix + "u16", ScalarType::UInt16, 1, n);
  DataArray i32(prefix + "i32", ScalarType::Int32, 1, n);
  DataArray u32(prefix + "u32", ScalarType::UInt32, 1, n);
  DataArray i64(prefix + "i64", ScalarType::Int64, 1, n);
  DataArray u64(prefix + "u64", ScalarType::UInt64, 1, n);
  DataArray f32(prefix + "f32", ScalarType::Float32, 2, n);
  DataArray f64(prefix + "f64", ScalarType::Float64, 1, n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::int64_t>(i);
    i8.values<std::int8_t>()[i] = static_cast<std::int8_t>(i % 2 ? -128 + k : 127 - k);
    u8.values<std::uint8_t>()[2 * i] = static_cast<std::uint8_t>(255 - i);
    u8.values<std::uint8_t>()[2 * i + 1] = static_cast<std::uint8_t>(i);
    i16.values<std::int16_t>()[i] = static_cast<std::int16_t>(-32768 + 1000 * k);
    u16.values<std::uint16_t>()[i] = static_cast<std::uint16_t>(65535 - 7 * k);
    i32.values<std::int32_t>()[i] =
        static_cast<std::int32_t>(i % 2 ? INT32_MIN + k : INT32_MAX - k);
    u32.values<std::uint32_t>()[i] = static_cast<std::uint32_t>(UINT32_MAX - k);
    i64.values<std::int64_t>()[i] = i % 2 ? INT64_MIN + k : INT64_MAX - k;
    u64.values<std::uint64_t>()[i] = UINT64_MAX - static_cast<std::uint64_t>(k);
    f32.values<float>()[2 * i] = static_cast<float>(0.1 * static_cast<double>(k) - 1.0 / 3.0);
    f32.values<float>()[2 * i + 1] = i == 0 ? 1e-45f : (i == 1 ? 3.4028235e38f : -1.17549435e-38f);
    f64.values<double>()[i] = i == 0 ? 4.9e-324 : std::sqrt(2.0) * 1e300 / static_cast<double>(k);
  }
  for (auto* arr : {&i8, &u8, &i16, &u16, &i32, &u32, &i64, &u64, &f32, &f64}) {
    a.add(std::move(*arr));
  }
}

void add_field_data(Attributes& f) {
  f.add(DataArray::from_vector<double>("time", 1, {0.25}));
  f.add(DataArray::from_vector<std::int32_t>("cycle", 1, {7, 8, 9}));
  f.add(DataArray::from_vector<float>("pairs", 2, {1.5f, -2.5f, 1e10f, 0.0f}));
  f.add(DataArray::from_vector<std::uint8_t>("empty", 1, {}));
}

ImageData rich_image() {
  ImageData d = test::sample_image();
  add_all_types(d.point_data, d.num_points(), "p_");
  add_all_types(d.cell_data, d.num_cells(), "c_");
  DataArray tc("uv", ScalarType::Float32, 2, d.num_points());
  for (std::size_t i = 0; i < d.num_points(); ++i) tc.set(i, 1, static_cast<double>(i) / 8);
  d.point_data.add(std::move(tc), AttributeRole::TCoords);
  d.cell_data.set_active(AttributeRole::Scalars, "cell_id");
  add_field_data(d.field_data);
  return d;
}

StructuredGrid rich_structured() {
  StructuredGrid d = test::sample_structured();
  d.points = Points(d.points.array().converted(ScalarType::Float64));
  d.points.set(3, {1.0 / 3.0, -1e-300, 12345.678901234567});
  add_all_types(d.point_data, d.num_points(), "p_");
  add_all_types(d.cell_data, d.num_cells(), "c_");
  d.cell_data.set_active(AttributeRole::Vectors, "c_f32");
  add_field_data(d.field_data);
  return d;
}

PolyData rich_poly() {
  PolyData d = test::sample_poly();
  d.strips.add({0, 1, 3, 2, 4});
  d.cell_data.get("area_class").resize(d.num_cells());
  add_all_types(d.point_data, d.num_points(), "p_");
  add_all_types(d.cell_data, d.num_cells(), "c_");
  d.point_data.set_active(AttributeRole::Scalars, "p_u16");
  add_field_data(d.field_data);
  return d;
}

UnstructuredGrid rich_unstructured() {
  UnstructuredGrid d = test::sample_unstructured();
  add_all_types(d.point_data, d.num_points(), "p_");
  add_all_types(d.cell_data, d.num_cells(), "c_");
  d.point_data.set_active(AttributeRole::Vectors, "p_f32");
  d.cell_data.set_active(AttributeRole::Normals, "c_u8");
  add_field_data(d.field_data);
  return d;
}

Dataset rich(int kind) {
  switch (kind) {
    case 0:
      return rich_image();
    case 1:
      return rich_structured();
    case 2:
      return rich_poly();
    default:
      return rich_unstructured();
  }
}

const char* kEncodingName[] = {"ascii", "base64", "appended"};
constexpr VtkXmlEncoding kEncodings[] = {VtkXmlEncoding::Ascii, VtkXmlEncoding::Base64,
                                         VtkXmlEncoding::Appended};

}  // namespace

// =============================================================================================
// Real file
// =============================================================================================

TEST(VtkXmlRead, TorsoVtp) {
  const Dataset ds = read_vtk_xml(fs::path(ISOFORGE_DATA_DIR) / "Torso.vtp");
  ASSERT_TRUE(std::holds_alternative<PolyData>(ds));
  const auto& pd = std::get<PolyData>(ds);
  EXPECT_EQ(pd.points.size(), 12015u);
  EXPECT_EQ(pd.points.type(), ScalarType::Float32);
  EXPECT_EQ(pd.polys.size(), 12448u);
  EXPECT_EQ(pd.verts.size() + pd.lines.size() + pd.strips.size(), 0u);
  std::size_t quads = 0, tris = 0;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    if (pd.polys.cell_size(c) == 4) ++quads;
    if (pd.polys.cell_size(c) == 3) ++tris;
  }
  EXPECT_EQ(quads, 11314u);
  EXPECT_EQ(tris, 1134u);
  const Bounds b = pd.bounds();
  EXPECT_NEAR(b.min.x, -168, 1.5);
  EXPECT_NEAR(b.max.x, 172, 1.5);
  EXPECT_NEAR(b.min.y, -162, 1.5);
  EXPECT_NEAR(b.max.y, 132, 1.5);
  EXPECT_NEAR(b.min.z, -644, 1.5);
  EXPECT_NEAR(b.max.z, 91, 1.5);
  // And the generic entry point dispatches here too.
  EXPECT_EQ(read(fs::path(ISOFORGE_DATA_DIR) / "Torso.vtp"), ds);
}

TEST(VtkXmlRead, TorsoRewrittenInEveryEncodingIsEqual) {
  const Dataset ds = read_vtk_xml(fs::path(ISOFORGE_DATA_DIR) / "Torso.vtp");
  for (VtkXmlEncoding enc : kEncodings) {
    for (bool z : {false, true}) {
      EXPECT_EQ(read_string(write_string(ds, enc, z)), ds);
    }
  }
}

// =============================================================================================
// Round trips
// =============================================================================================

class VtkXmlRoundTrip : public ::testing::TestWithParam<std::tuple<int, int, bool>> {};

TEST_P(VtkXmlRoundTrip, EqualDataset) {
  const auto [kind, enc, z] = GetParam();
  const Dataset ds = rich(kind);
  ASSERT_NO_THROW(validate(ds));
  const std::string text = write_string(ds, kEncodings[enc], z);
  const std::string ext(vtk_xml_extension(ds));
  const Dataset back = read_string(text, "roundtrip" + ext);
  EXPECT_EQ(back, ds) << text.substr(0, 3000);
  // Through a file as well.
  const fs::path dir =
      scratch("rt_" + std::to_string(kind) + "_" + std::to_string(enc) + (z ? "_z" : ""));
  const fs::path path = dir / ("data" + ext);
  write_vtk_xml(ds, path, VtkXmlWriteOptions{kEncodings[enc], z});
  EXPECT_EQ(read_vtk_xml(path), ds);
  EXPECT_EQ(entries(dir), 1u);
}

std::string round_trip_name(const ::testing::TestParamInfo<std::tuple<int, int, bool>>& info) {
  static const char* kinds[] = {"image", "structured", "poly", "ugrid"};
  return std::string(kinds[std::get<0>(info.param)]) + "_" +
         kEncodingName[std::get<1>(info.param)] + (std::get<2>(info.param) ? "_zlib" : "_raw");
}

INSTANTIATE_TEST_SUITE_P(AllTypesEncodings, VtkXmlRoundTrip,
                         ::testing::Combine(::testing::Range(0, 4), ::testing::Range(0, 3),
                                            ::testing::Bool()),
                         round_trip_name);

TEST(VtkXmlRoundTrip, LargeArraysSpanManyCompressionBlocks) {
  ImageData img;
  img.dims = {64, 64, 33};
  img.origin = {-1.5, 0.1, 1e-7};
  img.spacing = {0.1, 0.2, 0.3};
  DataArray f("noise", ScalarType::Float32, 1, img.num_points());
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> u(-1, 1);
  for (auto& v : f.values<float>()) v = u(rng);
  img.point_data.add(std::move(f), AttributeRole::Scalars);
  DataArray z("zeros", ScalarType::Float64, 3, img.num_points());
  img.point_data.add(std::move(z));
  for (VtkXmlEncoding enc : kEncodings) {
    for (bool c : {false, true}) {
      const std::string text = write_string(img, enc, c);
      EXPECT_EQ(read_string(text, "big.vti"), Dataset(img));
    }
  }
  // Compression actually compresses the zero array.
  EXPECT_LT(write_string(img, VtkXmlEncoding::Appended, true).size(),
            write_string(img, VtkXmlEncoding::Appended, false).size() * 3 / 4);
}

TEST(VtkXmlRoundTrip, EmptyDatasets) {
  PolyData empty;
  UnstructuredGrid ug;
  ImageData one;  // a single point
  for (VtkXmlEncoding enc : kEncodings) {
    for (bool c : {false, true}) {
      EXPECT_EQ(read_string(write_string(empty, enc, c)), Dataset(empty));
      EXPECT_EQ(read_string(write_string(ug, enc, c)), Dataset(ug));
      EXPECT_EQ(read_string(write_string(one, enc, c)), Dataset(one));
    }
  }
}

TEST(VtkXmlRoundTrip, NamesNeedingEscapes) {
  PolyData pd = test::sample_poly(true);
  pd.point_data.add(DataArray::from_vector<float>("a<b>&\"c\" d", 1, {1, 2, 3, 4, 5}),
                    AttributeRole::Scalars);
  for (VtkXmlEncoding enc : kEncodings) {
    EXPECT_EQ(read_string(write_string(pd, enc, true)), Dataset(pd));
  }
}

TEST(VtkXmlWrite, AsciiFloatsAreShortestRoundTrip) {
  PolyData pd;
  pd.points = Points(0, ScalarType::Float64);
  pd.points.push_back({0.1, 1.0 / 3.0, 1e-300});
  pd.verts.add({0});
  const std::string text = write_string(pd, VtkXmlEncoding::Ascii, false);
  EXPECT_NE(text.find("0.1 0.3333333333333333 1e-300"), std::string::npos) << text;
  EXPECT_NE(text.find("format=\"ascii\""), std::string::npos);
  EXPECT_EQ(text.find("compressor"), std::string::npos);
  EXPECT_EQ(read_string(text), Dataset(pd));
}

TEST(VtkXmlWrite, HeaderAndConnectivityTypes) {
  const Dataset ds = test::sample_unstructured();
  const std::string text = write_string(ds, VtkXmlEncoding::Appended, true);
  EXPECT_NE(text.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(text.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(text.find("byte_order=\"LittleEndian\""), std::string::npos);
  // The ids fit: Int32 (VTK's SetIdTypeToInt32), half the bytes.
  EXPECT_NE(text.find("type=\"Int32\" Name=\"connectivity\""), std::string::npos);
  EXPECT_NE(text.find("type=\"Int32\" Name=\"offsets\""), std::string::npos);
  EXPECT_EQ(text.find("Int64\" Name=\"connectivity"), std::string::npos);
  EXPECT_NE(text.find("type=\"UInt8\" Name=\"types\""), std::string::npos);
  EXPECT_NE(text.find("<PointData Scalars=\"pressure\" Tensors=\"stress\">"), std::string::npos);
  EXPECT_NE(text.find("<AppendedData encoding=\"raw\">"), std::string::npos);
}

TEST(VtkXmlWrite, Extension) {
  EXPECT_EQ(vtk_xml_extension(Dataset(ImageData{})), ".vti");
  EXPECT_EQ(vtk_xml_extension(Dataset(StructuredGrid{})), ".vts");
  EXPECT_EQ(vtk_xml_extension(Dataset(PolyData{})), ".vtp");
  EXPECT_EQ(vtk_xml_extension(Dataset(UnstructuredGrid{})), ".vtu");
  const fs::path dir = scratch("ext");
  try {
    write_vtk_xml(test::sample_poly(), dir / "mesh.vtu");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("mesh.vtu"), std::string::npos) << m;
    EXPECT_NE(m.find(".vtp"), std::string::npos) << m;
  }
  EXPECT_EQ(entries(dir), 0u);
  // Upper-case extensions are fine.
  write_vtk_xml(test::sample_image(), dir / "IMG.VTI");
  EXPECT_EQ(read_vtk_xml(dir / "IMG.VTI"), Dataset(test::sample_image()));
}

TEST(VtkXmlWrite, InvalidDatasetIsRejectedBeforeWriting) {
  PolyData pd = test::sample_poly();
  pd.polys.add({0, 1, 99});
  std::ostringstream out;
  EXPECT_THROW(write_vtk_xml(pd, out), Error);
  EXPECT_TRUE(out.str().empty());
  try {
    write_vtk_xml(pd, fs::path(ISOFORGE_TEST_TMP) / isoforge::test::current_test_id() / "never.vtp");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("never.vtp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("99"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(fs::path(ISOFORGE_TEST_TMP) / isoforge::test::current_test_id() / "never.vtp"));
}

// =============================================================================================
// Atomic writes
// =============================================================================================

TEST(VtkXmlWrite, FailedWriteLeavesExistingFileAndNoTemp) {
  const fs::path dir = scratch("atomic");
  const fs::path path = dir / "keep.vtp";
  write_vtk_xml(test::sample_poly(), path);
  const std::string good = slurp(path);
  // 1. An invalid dataset.
  PolyData bad = test::sample_poly();
  bad.lines.add({0, 42});
  EXPECT_THROW(write_vtk_xml(bad, path), Error);
  EXPECT_EQ(slurp(path), good);
  EXPECT_EQ(entries(dir), 1u);
  // 2. An I/O failure half-way: a file size limit makes the write fail after the temporary file
  //    was created and partly written.
  PolyData big;
  for (int i = 0; i < 40000; ++i) big.points.push_back({0, 0, 0});
  big.verts.add({0});
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit small = old;
  small.rlim_cur = 64 * 1024;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  try {
    write_vtk_xml(big, path, VtkXmlWriteOptions{VtkXmlEncoding::Ascii, false});
  } catch (const Error& e) {
    threw = true;
    EXPECT_NE(std::string(e.what()).find("keep.vtp"), std::string::npos) << e.what();
  }
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &old), 0);
  EXPECT_TRUE(threw);
  EXPECT_EQ(slurp(path), good);
  EXPECT_EQ(entries(dir), 1u);
  // The same write succeeds without the limit.
  write_vtk_xml(big, path, VtkXmlWriteOptions{VtkXmlEncoding::Ascii, false});
  EXPECT_EQ(read_vtk_xml(path), Dataset(big));
  EXPECT_EQ(entries(dir), 1u);
  // 3. A directory that does not exist.
  EXPECT_THROW(write_vtk_xml(test::sample_poly(), dir / "no" / "such.vtp"), Error);
}

// =============================================================================================
// Hand-written files: each format feature
// =============================================================================================

TEST(VtkXmlRead, AsciiTriangleAndRoles) {
  const Dataset ds = read_string(kTriangle, "tri.vtp");
  const auto& pd = std::get<PolyData>(ds);
  EXPECT_EQ(pd.points.size(), 3u);
  EXPECT_EQ(pd.polys.size(), 1u);
  EXPECT_EQ(pd.points.array().name(), "Points");
  ASSERT_NE(pd.point_data.scalars(), nullptr);
  EXPECT_EQ(pd.point_data.scalars()->name(), "s");
  EXPECT_EQ(pd.point_data.scalars()->get(2), 3.0);
  EXPECT_EQ(pd.points[1].x, 1.0);
}

TEST(VtkXmlRead, InformationKeysStringAndBitArraysAreSkipped) {
  std::string f =
      replace(kTriangle, R"(<DataArray type="Float32" Name="s" format="ascii">1 2 3</DataArray>)",
              R"(<DataArray type="Float32" Name="s" format="ascii">
          1 2
          <InformationKey name="L2_NORM_RANGE" location="vtkDataArray" length="2">
            <Value index="0">99</Value><Value index="1">98</Value>
          </InformationKey>
          3
        </DataArray>
        <DataArray type="String" Name="labels" format="ascii">97 0 98 0 99 0</DataArray>
        <DataArray type="Bit" Name="bits" format="ascii">1 0 1</DataArray>
        <Array type="String" Name="other" NumberOfTuples="1" format="ascii">97 0</Array>)");
  f = replace(f, "<PolyData>", R"(<PolyData>
    <FieldData>
      <DataArray type="String" Name="names" NumberOfTuples="1" format="binary">AAAA</DataArray>
      <DataArray type="Int16" Name="ids" NumberOfTuples="2" format="ascii">-5 5</DataArray>
    </FieldData>)");
  const auto pd = std::get<PolyData>(read_string(f, "info.vtp"));
  ASSERT_EQ(pd.point_data.size(), 1u);
  EXPECT_EQ(pd.point_data[0].values<float>()[2], 3.0f);
  ASSERT_EQ(pd.field_data.size(), 1u);
  EXPECT_EQ(pd.field_data.get("ids").get(0), -5.0);
}

TEST(VtkXmlRead, UInt64HeadersInlineBinary) {
  for (bool z : {false, true}) {
    for (bool separate : {false, true}) {
      Enc e;
      e.h64 = true;
      e.z = z;
      e.separate = separate;
      const std::vector<double> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.5};
      const std::vector<std::int64_t> conn = {0, 1, 3, 2};
      const std::vector<std::int64_t> off = {4};
      const std::string f =
          std::string("<VTKFile type=\"PolyData\"") + root_attrs(e) +
          "><PolyData><Piece NumberOfPoints=\"4\" NumberOfPolys=\"1\"><Points>"
          "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">" +
          inline_payload(raw_bytes(pts, false), e) +
          "</DataArray></Points><Polys>"
          "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"binary\">\n  " +
          inline_payload(raw_bytes(conn, false), e) +
          "\n</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\">" +
          inline_payload(raw_bytes(off, false), e) +
          "</DataArray></Polys></Piece></PolyData></VTKFile>";
      const auto pd = std::get<PolyData>(read_string(f, "u64.vtp"));
      EXPECT_EQ(pd.points.type(), ScalarType::Float64);
      EXPECT_EQ(pd.points[3].z, 0.5);
      ASSERT_EQ(pd.polys.size(), 1u);
      EXPECT_EQ(std::vector<Index>(pd.polys.cell(0).begin(), pd.polys.cell(0).end()),
                (std::vector<Index>{0, 1, 3, 2}));
    }
  }
}

TEST(VtkXmlRead, BigEndianInlineAndAppended) {
  for (bool z : {false, true}) {
    for (bool h64 : {false, true}) {
      Enc e;
      e.big = true;
      e.z = z;
      e.h64 = h64;
      e.separate = z;
      const std::vector<float> pts = {0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 4};
      const std::vector<std::int32_t> conn = {0, 1, 2, 3};
      const std::vector<std::int32_t> off = {4};
      const std::vector<std::uint8_t> types = {10};
      const std::vector<std::int16_t> s16 = {-1, 256, 1000, -32768};
      const std::vector<double> cellv = {1.0 / 3.0};
      // Inline.
      std::string f =
          std::string("<VTKFile type=\"UnstructuredGrid\"") + root_attrs(e) +
          "><UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">"
          "<PointData Scalars=\"s\"><DataArray type=\"Int16\" Name=\"s\" format=\"binary\">" +
          inline_payload(raw_bytes(s16, true), e) +
          "</DataArray></PointData><CellData><DataArray type=\"Float64\" Name=\"c\" "
          "format=\"binary\">" +
          inline_payload(raw_bytes(cellv, true), e) +
          "</DataArray></CellData><Points><DataArray type=\"Float32\" "
          "NumberOfComponents=\"3\" format=\"binary\">" +
          inline_payload(raw_bytes(pts, true), e) +
          "</DataArray></Points><Cells>"
          "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"binary\">" +
          inline_payload(raw_bytes(conn, true), e) +
          "</DataArray><DataArray type=\"Int32\" Name=\"offsets\" format=\"binary\">" +
          inline_payload(raw_bytes(off, true), e) +
          "</DataArray><DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">" +
          inline_payload(raw_bytes(types, true), e) +
          "</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>";
      const auto ug = std::get<UnstructuredGrid>(read_string(f, "be.vtu"));
      EXPECT_EQ(ug.points[2].y, 3.0);
      EXPECT_EQ(ug.types, std::vector<CellType>{CellType::Tetra});
      EXPECT_EQ(ug.point_data.scalars()->values<std::int16_t>()[1], 256);
      EXPECT_EQ(ug.point_data.scalars()->values<std::int16_t>()[3], -32768);
      EXPECT_EQ(ug.cell_data.get("c").get(0), 1.0 / 3.0);
      // Appended raw.
      std::string app;
      auto put = [&](const std::string& bytes) {
        const std::string off_s = std::to_string(app.size());
        app += appended_payload(bytes, e);
        return off_s;
      };
      const std::string o1 = put(raw_bytes(pts, true));
      const std::string o2 = put(raw_bytes(conn, true));
      const std::string o3 = put(raw_bytes(off, true));
      const std::string o4 = put(raw_bytes(types, true));
      f = std::string("<VTKFile type=\"UnstructuredGrid\"") + root_attrs(e) +
          "><UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points>"
          "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
          o1 +
          "\"/></Points><Cells>"
          "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\"" +
          o2 + "\"/><DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\"" + o3 +
          "\"/><DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" + o4 +
          "\"/></Cells></Piece></UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n   _" + app +
          "\n</AppendedData>\n</VTKFile>\n";
      const auto ug2 = std::get<UnstructuredGrid>(read_string(f, "be_app.vtu"));
      EXPECT_EQ(ug2.points[3].z, 4.0);
      EXPECT_EQ(ug2.cells.connectivity(), (std::vector<Index>{0, 1, 2, 3}));
    }
  }
}

TEST(VtkXmlRead, Int32AndInt64Connectivity) {
  for (const char* t : {"Int32", "Int64", "UInt8", "UInt32", "UInt64", "Int16"}) {
    std::string f = kTriangle;
    f = replace(f, R"(<DataArray type="Int32" Name="connectivity")",
                std::string("<DataArray type=\"") + t + "\" Name=\"connectivity\"");
    f = replace(f, R"(<DataArray type="Int32" Name="offsets")",
                std::string("<DataArray type=\"") + t + "\" Name=\"offsets\"");
    const auto pd = std::get<PolyData>(read_string(f, std::string("conn_") + t + ".vtp"));
    EXPECT_EQ(pd.polys.connectivity(), (std::vector<Index>{0, 1, 2})) << t;
    EXPECT_EQ(pd.polys.offsets(), (std::vector<Index>{0, 3})) << t;
  }
}

/// A raw appended section being built: put() adds a payload and returns its offset.
struct RawAppended {
  Enc e;
  std::string data{};
  std::string put(const std::string& bytes) {
    const std::string offset = std::to_string(data.size());
    data += appended_payload(bytes, e);
    return offset;
  }
};

// Ids of every integer type are widened in place, in rounds from the top of the array (300 000
// vertices: several rounds of parallel passes, then a serial rest), in both byte orders, raw
// and zlib; offsets of 32 and 64 bits, connectivity of any type (its ids stay below 100).
template <class T>
void expect_widened_ids(const char* type, const char* offsets_type, bool big, bool z) {
  SCOPED_TRACE(std::string(type) + " / " + offsets_type + (big ? " big" : " little") +
               (z ? " zlib" : " raw"));
  const std::size_t n = 300'000, np = 100;
  std::vector<T> conn(n);
  std::vector<Index> want(n);
  for (std::size_t i = 0; i < n; ++i) {
    conn[i] = static_cast<T>((i * 37) % np);
    want[i] = static_cast<Index>(conn[i]);
  }
  Enc e;
  e.h64 = true;
  e.big = big;
  e.z = z;
  e.block = 1 << 16;
  const auto offsets_bytes = [&]() {
    std::vector<std::int64_t> o64(n);
    std::vector<std::uint32_t> o32(n);
    for (std::size_t i = 0; i < n; ++i) o64[i] = static_cast<std::int64_t>(i + 1);
    for (std::size_t i = 0; i < n; ++i) o32[i] = static_cast<std::uint32_t>(i + 1);
    return std::string(offsets_type) == "UInt32" ? raw_bytes(o32, big) : raw_bytes(o64, big);
  };
  std::vector<float> pts(3 * np, 0.5f);
  RawAppended app{e};
  const std::string o1 = app.put(raw_bytes(pts, big));
  const std::string o2 = app.put(raw_bytes(conn, big));
  const std::string o3 = app.put(offsets_bytes());
  const std::string f =
      std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"") + root_attrs(e) +
      ">\n<PolyData><Piece NumberOfPoints=\"100\" NumberOfVerts=\"300000\"><Points>"
      "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
      o1 + "\"/></Points><Verts><DataArray type=\"" + type +
      "\" Name=\"connectivity\" format=\"appended\" offset=\"" + o2 + "\"/><DataArray type=\"" +
      offsets_type + "\" Name=\"offsets\" format=\"appended\" offset=\"" + o3 +
      "\"/></Verts></Piece></PolyData>\n<AppendedData encoding=\"raw\">\n   _" + app.data +
      "\n</AppendedData>\n</VTKFile>\n";
  const auto pd = std::get<PolyData>(read_string(f, "widen.vtp"));
  ASSERT_EQ(pd.verts.size(), n);
  EXPECT_EQ(pd.verts.connectivity(), want);
  std::vector<Index> offsets(n + 1);
  for (std::size_t i = 0; i <= n; ++i) offsets[i] = static_cast<Index>(i);
  EXPECT_EQ(pd.verts.offsets(), offsets);
}

TEST(VtkXmlRead, IdsOfEveryIntegerTypeAreWidenedInPlace) {
  for (const bool big : {false, true}) {
    for (const bool z : {false, true}) {
      expect_widened_ids<std::int8_t>("Int8", "UInt32", big, z);
      expect_widened_ids<std::uint8_t>("UInt8", "Int64", big, z);
      expect_widened_ids<std::int16_t>("Int16", "UInt32", big, z);
      expect_widened_ids<std::uint16_t>("UInt16", "Int64", big, z);
      expect_widened_ids<std::int32_t>("Int32", "UInt32", big, z);
      expect_widened_ids<std::uint32_t>("UInt32", "Int64", big, z);
      expect_widened_ids<std::int64_t>("Int64", "UInt32", big, z);
      expect_widened_ids<std::uint64_t>("UInt64", "Int64", big, z);
    }
  }
  // An UInt64 id above Int64's range is named, binary and ascii.
  {
    Enc e;
    const std::vector<float> pts(9, 0.0f);
    const std::vector<std::uint64_t> conn = {0, std::uint64_t{1} << 63, 2};
    const std::vector<std::int32_t> off = {3};
    RawAppended app{e};
    const std::string o1 = app.put(raw_bytes(pts, false));
    const std::string o2 = app.put(raw_bytes(conn, false));
    const std::string o3 = app.put(raw_bytes(off, false));
    expect_read_error(
        std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"") + root_attrs(e) +
            ">\n<PolyData><Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\"><Points>"
            "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" "
            "offset=\"" +
            o1 +
            "\"/></Points><Polys><DataArray type=\"UInt64\" Name=\"connectivity\" "
            "format=\"appended\" offset=\"" +
            o2 + "\"/><DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\"" +
            o3 + "\"/></Polys></Piece></PolyData>\n<AppendedData encoding=\"raw\">\n   _" +
            app.data + "\n</AppendedData>\n</VTKFile>\n",
        "u64bin.vtp", {"'connectivity'", "value 1 (9223372036854775808) is out of range"});
  }
  std::string f = kTriangle;
  f = replace(f, R"(<DataArray type="Int32" Name="connectivity")",
              R"(<DataArray type="UInt64" Name="connectivity")");
  expect_read_error(replace(f, ">0 1 2<", ">0 9223372036854775808 2<"), "u64big.vtp",
                    {"value 1 (9223372036854775808) is out of range"});
}

TEST(VtkXmlRead, AppendedBase64) {
  for (int variant = 0; variant < 4; ++variant) {
    Enc e;
    e.z = variant & 1;
    e.separate = variant & 2;
    const std::vector<float> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<std::int64_t> conn = {0, 1, 2};
    const std::vector<std::int64_t> off = {3};
    const std::vector<std::uint32_t> val = {7, 8, 9};
    std::string app;
    auto put = [&](const std::string& bytes) {
      const std::string o = std::to_string(app.size());
      app += inline_payload(bytes, e);
      return o;
    };
    const std::string o1 = put(raw_bytes(val, false));
    const std::string o2 = put(raw_bytes(pts, false));
    const std::string o3 = put(raw_bytes(conn, false));
    const std::string o4 = put(raw_bytes(off, false));
    const std::string f =
        std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"") + root_attrs(e) +
        ">\n<PolyData><Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\"><PointData>"
        "<DataArray type=\"UInt32\" Name=\"v\" format=\"appended\" offset=\"" +
        o1 +
        "\"/></PointData><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"appended\" offset=\"" +
        o2 +
        "\"/></Points><Polys>"
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"" +
        o3 + "\"/><DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"" + o4 +
        "\"/></Polys></Piece></PolyData>\n  <AppendedData encoding=\"base64\">\n   _" + app +
        "\n  </AppendedData>\n</VTKFile>\n";
    const auto pd = std::get<PolyData>(read_string(f, "app64.vtp"));
    EXPECT_EQ(pd.point_data.get("v").values<std::uint32_t>()[2], 9u);
    EXPECT_EQ(pd.points[2].y, 1.0);
    EXPECT_EQ(pd.polys.size(), 1u);
  }
}

TEST(VtkXmlRead, MultiplePolyDataPiecesAreMerged) {
  const std::string f = R"(<VTKFile type="PolyData" version="1.0">
<PolyData>
  <Piece NumberOfPoints="3" NumberOfVerts="1" NumberOfPolys="1">
    <PointData Scalars="p"><DataArray type="Float32" Name="p" format="ascii">1 2 3</DataArray></PointData>
    <CellData><DataArray type="Int32" Name="c" format="ascii">10 20</DataArray></CellData>
    <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray></Points>
    <Verts><DataArray type="Int32" Name="connectivity" format="ascii">0</DataArray>
           <DataArray type="Int32" Name="offsets" format="ascii">1</DataArray></Verts>
    <Polys><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
           <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray></Polys>
  </Piece>
  <Piece NumberOfPoints="4" NumberOfLines="1" NumberOfPolys="1">
    <PointData Scalars="p"><DataArray type="Float32" Name="p" format="ascii">4 5 6 7</DataArray></PointData>
    <CellData><DataArray type="Int32" Name="c" format="ascii">30 40</DataArray></CellData>
    <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 1 1 0 1 1 1 1 0 1 1</DataArray></Points>
    <Lines><DataArray type="Int64" Name="connectivity" format="ascii">1 2</DataArray>
           <DataArray type="Int64" Name="offsets" format="ascii">2</DataArray></Lines>
    <Polys><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
           <DataArray type="Int32" Name="offsets" format="ascii">4</DataArray></Polys>
  </Piece>
</PolyData>
</VTKFile>)";
  const auto pd = std::get<PolyData>(read_string(f, "pieces.vtp"));
  EXPECT_EQ(pd.points.size(), 7u);
  EXPECT_EQ(pd.points.type(), ScalarType::Float64);  // promoted
  EXPECT_EQ(pd.points[6].y, 1.0);
  EXPECT_EQ(pd.verts.connectivity(), (std::vector<Index>{0}));
  EXPECT_EQ(pd.lines.connectivity(), (std::vector<Index>{4, 5}));
  EXPECT_EQ(pd.polys.connectivity(), (std::vector<Index>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(pd.polys.offsets(), (std::vector<Index>{0, 3, 7}));
  const auto p = pd.point_data.get("p").values<float>();
  EXPECT_EQ(std::vector<float>(p.begin(), p.end()), (std::vector<float>{1, 2, 3, 4, 5, 6, 7}));
  // Cell order is verts, lines, polys over the whole dataset.
  const auto c = pd.cell_data.get("c").values<std::int32_t>();
  EXPECT_EQ(std::vector<std::int32_t>(c.begin(), c.end()),
            (std::vector<std::int32_t>{10, 30, 20, 40}));
  EXPECT_EQ(pd.point_data.scalars()->name(), "p");
}

TEST(VtkXmlRead, MultipleUnstructuredPiecesAreMerged) {
  const std::string piece = R"(
  <Piece NumberOfPoints="3" NumberOfCells="1">
    <CellData><DataArray type="UInt8" Name="m" format="ascii">%M</DataArray></CellData>
    <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 %Z</DataArray></Points>
    <Cells><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
           <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
           <DataArray type="UInt8" Name="types" format="ascii">5</DataArray></Cells>
  </Piece>)";
  std::string f = "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>";
  for (int i = 0; i < 3; ++i) {
    f += replace(replace(piece, "%M", std::to_string(i + 1)), "%Z", std::to_string(i));
  }
  f += "</UnstructuredGrid></VTKFile>";
  const auto ug = std::get<UnstructuredGrid>(read_string(f, "pieces.vtu"));
  EXPECT_EQ(ug.points.size(), 9u);
  EXPECT_EQ(ug.cells.connectivity(), (std::vector<Index>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ug.types.size(), 3u);
  EXPECT_EQ(ug.cell_data.get("m").get(2), 3.0);
  EXPECT_EQ(ug.points[8].z, 2.0);
}

TEST(VtkXmlRead, EmptyPiecesWithoutTheArraysAreSkipped) {
  // Parallel writers emit pieces with no point and no cell, often without the arrays of the
  // others; VTK reads past them, and so does the reader (first, middle and last).
  const std::string full = R"(
  <Piece NumberOfPoints="3" NumberOfPolys="1">
    <PointData><DataArray type="Float32" Name="p" format="ascii">1 2 3</DataArray></PointData>
    <CellData><DataArray type="Int32" Name="c" format="ascii">7</DataArray></CellData>
    <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray></Points>
    <Polys><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
           <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray></Polys>
  </Piece>)";
  const std::string empty = R"(<Piece NumberOfPoints="0" NumberOfPolys="0"></Piece>)";
  const std::string f = "<VTKFile type=\"PolyData\"><PolyData>" + empty + full + empty + full +
                        empty + "</PolyData></VTKFile>";
  const auto pd = std::get<PolyData>(read_string(f, "empty_pieces.vtp"));
  EXPECT_EQ(pd.points.size(), 6u);
  EXPECT_EQ(pd.polys.connectivity(), (std::vector<Index>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(pd.point_data.get("p").get(5), 3.0);
  EXPECT_EQ(pd.cell_data.get("c").size(), 2u);
  // Only empty pieces: an empty dataset.
  const auto none = std::get<PolyData>(read_string(
      "<VTKFile type=\"PolyData\"><PolyData>" + empty + empty + "</PolyData></VTKFile>", "e.vtp"));
  EXPECT_EQ(none.points.size(), 0u);
  // Unstructured grids likewise.
  const std::string cell = R"(
  <Piece NumberOfPoints="3" NumberOfCells="1">
    <CellData><DataArray type="UInt8" Name="m" format="ascii">4</DataArray></CellData>
    <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray></Points>
    <Cells><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
           <DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
           <DataArray type="UInt8" Name="types" format="ascii">5</DataArray></Cells>
  </Piece>)";
  const auto ug = std::get<UnstructuredGrid>(
      read_string("<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>" + cell +
                      R"(<Piece NumberOfPoints="0" NumberOfCells="0"></Piece>)" + cell +
                      "</UnstructuredGrid></VTKFile>",
                  "empty_pieces.vtu"));
  EXPECT_EQ(ug.points.size(), 6u);
  EXPECT_EQ(ug.types.size(), 2u);
  EXPECT_EQ(ug.cell_data.get("m").get(1), 4.0);
}

TEST(VtkXmlRead, ImageExtentNotStartingAtZero) {
  const std::string f =
      R"(<VTKFile type="ImageData" version="2.2" byte_order="LittleEndian" header_type="UInt64">
  <ImageData WholeExtent="2 4 -1 0 5 5" Origin="10 20 30" Spacing="0.5 2 3" Direction="1 0 0 0 1 0 0 0 1">
    <Piece Extent="2 4 -1 0 5 5">
      <PointData Scalars="v"><DataArray type="Int8" Name="v" format="ascii">-1 -2 -3 4 5 6</DataArray></PointData>
      <CellData><DataArray type="Float64" Name="c" format="ascii">0.5 0.25</DataArray></CellData>
    </Piece>
  </ImageData>
</VTKFile>)";
  const auto img = std::get<ImageData>(read_string(f, "ext.vti"));
  EXPECT_EQ(img.dims, (Dims{3, 2, 1}));
  EXPECT_EQ(img.origin, (Vec3{11, 18, 45}));
  EXPECT_EQ(img.spacing, (Vec3{0.5, 2, 3}));
  EXPECT_EQ(img.point_data.scalars()->get(2), -3.0);
  EXPECT_EQ(img.cell_data.get("c").get(1), 0.25);
}

TEST(VtkXmlRead, ImagePiecesTilingTheWholeExtentAreAssembled) {
  const std::string f = R"(<VTKFile type="ImageData">
  <ImageData WholeExtent="0 3 0 1 0 0" Origin="0 0 0" Spacing="1 1 1">
    <Piece Extent="1 3 0 1 0 0">
      <PointData Scalars="v"><DataArray type="Float32" Name="v" format="ascii">1 2 3 5 6 7</DataArray></PointData>
      <CellData><DataArray type="Int32" Name="c" format="ascii">101 102</DataArray></CellData>
    </Piece>
    <Piece Extent="0 1 0 1 0 0">
      <PointData Scalars="v"><DataArray type="Float32" Name="v" format="ascii">0 1 4 5</DataArray></PointData>
      <CellData><DataArray type="Int32" Name="c" format="ascii">100</DataArray></CellData>
    </Piece>
    <Piece Extent="0 -1 0 -1 0 -1"/>
  </ImageData>
</VTKFile>)";
  const auto img = std::get<ImageData>(read_string(f, "tiles.vti"));
  const auto v = img.point_data.get("v").values<float>();
  EXPECT_EQ(std::vector<float>(v.begin(), v.end()), (std::vector<float>{0, 1, 2, 3, 4, 5, 6, 7}));
  const auto c = img.cell_data.get("c").values<std::int32_t>();
  EXPECT_EQ(std::vector<std::int32_t>(c.begin(), c.end()),
            (std::vector<std::int32_t>{100, 101, 102}));
  EXPECT_EQ(img.point_data.scalars()->name(), "v");
}

TEST(VtkXmlRead, StructuredGridPiecesAreAssembled) {
  const std::string f = R"(<VTKFile type="StructuredGrid">
  <StructuredGrid WholeExtent="0 1 0 2 0 0">
    <Piece Extent="0 1 0 1 0 0">
      <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 1 1 0</DataArray></Points>
    </Piece>
    <Piece Extent="0 1 1 2 0 0">
      <Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 1 0 1 1 0 0 2 0 1 2.5 0</DataArray></Points>
    </Piece>
  </StructuredGrid>
</VTKFile>)";
  const auto sg = std::get<StructuredGrid>(read_string(f, "tiles.vts"));
  EXPECT_EQ(sg.dims, (Dims{2, 3, 1}));
  ASSERT_EQ(sg.points.size(), 6u);
  EXPECT_EQ(sg.points[5].y, 2.5);
  EXPECT_EQ(sg.points[2].y, 1.0);
}

TEST(VtkXmlRead, ManySmallCompressedBlocksUInt32) {
  // 40 floats (160 bytes) in 24-byte blocks: 7 blocks, the last one partial (16 bytes).
  Enc e;
  e.z = true;
  e.separate = true;
  e.block = 24;
  std::vector<float> s(40);
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<float>(i) * 0.5f;
  std::string f = kTriangle;
  f = replace(f, R"(version="0.1" byte_order="LittleEndian")",
              R"(version="0.1" byte_order="LittleEndian" compressor="vtkZLibDataCompressor")");
  f = replace(f, "<PolyData>",
              "<PolyData><FieldData><DataArray type=\"Float32\" Name=\"big\" "
              "NumberOfTuples=\"40\" format=\"binary\">" +
                  inline_payload(raw_bytes(s, false), e) + "</DataArray></FieldData>");
  const auto pd = std::get<PolyData>(read_string(f, "blocks.vtp"));
  const auto v = pd.field_data.get("big").values<float>();
  EXPECT_EQ(std::vector<float>(v.begin(), v.end()), s);
}

// =============================================================================================
// VTK (python3-vtk) cross-checks
// =============================================================================================

namespace {

/// A python interpreter that can `import vtk`, or "" (the tests are then skipped).
const std::string& vtk_python() {
  static const std::string python = [] {
    for (const char* p : {"python3", "/usr/bin/python3"}) {
      const std::string cmd = std::string(p) + " -c \"import vtk\" >/dev/null 2>&1";
      if (std::system(cmd.c_str()) == 0) return std::string(p);
    }
    return std::string();
  }();
  return python;
}

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0) out.append(buf, n);
  const int status = ::pclose(p);
  EXPECT_EQ(status, 0) << cmd << "\n" << out;
  return out;
}

const char* kSummaryPy = R"(
import sys, vtk
import numpy
from vtk.util.numpy_support import vtk_to_numpy
def ids(name, cells):
    c = vtk_to_numpy(cells.GetConnectivityArray()).astype('int64')
    o = vtk_to_numpy(cells.GetOffsetsArray()).astype('int64')
    w = numpy.arange(len(c), dtype='int64') % 1000 + 1
    print('ids', name, len(c), int(c.sum()), int((c * w).sum()), len(o), int(o.sum()))
def summary(path):
    ext = path.rsplit('.', 1)[1]
    cls = {'vti': vtk.vtkXMLImageDataReader, 'vts': vtk.vtkXMLStructuredGridReader,
           'vtp': vtk.vtkXMLPolyDataReader, 'vtu': vtk.vtkXMLUnstructuredGridReader}[ext]
    r = cls()
    errors = []
    r.AddObserver('ErrorEvent', lambda o, e: errors.append(e))
    r.SetFileName(path)
    r.Update()
    d = r.GetOutput()
    print('errors', len(errors))
    print('points', d.GetNumberOfPoints())
    print('cells', d.GetNumberOfCells())
    print('bounds', *[repr(x) for x in d.GetBounds()])
    if ext == 'vtp':
        print('polycells', d.GetNumberOfVerts(), d.GetNumberOfLines(), d.GetNumberOfPolys(),
              d.GetNumberOfStrips())
        for name, cells in (('verts', d.GetVerts()), ('lines', d.GetLines()),
                            ('polys', d.GetPolys()), ('strips', d.GetStrips())):
            ids(name, cells)
    if ext == 'vtu':
        print('celltypes', *[d.GetCellType(i) for i in range(min(d.GetNumberOfCells(), 50))])
        ids('cells', d.GetCells())
    for tag, fd in (('pd', d.GetPointData()), ('cd', d.GetCellData()), ('fd', d.GetFieldData())):
        for i in range(fd.GetNumberOfArrays()):
            a = fd.GetAbstractArray(i)
            if not isinstance(a, vtk.vtkDataArray):
                continue
            lo, hi = a.GetRange(0) if a.GetNumberOfTuples() else (0.0, 0.0)
            print(tag, a.GetName(), a.GetNumberOfComponents(), a.GetNumberOfTuples(),
                  repr(float(lo)), repr(float(hi)))
    for tag, att in (('pd', d.GetPointData()), ('cd', d.GetCellData())):
        for role, get in (('Scalars', att.GetScalars), ('Vectors', att.GetVectors),
                          ('Normals', att.GetNormals), ('Tensors', att.GetTensors),
                          ('TCoords', att.GetTCoords)):
            a = get()
            print('role', tag, role, a.GetName() if a is not None else '-')
for p in sys.argv[1:]:
    print('file', p)
    summary(p)
)";

/// Writes the summary script into `dir` (each test has its own, as ctest runs tests in
/// parallel processes).
fs::path summary_script(const fs::path& dir) {
  const fs::path p = dir / "vtk_summary.py";
  spit(p, kSummaryPy);
  return p;
}

bool near(double a, double b) {
  if (a == b) return true;
  return std::abs(a - b) <= 1e-6 * std::max({1.0, std::abs(a), std::abs(b)});
}

/// Compares VTK's summary of one file (lines after "file <path>") with what isoforge read.
void compare_summary(const Dataset& ds, const std::vector<std::string>& lines,
                     const std::string& what) {
  SCOPED_TRACE(what);
  int arrays_seen = 0, id_lists = 0;
  bool saw_counts = false;
  for (const std::string& line : lines) {
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "errors") {
      int n = -1;
      in >> n;
      EXPECT_EQ(n, 0) << "VTK reported errors";
    } else if (key == "points") {
      std::size_t n = 0;
      in >> n;
      saw_counts = true;
      EXPECT_EQ(n, num_points(ds));
    } else if (key == "cells") {
      std::size_t n = 0;
      in >> n;
      EXPECT_EQ(n, num_cells(ds));
    } else if (key == "bounds") {
      double b[6];
      for (double& x : b) in >> x;
      const Bounds ours = bounds(ds);
      if (!ours.empty()) {
        for (int a = 0; a < 3; ++a) {
          EXPECT_TRUE(near(b[2 * a], ours.min[a]))
              << a << ": " << b[2 * a] << " vs " << ours.min[a];
          EXPECT_TRUE(near(b[2 * a + 1], ours.max[a])) << b[2 * a + 1] << " vs " << ours.max[a];
        }
      }
    } else if (key == "polycells") {
      std::size_t v, l, p, s;
      in >> v >> l >> p >> s;
      const auto& pd = std::get<PolyData>(ds);
      EXPECT_EQ(v, pd.verts.size());
      EXPECT_EQ(l, pd.lines.size());
      EXPECT_EQ(p, pd.polys.size());
      EXPECT_EQ(s, pd.strips.size());
    } else if (key == "ids") {
      // The connectivity as VTK read it: count, sum, weighted sum; offsets' count and sum.
      std::string name;
      std::size_t n = 0, noff = 0;
      long long sum = 0, weighted = 0, offsum = 0;
      in >> name >> n >> sum >> weighted >> noff >> offsum;
      const CellArray* cells = nullptr;
      if (const auto* pd = std::get_if<PolyData>(&ds)) {
        cells = name == "verts"   ? &pd->verts
                : name == "lines" ? &pd->lines
                : name == "polys" ? &pd->polys
                                  : &pd->strips;
      } else {
        cells = &std::get<UnstructuredGrid>(ds).cells;
      }
      const auto& conn = cells->connectivity();
      long long s = 0, w = 0, o = 0;
      for (std::size_t i = 0; i < conn.size(); ++i) {
        s += conn[i];
        w += conn[i] * static_cast<long long>(i % 1000 + 1);
      }
      for (const Index v : cells->offsets()) o += v;
      EXPECT_EQ(n, conn.size()) << name;
      EXPECT_EQ(sum, s) << name;
      EXPECT_EQ(weighted, w) << name;
      // VTK keeps a lone 0 offset for an empty cell list; isoforge keeps the same.
      EXPECT_EQ(noff, cells->offsets().size()) << name;
      EXPECT_EQ(offsum, o) << name;
      ++id_lists;
    } else if (key == "celltypes") {
      const auto& ug = std::get<UnstructuredGrid>(ds);
      int t;
      std::size_t i = 0;
      while (in >> t) {
        ASSERT_LT(i, ug.types.size());
        EXPECT_EQ(t, static_cast<int>(ug.types[i])) << "cell " << i;
        ++i;
      }
    } else if (key == "pd" || key == "cd" || key == "fd") {
      std::string name;
      int comps;
      std::size_t tuples;
      double lo, hi;
      in >> name >> comps >> tuples >> lo >> hi;
      const Attributes& a = key == "pd"   ? point_data(ds)
                            : key == "cd" ? cell_data(ds)
                                          : field_data(ds);
      const DataArray* arr = a.find(name);
      ASSERT_NE(arr, nullptr) << key << " array " << name;
      EXPECT_EQ(comps, arr->components()) << name;
      EXPECT_EQ(tuples, arr->tuples()) << name;
      if (tuples > 0) {
        const auto [mn, mx] = arr->range(0);
        EXPECT_TRUE(near(lo, mn)) << name << " min " << lo << " vs " << mn;
        EXPECT_TRUE(near(hi, mx)) << name << " max " << hi << " vs " << mx;
      }
      ++arrays_seen;
    } else if (key == "role") {
      std::string tag, role, name;
      in >> tag >> role >> name;
      const Attributes& a = tag == "pd" ? point_data(ds) : cell_data(ds);
      static const std::map<std::string, AttributeRole> roles = {
          {"Scalars", AttributeRole::Scalars},
          {"Vectors", AttributeRole::Vectors},
          {"Normals", AttributeRole::Normals},
          {"Tensors", AttributeRole::Tensors},
          {"TCoords", AttributeRole::TCoords}};
      const std::string& ours = a.active_name(roles.at(role));
      // VTK only reports a role whose array suits it (e.g. 3-component vectors).
      if (name != "-") {
        EXPECT_EQ(name, ours) << tag << " " << role;
      }
    }
  }
  const std::size_t ours = point_data(ds).size() + cell_data(ds).size() + field_data(ds).size();
  EXPECT_EQ(static_cast<std::size_t>(arrays_seen), ours);
  EXPECT_TRUE(saw_counts) << "VTK printed no summary";
  const bool has_cells =
      std::holds_alternative<PolyData>(ds) || std::holds_alternative<UnstructuredGrid>(ds);
  EXPECT_EQ(id_lists, has_cells ? (std::holds_alternative<PolyData>(ds) ? 4 : 1) : 0);
}

/// Runs the summary script on files; returns per-file line lists.
std::map<std::string, std::vector<std::string>> vtk_summaries(const fs::path& dir,
                                                              const std::vector<fs::path>& files) {
  std::string cmd = vtk_python() + " " + summary_script(dir).string();
  for (const auto& f : files) cmd += " '" + f.string() + "'";
  cmd += " 2>&1";
  const std::string out = run(cmd);
  std::map<std::string, std::vector<std::string>> result;
  std::istringstream in(out);
  std::string line, current;
  while (std::getline(in, line)) {
    if (line.rfind("file ", 0) == 0) {
      current = line.substr(5);
      result[current];
    } else if (!current.empty()) {
      result[current].push_back(line);
    }
  }
  return result;
}

}  // namespace

namespace {
ImageData blocky_image();
}  // namespace

TEST(VtkXmlPython, VtkReadsWhatWeWrite) {
  if (vtk_python().empty()) GTEST_SKIP() << "python3 with the vtk module is not available";
  const fs::path dir = scratch("py_read");
  std::vector<fs::path> files;
  std::vector<Dataset> datasets;
  for (int kind = 0; kind < 5; ++kind) {  // kind 4: arrays of several compressed blocks
    const Dataset ds = kind < 4 ? rich(kind) : Dataset(blocky_image());
    for (int enc = 0; enc < 3; ++enc) {
      for (int z : {0, 1, 2}) {  // none, zlib, LZ4
        const fs::path p = dir / ("k" + std::to_string(kind) + "_" + kEncodingName[enc] +
                                  (z == 1 ? "_z" : z == 2 ? "_lz4" : "") +
                                  std::string(vtk_xml_extension(ds)));
        VtkXmlWriteOptions o{kEncodings[enc], z > 0};
        if (z == 2) o.compressor = VtkXmlCompressor::Lz4;
        write_vtk_xml(ds, p, o);
        files.push_back(p);
        datasets.push_back(ds);
      }
    }
    // Cell ids as Int64 too (the files above hold Int32: their ids fit).
    const fs::path p =
        dir / ("k" + std::to_string(kind) + "_int64" + std::string(vtk_xml_extension(ds)));
    VtkXmlWriteOptions o;
    o.id_type = VtkXmlIdType::Int64;
    write_vtk_xml(ds, p, o);
    files.push_back(p);
    datasets.push_back(ds);
  }
  const auto summaries = vtk_summaries(dir, files);
  ASSERT_EQ(summaries.size(), files.size());
  for (std::size_t i = 0; i < files.size(); ++i) {
    const auto it = summaries.find(files[i].string());
    ASSERT_NE(it, summaries.end()) << files[i];
    compare_summary(datasets[i], it->second, files[i].filename().string());
  }
}

TEST(VtkXmlPython, WeReadWhatVtkWrites) {
  if (vtk_python().empty()) GTEST_SKIP() << "python3 with the vtk module is not available";
  const fs::path dir = scratch("py_write");
  const std::string script = R"(
import sys, vtk
out = sys.argv[1]
s = vtk.vtkSphereSource(); s.SetThetaResolution(24); s.SetPhiResolution(16); s.Update()
e = vtk.vtkElevationFilter(); e.SetInputConnection(s.GetOutputPort()); e.Update()
pd = e.GetOutput()
ids = vtk.vtkIntArray(); ids.SetName('cell_ids')
for i in range(pd.GetNumberOfCells()): ids.InsertNextValue(i * 3 - 100)
pd.GetCellData().AddArray(ids)
fd = vtk.vtkDoubleArray(); fd.SetName('time'); fd.InsertNextValue(2.5); fd.InsertNextValue(-1)
pd.GetFieldData().AddArray(fd)
def to32(ca):
    res = vtk.vtkCellArray(); res.Use32BitStorage(); ids = vtk.vtkIdList(); ca.InitTraversal()
    while ca.GetNextCell(ids): res.InsertNextCell(ids)
    return res
pd32 = vtk.vtkPolyData(); pd32.DeepCopy(pd); pd32.SetPolys(to32(pd.GetPolys()))
def poly(name, mode, comp, ht64=False, encode=False, ids32=False):
    w = vtk.vtkXMLPolyDataWriter(); w.SetInputData(pd32 if ids32 else pd)
    w.SetFileName(out + '/' + name)
    getattr(w, 'SetDataModeTo' + mode)()
    if comp == 'none': w.SetCompressorTypeToNone()
    elif comp == 'zlib': w.SetCompressorTypeToZLib()
    elif comp == 'lz4': w.SetCompressorTypeToLZ4()
    elif comp == 'lzma': w.SetCompressorTypeToLZMA()
    if ht64: w.SetHeaderTypeToUInt64()
    if encode: w.EncodeAppendedDataOn()
    else: w.EncodeAppendedDataOff()
    w.SetBlockSize(1024)
    assert w.Write() == 1
poly('sphere_appended_zlib.vtp', 'Appended', 'zlib')
poly('sphere_appended_raw.vtp', 'Appended', 'none', ids32=True)
poly('sphere_appended_b64_zlib64.vtp', 'Appended', 'zlib', ht64=True, encode=True)
poly('sphere_binary_zlib.vtp', 'Binary', 'zlib', ids32=True)
poly('sphere_binary_raw64.vtp', 'Binary', 'none', ht64=True)
poly('sphere_ascii.vtp', 'Ascii', 'none')
poly('sphere_lz4.vtp', 'Appended', 'lz4')
poly('sphere_lzma.vtp', 'Binary', 'lzma')
poly('sphere_lz4_b64.vtp', 'Appended', 'lz4', ht64=True, encode=True)
poly('sphere_lzma_app.vtp', 'Appended', 'lzma', ids32=True)
w = vtk.vtkRTAnalyticSource(); w.SetWholeExtent(-4, 5, -3, 3, 0, 4); w.Update()
img = w.GetOutput()
iw = vtk.vtkXMLImageDataWriter(); iw.SetInputData(img); iw.SetFileName(out + '/wavelet.vti')
iw.SetDataModeToAscii(); assert iw.Write() == 1
iw = vtk.vtkXMLImageDataWriter(); iw.SetInputData(img); iw.SetFileName(out + '/wavelet_z.vti')
iw.SetDataModeToAppended(); iw.SetCompressorTypeToZLib(); iw.SetHeaderTypeToUInt64(); assert iw.Write() == 1
for comp in ('LZ4', 'LZMA'):
    iw = vtk.vtkXMLImageDataWriter(); iw.SetInputData(img); iw.SetFileName(out + '/wavelet_' + comp + '.vti')
    iw.SetDataModeToAppended(); getattr(iw, 'SetCompressorTypeTo' + comp)(); iw.SetBlockSize(512)
    assert iw.Write() == 1
t = vtk.vtkDataSetTriangleFilter(); t.SetInputData(img); t.Update()
ug = t.GetOutput()
uw = vtk.vtkXMLUnstructuredGridWriter(); uw.SetInputData(ug); uw.SetFileName(out + '/tets64.vtu')
uw.SetHeaderTypeToUInt64(); uw.SetDataModeToBinary(); uw.SetCompressorTypeToZLib(); assert uw.Write() == 1
ug32 = vtk.vtkUnstructuredGrid(); ug32.DeepCopy(ug); ug32.SetCells(ug.GetCellTypesArray(), to32(ug.GetCells()))
uw = vtk.vtkXMLUnstructuredGridWriter(); uw.SetInputData(ug32); uw.SetFileName(out + '/tets_app.vtu')
uw.SetHeaderTypeToUInt64(); uw.SetDataModeToAppended(); uw.SetCompressorTypeToNone(); assert uw.Write() == 1
c = vtk.vtkImageDataToPointSet(); c.SetInputData(img); c.Update()
sw = vtk.vtkXMLStructuredGridWriter(); sw.SetInputData(c.GetOutput()); sw.SetFileName(out + '/grid.vts')
sw.SetDataModeToAppended(); sw.EncodeAppendedDataOn(); sw.SetCompressorTypeToZLib(); assert sw.Write() == 1
c2 = vtk.vtkImageDataToPointSet(); c2.SetInputConnection(w.GetOutputPort())
for name, writer, port in (('wavelet_ghost.vti', vtk.vtkXMLImageDataWriter(), w.GetOutputPort()),
                           ('grid_ghost.vts', vtk.vtkXMLStructuredGridWriter(), c2.GetOutputPort())):
    writer.SetInputConnection(port); writer.SetFileName(out + '/' + name)
    writer.SetNumberOfPieces(3); writer.SetGhostLevel(1); assert writer.Write() == 1
print('ok')
)";
  const fs::path sp = dir / "write.py";
  spit(sp, script);
  ASSERT_NE(run(vtk_python() + " " + sp.string() + " " + dir.string() + " 2>&1").find("ok"),
            std::string::npos);
  // VTK wrote LZ4 and LZMA where asked.
  EXPECT_NE(slurp(dir / "sphere_lz4.vtp").find("compressor=\"vtkLZ4DataCompressor\""),
            std::string::npos);
  EXPECT_NE(slurp(dir / "wavelet_LZMA.vti").find("compressor=\"vtkLZMADataCompressor\""),
            std::string::npos);
  std::vector<fs::path> files;
  for (const char* name :
       {"sphere_appended_zlib.vtp", "sphere_appended_raw.vtp", "sphere_appended_b64_zlib64.vtp",
        "sphere_binary_zlib.vtp", "sphere_binary_raw64.vtp", "sphere_ascii.vtp", "wavelet.vti",
        "wavelet_z.vti", "tets64.vtu", "tets_app.vtu", "grid.vts", "sphere_lz4.vtp",
        "sphere_lzma.vtp", "sphere_lz4_b64.vtp", "sphere_lzma_app.vtp", "wavelet_LZ4.vti",
        "wavelet_LZMA.vti"}) {
    files.push_back(dir / name);
  }
  const auto summaries = vtk_summaries(dir, files);
  ASSERT_EQ(summaries.size(), files.size());
  // VTK wrote Int32 connectivity where asked (so both id widths are covered).
  for (const char* name : {"sphere_appended_raw.vtp", "sphere_binary_zlib.vtp", "tets_app.vtu"}) {
    EXPECT_NE(slurp(dir / name).find("type=\"Int32\" Name=\"connectivity\""), std::string::npos)
        << name;
  }
  EXPECT_NE(slurp(dir / "tets64.vtu").find("type=\"Int64\" Name=\"connectivity\""),
            std::string::npos);
  std::optional<PolyData> sphere0;
  for (const fs::path& f : files) {
    const Dataset ds = read_vtk_xml(f);
    const auto it = summaries.find(f.string());
    ASSERT_NE(it, summaries.end()) << f;
    compare_summary(ds, it->second, f.filename().string());
    // All sphere encodings hold the same data.
    if (f.filename().string().rfind("sphere", 0) == 0) {
      if (!sphere0) {
        sphere0 = std::get<PolyData>(ds);
      } else {
        const auto& a = std::get<PolyData>(ds);
        const auto& b = *sphere0;
        EXPECT_EQ(a.points, b.points) << f;
        EXPECT_EQ(a.polys, b.polys) << f;
        EXPECT_EQ(a.point_data.get("Elevation"), b.point_data.get("Elevation")) << f;
        EXPECT_EQ(a.cell_data.get("cell_ids"), b.cell_data.get("cell_ids")) << f;
      }
    }
  }
  // The wavelet's extent starts at -4: the origin is shifted so the bounds match VTK's.
  const auto img = std::get<ImageData>(read_vtk_xml(dir / "wavelet.vti"));
  EXPECT_EQ(img.dims, (Dims{10, 7, 5}));
  EXPECT_EQ(img.origin, (Vec3{-4, -3, 0}));
  EXPECT_EQ(read_vtk_xml(dir / "wavelet_z.vti"), Dataset(img));
  EXPECT_EQ(read_vtk_xml(dir / "wavelet_LZ4.vti"), Dataset(img));
  EXPECT_EQ(read_vtk_xml(dir / "wavelet_LZMA.vti"), Dataset(img));
  // Pieces written with a ghost level overlap; assembled, they hold the data written, and the
  // ghost flags mark nothing as duplicate.
  EXPECT_NE(slurp(dir / "wavelet_ghost.vti").find("vtkGhostType"), std::string::npos);
  const auto ghost = std::get<ImageData>(read_vtk_xml(dir / "wavelet_ghost.vti"));
  const auto grid = std::get<StructuredGrid>(read_vtk_xml(dir / "grid.vts"));
  const auto grid_ghost = std::get<StructuredGrid>(read_vtk_xml(dir / "grid_ghost.vts"));
  EXPECT_EQ(ghost.dims, img.dims);
  EXPECT_EQ(ghost.origin, img.origin);
  EXPECT_EQ(ghost.point_data.get("RTData"), img.point_data.get("RTData"));
  EXPECT_EQ(grid_ghost.points, grid.points);
  EXPECT_EQ(grid_ghost.point_data.get("RTData"), grid.point_data.get("RTData"));
  for (const Attributes* a :
       {&ghost.point_data, &ghost.cell_data, &grid_ghost.point_data, &grid_ghost.cell_data}) {
    const auto flags = a->get("vtkGhostType").values<std::uint8_t>();
    EXPECT_EQ(std::count(flags.begin(), flags.end(), std::uint8_t{0}),
              static_cast<std::ptrdiff_t>(flags.size()));
  }
}

TEST(VtkXml, OverlappingGhostPiecesAssembleWithoutDuplicateMarks) {
  // Three cells along x, two pieces that repeat the middle one, as VTK writes pieces with a ghost
  // level: each marks the points and the cell it repeats as duplicate (1); cell 2 is also hidden
  // (32) by the piece that owns it.
  const std::string doc =
      R"(<VTKFile type="ImageData"><ImageData WholeExtent="0 3 0 1 0 0" Origin="0 0 0" Spacing="1 1 1">
<Piece Extent="0 2 0 1 0 0">
<PointData Scalars="s"><DataArray type="Float32" Name="s" format="ascii">0 1 2 10 11 12</DataArray>
<DataArray type="UInt8" Name="vtkGhostType" format="ascii">0 0 1 0 0 1</DataArray></PointData>
<CellData><DataArray type="Int32" Name="c" format="ascii">100 101</DataArray>
<DataArray type="UInt8" Name="vtkGhostType" format="ascii">0 1</DataArray></CellData></Piece>
<Piece Extent="1 3 0 1 0 0">
<PointData Scalars="s"><DataArray type="Float32" Name="s" format="ascii">1 2 3 11 12 13</DataArray>
<DataArray type="UInt8" Name="vtkGhostType" format="ascii">1 0 0 1 0 0</DataArray></PointData>
<CellData><DataArray type="Int32" Name="c" format="ascii">101 102</DataArray>
<DataArray type="UInt8" Name="vtkGhostType" format="ascii">0 32</DataArray></CellData></Piece>
</ImageData></VTKFile>)";
  const auto img = std::get<ImageData>(read_string(doc, "ghost.vti"));
  EXPECT_EQ(img.dims, (Dims{4, 2, 1}));
  const auto s = img.point_data.get("s").values<float>();
  EXPECT_EQ(std::vector<float>(s.begin(), s.end()),
            (std::vector<float>{0, 1, 2, 3, 10, 11, 12, 13}));
  const auto c = img.cell_data.get("c").values<std::int32_t>();
  EXPECT_EQ(std::vector<std::int32_t>(c.begin(), c.end()),
            (std::vector<std::int32_t>{100, 101, 102}));
  const auto pg = img.point_data.get("vtkGhostType").values<std::uint8_t>();
  EXPECT_EQ(std::vector<std::uint8_t>(pg.begin(), pg.end()), std::vector<std::uint8_t>(8, 0));
  const auto cg = img.cell_data.get("vtkGhostType").values<std::uint8_t>();
  EXPECT_EQ(std::vector<std::uint8_t>(cg.begin(), cg.end()), (std::vector<std::uint8_t>{0, 0, 32}));
  EXPECT_EQ(img.point_data.active_name(AttributeRole::Scalars), "s");
  // info's summary of such a file is that of the assembled whole.
  const fs::path p = scratch("ghost") / "ghost.vti";
  spit(p, doc);
  const DatasetSummary sum = summarize_file(p);
  EXPECT_EQ(sum.points, 8u);
  EXPECT_EQ(sum.cells, 3u);
  const ArraySummary* g = nullptr;
  for (const ArraySummary& a : sum.cell_data.arrays) {
    if (a.name == "vtkGhostType") g = &a;
  }
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->ranges.component(0), (std::pair<double, double>{0, 32}));
}

// =============================================================================================
// Bad input: one test per class; each message names the file and the problem
// =============================================================================================

TEST(VtkXmlBad, MalformedXml) {
  expect_read_error("<VTKFile type=\"PolyData\"><PolyData><Piece></PolyData></VTKFile>", "bad.vtp",
                    {"malformed XML", "byte"});
  expect_read_error("", "empty.vtp", {"malformed XML"});
  expect_read_error("\x01\x02garbage", "binary.vtp", {"malformed XML"});
  expect_read_error(std::string(kTriangle).substr(0, 300), "cut.vtp", {"malformed XML"});
}

TEST(VtkXmlBad, WrongRoot) {
  expect_read_error("<?xml version=\"1.0\"?><html><body/></html>", "page.vtp",
                    {"root element is <html>", "VTKFile"});
}

TEST(VtkXmlBad, UnknownOrUnsupportedDatasetType) {
  expect_read_error(replace(kTriangle, "type=\"PolyData\"", "type=\"RectilinearGrid\""), "r.vtr",
                    {"RectilinearGrid", "not supported"});
  expect_read_error(replace(kTriangle, "type=\"PolyData\"", "type=\"PPolyData\""), "p.pvtp",
                    {"parallel"});
  expect_read_error(replace(kTriangle, "type=\"PolyData\"", ""), "nt.vtp",
                    {"missing attribute 'type'"});
  expect_read_error(replace(kTriangle, "type=\"PolyData\"", "type=\"UnstructuredGrid\""), "m.vtu",
                    {"missing <UnstructuredGrid> element"});
}

TEST(VtkXmlBad, UnknownCompressor) {
  // LZ4 and LZMA are known (an ascii file is read whatever its compressor); others are not.
  for (const char* c : {"vtkLZ4DataCompressor", "vtkLZMADataCompressor"}) {
    EXPECT_EQ(read_string(replace(kTriangle, "byte_order=",
                                  std::string("compressor=\"") + c + "\" byte_order=")),
              read_string(kTriangle));
  }
  expect_read_error(replace(kTriangle, "byte_order=", "compressor=\"vtkFancy\" byte_order="),
                    "fancy.vtp", {"unknown compressor 'vtkFancy'"});
}

TEST(VtkXmlBad, BadHeaderAttributes) {
  expect_read_error(replace(kTriangle, "LittleEndian", "MiddleEndian"), "bo.vtp",
                    {"byte_order='MiddleEndian'"});
  expect_read_error(replace(kTriangle, "byte_order=", "header_type=\"UInt16\" byte_order="),
                    "ht.vtp", {"header_type='UInt16'"});
  expect_read_error(replace(kTriangle, "version=\"0.1\"", "version=\"3.0\""), "v.vtp",
                    {"version 3.0"});
  expect_read_error(replace(kTriangle, "version=\"0.1\"", "version=\"abc\""), "v2.vtp",
                    {"version='abc'"});
}

TEST(VtkXmlBad, MissingAttributes) {
  expect_read_error(replace(kTriangle, "NumberOfPoints=\"3\"", ""), "np.vtp",
                    {"Piece 0", "missing attribute 'NumberOfPoints'"});
  expect_read_error(replace(kTriangle, "type=\"Float32\" Name=\"s\"", "Name=\"s\""), "t.vtp",
                    {"PointData/DataArray 's'", "missing attribute 'type'"});
  expect_read_error(replace(kTriangle, "Name=\"s\" format=\"ascii\"", "Name=\"s\""), "f.vtp",
                    {"PointData/DataArray 's'", "missing attribute 'format'"});
  expect_read_error(replace(kTriangle, "Name=\"s\" format=\"ascii\"", "Name=\"s\" format=\"hex\""),
                    "f2.vtp", {"format='hex'"});
  expect_read_error(R"(<VTKFile type="ImageData"><ImageData><Piece/></ImageData></VTKFile>)",
                    "we.vti", {"missing attribute 'WholeExtent'"});
  expect_read_error(replace(kTriangle, "Name=\"offsets\"", "Name=\"offs\""), "o.vtp",
                    {"Polys", "missing DataArray 'offsets'"});
  expect_read_error(replace(replace(kTriangle, "<Points>", "<!--"), "</Points>", "-->"), "pts.vtp",
                    {"missing <Points>"});
}

TEST(VtkXmlBad, UnknownScalarType) {
  expect_read_error(
      replace(kTriangle, "type=\"Float32\" Name=\"s\"", "type=\"Float16\" Name=\"s\""), "ty.vtp",
      {"PointData/DataArray 's'", "unknown type 'Float16'"});
  expect_read_error(replace(kTriangle, "<DataArray type=\"Float32\" NumberOfComponents=\"3\"",
                            "<DataArray type=\"String\" NumberOfComponents=\"3\""),
                    "sp.vtp", {"Points", "String is not allowed"});
}

TEST(VtkXmlBad, NegativeOrOverflowingExtents) {
  const std::string img =
      R"(<VTKFile type="ImageData"><ImageData WholeExtent="%E" Origin="0 0 0" Spacing="1 1 1"><Piece Extent="%E"/></ImageData></VTKFile>)";
  auto with = [&](const std::string& e) { return replace(replace(img, "%E", e), "%E", e); };
  expect_read_error(with("0 -3 0 1 0 1"), "neg.vti",
                    {"WholeExtent='0 -3 0 1 0 1'", "empty or negative"});
  expect_read_error(with("0 3 0 1 0"), "few.vti", {"WholeExtent", "6 numbers"});
  expect_read_error(with("0 4611686018427387905 0 1 0 1"), "big.vti", {"out of range"});
  expect_read_error(with("0 99999999999999999999 0 1 0 1"), "huge.vti", {"WholeExtent"});
  expect_read_error(with("0 2000000000 0 2000000000 0 2000000000"), "ovf.vti", {"overflow"});
  expect_read_error(with("-4611686018427387904 4611686018427387904 0 1 0 1"), "wide.vti",
                    {"overflow"});
}

TEST(VtkXmlBad, CountsTheDataDoesNotHold) {
  // ascii: too few / too many values (the points are read first)
  expect_read_error(replace(kTriangle, "NumberOfPoints=\"3\"", "NumberOfPoints=\"4\""), "np4.vtp",
                    {"Points/DataArray", "holds 9 values but the array needs 12"});
  expect_read_error(replace(kTriangle, "NumberOfPoints=\"3\"", "NumberOfPoints=\"999999999999\""),
                    "npbig.vtp", {"holds 9 values but the array needs 2999999999997"});
  expect_read_error(replace(kTriangle, "NumberOfPoints=\"3\"", "NumberOfPoints=\"2\""), "np2.vtp",
                    {"Points/DataArray", "holds more than the 6 values"});
  expect_read_error(replace(kTriangle, "NumberOfPolys=\"1\"", "NumberOfPolys=\"2\""), "nc.vtp",
                    {"offsets", "holds 1 values but the array needs 2"});
  // binary: header disagrees with NumberOfPoints
  Enc e;
  const std::vector<float> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::string bin =
      replace(kTriangle, R"(format="ascii">0 0 0 1 0 0 0 1 0<)",
              "format=\"binary\">" + inline_payload(raw_bytes(pts, false), e) + "<");
  EXPECT_NO_THROW((void)read_string(bin));
  expect_read_error(replace(bin, "NumberOfPoints=\"3\"", "NumberOfPoints=\"2\""), "b2.vtp",
                    {"Points/DataArray", "declares 36 bytes but the array needs 24"});
  // A huge NumberOfPoints with a header that agrees but data that is not there.
  std::string lie = replace(kTriangle, "NumberOfPoints=\"3\"", "NumberOfPoints=\"4000000000\"");
  lie = replace(lie, R"(format="ascii">0 0 0 1 0 0 0 1 0<)",
                "format=\"binary\">" + b64(word(48000000000ull, Enc{true}) + "abcd") + "<");
  lie = replace(lie, "byte_order=", "header_type=\"UInt64\" byte_order=");
  expect_read_error(lie, "lie.vtp", {"Points/DataArray", "truncated", "48000000000"});
  // field data with a NumberOfTuples the data does not hold
  expect_read_error(replace(kTriangle, "<PolyData>",
                            "<PolyData><FieldData><DataArray type=\"Int32\" Name=\"f\" "
                            "NumberOfTuples=\"3\" format=\"ascii\">1 2</DataArray></FieldData>"),
                    "fd.vtp", {"FieldData/DataArray 'f'", "holds 2 values"});
}

TEST(VtkXmlBad, Base64Garbage) {
  const std::string f =
      replace(kTriangle, R"(format="ascii">1 2 3<)", R"(format="binary">DAAA@AAA<)");
  expect_read_error(f, "g.vtp", {"PointData/DataArray 's'", "invalid character '@'"});
  expect_read_error(replace(kTriangle, R"(format="ascii">1 2 3<)", R"(format="binary">D===<)"),
                    "pad.vtp", {"misplaced '='"});
  expect_read_error(replace(kTriangle, R"(format="ascii">1 2 3<)", R"(format="binary">DA=A<)"),
                    "pad2.vtp", {"after '=' padding"});
  expect_read_error(replace(kTriangle, R"(format="ascii">1 2 3<)", R"(format="binary">DAAAAAAA<)"),
                    "short.vtp", {"truncated"});
  expect_read_error(replace(kTriangle, R"(format="ascii">1 2 3<)", R"(format="ascii">1 2 x3<)"),
                    "asc.vtp", {"ascii value 2 'x3' is not a valid Float32"});
  expect_read_error(replace(kTriangle, "Name=\"offsets\" format=\"ascii\">3",
                            "Name=\"offsets\" format=\"ascii\">3.5"),
                    "int.vtp", {"'3.5' is not a valid Int32"});
  expect_read_error(replace(kTriangle, "Name=\"offsets\" format=\"ascii\">3",
                            "Name=\"offsets\" format=\"ascii\">99999999999"),
                    "int2.vtp", {"not a valid Int32"});
}

namespace {
/// A raw-appended UnstructuredGrid (one tetra) written by isoforge, for appended-data damage.
std::string appended_tet(bool compress) {
  UnstructuredGrid ug;
  for (int i = 0; i < 4; ++i) ug.points.push_back({double(i == 1), double(i == 2), double(i == 3)});
  ug.add_cell(CellType::Tetra, {0, 1, 2, 3});
  ug.point_data.add(DataArray::from_vector<double>("d", 1, {1, 2, 3, 4}));
  return write_string(ug, VtkXmlEncoding::Appended, compress);
}
}  // namespace

TEST(VtkXmlBad, TruncatedAppendedData) {
  for (bool z : {false, true}) {
    const std::string f = appended_tet(z);
    const std::size_t start = f.find('_', f.find("<AppendedData")) + 1;
    expect_read_error(f.substr(0, start + 20), "cut.vtu", {"truncated"});
    expect_read_error(f.substr(0, start + 3), "cut2.vtu", {"truncated"});
    std::string no_us = f;
    no_us[start - 1] = '#';
    expect_read_error(no_us, "nous.vtu", {"expected '_'"});
    expect_read_error(f.substr(0, f.find("<AppendedData") + 15), "tag.vtu",
                      {"truncated <AppendedData> tag"});
  }
  std::string enc = replace(appended_tet(false), "encoding=\"raw\"", "encoding=\"hex\"");
  expect_read_error(enc, "enc.vtu", {"encoding='hex'"});
  std::string noapp = appended_tet(false);
  noapp = noapp.substr(0, noapp.find("<AppendedData")) + "</VTKFile>";
  expect_read_error(noapp, "noapp.vtu", {"no <AppendedData> section"});
}

TEST(VtkXmlBad, OffsetBeyondSection) {
  std::string f = appended_tet(false);
  f = replace(f, "offset=\"0\"", "offset=\"100000\"");
  expect_read_error(f, "off.vtu", {"offset 100000 is beyond the end"});
  std::string g = appended_tet(false);
  g = replace(g, "offset=\"0\"", "offset=\"-5\"");
  expect_read_error(g, "neg.vtu", {"offset=-5 is negative"});
}

TEST(VtkXmlBad, ZlibErrorsAndLyingBlockHeaders) {
  Enc e;
  e.z = true;
  e.block = 64;
  const std::vector<float> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  auto file = [&](const std::string& header, const std::string& body) {
    std::string f =
        replace(kTriangle, "byte_order=", "compressor=\"vtkZLibDataCompressor\" byte_order=");
    return replace(f, R"(format="ascii">0 0 0 1 0 0 0 1 0<)",
                   "format=\"binary\">" + b64(header) + b64(body) + "<");
  };
  const auto [h, b] = payload(raw_bytes(pts, false), e);
  EXPECT_NO_THROW((void)read_string(file(h, b)));
  // Corrupt deflate data (the checksum no longer matches).
  std::string bad = b;
  bad[bad.size() - 6] = static_cast<char>(bad[bad.size() - 6] ^ 0x5a);
  expect_read_error(file(h, bad), "corrupt.vtp",
                    {"Points/DataArray", "zlib error in compressed block 0"});
  std::string bad2 = b;
  bad2[0] = '\0';
  expect_read_error(file(h, bad2), "corrupt2.vtp", {"zlib error"});
  // A block header claiming 4 GB from a few bytes for an array of 9 floats.
  const std::string lie1 = word(1, e) + word(4000000000u, e) + word(0, e) + word(b.size(), e);
  expect_read_error(file(lie1, b), "lie1.vtp", {"4000000000", "needs 36"});
  // ... and with a NumberOfPoints that agrees with the lie: no allocation, a clear error.
  const std::string lie2 = word(1, e) + word(3999999996u, e) + word(0, e) + word(b.size(), e);
  expect_read_error(replace(file(lie2, b), "NumberOfPoints=\"3\"", "NumberOfPoints=\"333333333\""),
                    "lie2.vtp", {"more than zlib can produce"});
  // Block sizes that do not match the inflated data.
  const std::string lie3 = word(1, e) + word(40, e) + word(32, e) + word(b.size(), e);
  expect_read_error(file(lie3, b), "lie3.vtp", {"needs 36"});
  const std::string lie4 = word(2, e) + word(32, e) + word(4, e) + word(b.size(), e) + word(0, e);
  expect_read_error(file(lie4, b), "lie4.vtp", {"zlib error"});
  // Compressed sizes beyond the data.
  const std::string lie5 = word(1, e) + word(64, e) + word(36, e) + word(5000, e);
  expect_read_error(file(lie5, b), "lie5.vtp", {"truncated", "5000"});
  // A block count far beyond the data.
  const std::string lie6 = word(0xFFFFFFFFu, e) + word(16, e) + word(12, e);
  expect_read_error(file(lie6, b), "lie6.vtp", {"4294967295 blocks"});
  const std::string lie7 = word(1, e) + word(8, e) + word(36, e) + word(b.size(), e);
  expect_read_error(file(lie7, b), "lie7.vtp", {"last block size 36 exceeds the block size 8"});
}

TEST(VtkXmlBad, LargeCellListsNameTheFirstBadCell) {
  // 200 000 triangles and quads, checked in parallel ranges: the lowest bad cell is named,
  // whichever range finds its error first.
  const std::size_t cells = 200'000;
  const auto make = [&](std::size_t bad_cell, long long bad_id, std::size_t down_cell) {
    std::string conn, off;
    long long at = 0;
    for (std::size_t c = 0; c < cells; ++c) {
      const int size = c % 7 == 5 ? 4 : 3;
      for (int k = 0; k < size; ++k) {
        conn +=
            std::to_string(c == bad_cell && k == 1 ? bad_id : static_cast<long long>((c + k) % 3)) +
            ' ';
      }
      at += size;
      off += std::to_string(c == down_cell ? at - 5 : at) + ' ';  // before the cell's start
    }
    std::string f = replace(kTriangle, "NumberOfPolys=\"1\"",
                            "NumberOfPolys=\"" + std::to_string(cells) + "\"");
    f = replace(f, "Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2<",
                "Int64\" Name=\"connectivity\" format=\"ascii\">" + conn + "<");
    return replace(f, "Int32\" Name=\"offsets\" format=\"ascii\">3<",
                   "Int64\" Name=\"offsets\" format=\"ascii\">" + off + "<");
  };
  EXPECT_EQ(num_cells(read_string(make(cells, 0, cells), "good.vtp")), cells);
  expect_read_error(make(123'456, 3, cells), "big_oor.vtp",
                    {"'connectivity'", "cell 123456 refers to point 3, outside [0, 3)"});
  expect_read_error(make(199'999, -2, cells), "big_neg.vtp", {"cell 199999 refers to point -2"});
  expect_read_error(make(cells, 0, 150'001), "big_down.vtp",
                    {"'offsets'", "not monotonic: cell 150001 ends at"});
}

TEST(VtkXmlBad, OutOfRangeConnectivity) {
  expect_read_error(replace(kTriangle, ">0 1 2<", ">0 1 3<"), "oor.vtp",
                    {"Polys/DataArray 'connectivity'", "cell 0 refers to point 3, outside [0, 3)"});
  expect_read_error(replace(kTriangle, ">0 1 2<", ">0 -1 2<"), "neg.vtp", {"refers to point -1"});
  std::string u64 = replace(kTriangle, "<DataArray type=\"Int32\" Name=\"connectivity\"",
                            "<DataArray type=\"UInt64\" Name=\"connectivity\"");
  expect_read_error(replace(u64, ">0 1 2<", ">0 1 18446744073709551615<"), "u64.vtp",
                    {"out of range"});
  expect_read_error(replace(kTriangle, "<DataArray type=\"Int32\" Name=\"connectivity\"",
                            "<DataArray type=\"Float32\" Name=\"connectivity\""),
                    "fl.vtp", {"integer type"});
}

TEST(VtkXmlBad, BadCellTypes) {
  const std::string ug =
      R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Cells><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">4</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">%T</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>)";
  EXPECT_NO_THROW((void)read_string(replace(ug, "%T", "10")));
  expect_read_error(replace(ug, "%T", "99"), "t99.vtu",
                    {"Cells/DataArray 'types'", "unsupported cell type 99"});
  expect_read_error(replace(ug, "%T", "42"), "t42.vtu", {"polyhedron"});
  expect_read_error(replace(ug, "%T", "24"), "t24.vtu", {"only linear"});
  expect_read_error(replace(ug, "%T", "12"), "hex.vtu", {"cell 0 (hexahedron) has 4 points"});
  expect_read_error(replace(ug, "%T", "300"), "t300.vtu", {"not a valid UInt8"});
  expect_read_error(replace(replace(ug, "%T", "10"), "Name=\"types\"", "Name=\"kinds\""), "nt.vtu",
                    {"missing DataArray 'types'"});
}

TEST(VtkXmlBad, OffsetsNotMonotonic) {
  const std::string f = replace(
      replace(replace(kTriangle, "NumberOfPolys=\"1\"", "NumberOfPolys=\"2\""), ">3<", ">3 1<"),
      ">0 1 2<", ">0 1 2<");
  expect_read_error(f, "mono.vtp", {"Polys/DataArray 'offsets'", "not monotonic", "cell 1"});
  expect_read_error(replace(kTriangle, ">3<", ">-3<"), "negoff.vtp", {"not monotonic"});
}

TEST(VtkXmlBad, NonFinitePoints) {
  expect_read_error(replace(kTriangle, "0 0 0 1 0 0 0 1 0", "0 0 0 1 nan 0 0 1 0"), "nan.vtp",
                    {"Points", "point 1 has a non-finite coordinate"});
  expect_read_error(replace(kTriangle, "0 0 0 1 0 0 0 1 0", "0 0 0 1 0 0 0 1 -inf"), "inf.vtp",
                    {"point 2 has a non-finite coordinate"});
  expect_read_error(replace(kTriangle, "0 0 0 1 0 0 0 1 0", "0 0 0 1 0 0 0 1 1e99"), "ovf.vtp",
                    {"non-finite"});
}

TEST(VtkXmlBad, TupleCountsMismatch) {
  expect_read_error(replace(kTriangle, ">1 2 3<", ">1 2<"), "pd.vtp",
                    {"PointData/DataArray 's'", "holds 2 values but the array needs 3"});
  expect_read_error(replace(kTriangle, R"(Name="s" format="ascii">1 2 3)",
                            R"(Name="s" NumberOfTuples="4" format="ascii">1 2 3 4)"),
                    "nt.vtp", {"NumberOfTuples=4 but 3 tuples are needed"});
  expect_read_error(replace(kTriangle, "NumberOfComponents=\"3\"", "NumberOfComponents=\"2\""),
                    "pc.vtp", {"Points/DataArray", "has 2 components, expected 3"});
  expect_read_error(
      replace(kTriangle, R"(Name="s" format)", R"(Name="s" NumberOfComponents="0" format)"),
      "c0.vtp", {"NumberOfComponents=0"});
  expect_read_error(
      replace(
          kTriangle, "</PointData>",
          "<DataArray type=\"Float32\" Name=\"s\" format=\"ascii\">1 2 3</DataArray></PointData>"),
      "dup.vtp", {"duplicate array name 's'"});
}

TEST(VtkXmlBad, ImageDirectionAndPieces) {
  const std::string img =
      R"(<VTKFile type="ImageData"><ImageData WholeExtent="0 3 0 1 0 0" Origin="0 0 0" Spacing="1 1 1" %D>%P</ImageData></VTKFile>)";
  auto with = [&](const std::string& d, const std::string& p) {
    return replace(replace(img, "%D", d), "%P", p);
  };
  EXPECT_NO_THROW((void)read_string(with("", "<Piece Extent=\"0 3 0 1 0 0\"/>")));
  expect_read_error(with("Direction=\"0 1 0 1 0 0 0 0 1\"", "<Piece/>"), "dir.vti",
                    {"Direction", "axis-aligned"});
  expect_read_error(with("", "<Piece Extent=\"0 1 0 1 0 0\"/>"), "gap.vti",
                    {"cover 1 of the 3 cells", "tile"});
  expect_read_error(with("", "<Piece Extent=\"0 2 0 1 0 0\"/><Piece Extent=\"1 2 0 1 0 0\"/>"),
                    "overlap.vti", {"leave cells of WholeExtent '0 3 0 1 0 0' uncovered"});
  expect_read_error(with("", "<Piece Extent=\"0 5 0 1 0 0\"/>"), "outside.vti",
                    {"outside WholeExtent"});
  expect_read_error(with("", ""), "none.vti", {"no <Piece>"});
  expect_read_error(with("",
                         "<Piece Extent=\"0 1 0 1 0 0\"><PointData><DataArray type=\"Int8\" "
                         "Name=\"a\" format=\"ascii\">1 2 3 4</DataArray></PointData></Piece>"
                         "<Piece Extent=\"1 3 0 1 0 0\"/>"),
                    "arrays.vti", {"Piece 1", "PointData has 0 arrays but piece 0 has 1"});
  expect_read_error(replace(with("", "<Piece/>"), "Spacing=\"1 1 1\"", "Spacing=\"1 nan 1\""),
                    "sp.vti", {"finite"});
}

TEST(VtkXmlBad, ReadingAMissingFileNamesIt) {
  try {
    (void)read_vtk_xml(fs::path(ISOFORGE_TEST_TMP) / "does_not_exist.vtu");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does_not_exist.vtu"), std::string::npos);
  }
}

// =============================================================================================
// Robustness: truncation at many offsets and random damage never crash
// =============================================================================================

namespace {
std::vector<std::pair<std::string, std::string>> corpus() {
  std::vector<std::pair<std::string, std::string>> files;
  for (int kind = 0; kind < 4; ++kind) {
    const Dataset ds = rich(kind);
    for (int enc = 0; enc < 3; ++enc) {
      for (bool z : {false, true}) {
        files.emplace_back("k" + std::to_string(kind) + kEncodingName[enc] + (z ? "z" : ""),
                           write_string(ds, kEncodings[enc], z));
      }
    }
  }
  files.emplace_back("torso", slurp(fs::path(ISOFORGE_DATA_DIR) / "Torso.vtp"));
  files.emplace_back("triangle", kTriangle);
  return files;
}
}  // namespace

TEST(VtkXmlRobust, TruncatedFilesThrowOrParse) {
  for (const auto& [name, content] : corpus()) {
    const std::size_t step = std::max<std::size_t>(1, content.size() / 300);
    for (std::size_t len = 0; len < content.size(); len += step) {
      expect_error_or_ok(content.substr(0, len), name + " cut at " + std::to_string(len));
    }
    // Every byte near the start and the end.
    for (std::size_t len = 0; len < std::min<std::size_t>(content.size(), 200); ++len) {
      expect_error_or_ok(content.substr(0, content.size() - len),
                         name + " minus " + std::to_string(len));
    }
  }
}

TEST(VtkXmlRobust, RandomDamageThrowsOrParses) {
  std::mt19937 rng(12345);
  for (const auto& [name, content] : corpus()) {
    if (content.size() > 100000) continue;
    for (int iter = 0; iter < 150; ++iter) {
      std::string s = content;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < edits; ++k) {
        const std::size_t at = rng() % s.size();
        switch (rng() % 4) {
          case 0:
            s[at] = static_cast<char>(rng());
            break;
          case 1:
            s[at] = "0123456789-=<>_\"A/ "[rng() % 19];
            break;
          case 2:
            s.erase(at, 1 + rng() % 8);
            break;
          default:
            s.insert(at, std::string(1 + rng() % 4, static_cast<char>('0' + rng() % 10)));
            break;
        }
        if (s.empty()) s = "x";
      }
      expect_error_or_ok(s, name + " damage " + std::to_string(iter));
    }
  }
}

// The payload decoder on its own (io/detail/vtk_xml_block.hpp, what fuzz_vtk_xml_block drives):
// every encoding the reader supports decodes to the bytes written, and a lying header is an
// Error naming the name, the byte and the problem.
TEST(VtkXmlBlock, DecodesEveryEncodingAndRejectsLyingHeaders) {
  std::string data;
  for (int i = 0; i < 100; ++i) data += static_cast<char>(i * 7);
  for (const bool h64 : {false, true})
    for (const bool big : {false, true})
      for (const bool z : {false, true})
        for (const bool b64 : {false, true}) {
          Enc e;
          e.h64 = h64;
          e.big = big;
          e.z = z;
          e.separate = z;  // as VTK writes compressed base64 arrays
          const std::string text = b64 ? inline_payload(data, e) : appended_payload(data, e);
          io_detail::VtkXmlBlockFormat f{b64, z, h64, big};
          const auto bytes = std::as_bytes(std::span(text.data(), text.size()));
          const auto out = io_detail::decode_vtk_xml_block(bytes, f, std::nullopt, 4, "t.vtu");
          ASSERT_EQ(std::string(reinterpret_cast<const char*>(out.data()), out.size()), data)
              << h64 << big << z << b64;
          EXPECT_EQ(io_detail::decode_vtk_xml_block(bytes, f, 100, 4, "t.vtu").size(), 100u);
          EXPECT_THROW((void)io_detail::decode_vtk_xml_block(bytes, f, 96, 4, "t.vtu"), Error);
          EXPECT_THROW((void)io_detail::decode_vtk_xml_block(bytes, f, std::nullopt, 8, "t.vtu"),
                       Error);  // 100 bytes are not tuples of 8
        }
  // A header claiming more than follows.
  const std::string lying = word(1000, Enc{}) + data;
  try {
    (void)io_detail::decode_vtk_xml_block(std::as_bytes(std::span(lying.data(), lying.size())),
                                          {false, false, false, false}, std::nullopt, 1, "t.vtu");
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.vtu: byte 4: DataArray: truncated data: the header "
                                         "declares 1000 bytes"),
              std::string::npos)
        << e.what();
  }
}

// =============================================================================================
// Compressors: zlib (written with libdeflate), LZ4 (read and written), LZMA (read); blocks
// (de)compressed in parallel
// =============================================================================================

namespace {

const char* kCompressorName[] = {"none", "zlib", "lz4"};

VtkXmlWriteOptions codec_options(VtkXmlEncoding enc, int codec, int level) {
  VtkXmlWriteOptions o{enc, codec > 0};
  o.compressor = codec == 2 ? VtkXmlCompressor::Lz4 : VtkXmlCompressor::Zlib;
  o.level = level;
  return o;
}

std::string write_codec(const Dataset& ds, VtkXmlEncoding enc, int codec, int level = 0) {
  std::ostringstream out;
  write_vtk_xml(ds, out, codec_options(enc, codec, level));
  return out.str();
}

/// A smooth field and noise over a 64 x 48 x 40 image: 123k points, so the arrays span several
/// 256 KiB blocks (and several tasks of the parallel codecs).
ImageData blocky_image() {
  ImageData img;
  img.dims = {64, 48, 40};
  img.spacing = {0.5, 0.25, 1};
  DataArray f("smooth", ScalarType::Float32, 1, img.num_points());
  auto fv = f.values<float>();
  for (std::size_t i = 0; i < fv.size(); ++i) fv[i] = std::sin(0.001f * static_cast<float>(i));
  img.point_data.add(std::move(f), AttributeRole::Scalars);
  DataArray n("noise", ScalarType::Float64, 3, img.num_points());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (auto& v : n.values<double>()) v = u(rng);
  img.point_data.add(std::move(n));
  return img;
}

/// The header words and blocks of the first appended array of a file written with UInt64
/// headers: {block sizes, compressed blocks}.
std::pair<std::vector<std::uint64_t>, std::vector<std::string>> first_array_blocks(
    const std::string& file) {
  std::size_t at = file.find('_', file.find("<AppendedData")) + 1;
  auto word64 = [&] {
    std::uint64_t v;
    std::memcpy(&v, file.data() + at, 8);
    at += 8;
    return v;
  };
  const std::uint64_t nb = word64(), block = word64(), last = word64();
  std::vector<std::uint64_t> sizes, csizes;
  for (std::uint64_t b = 0; b < nb; ++b) {
    sizes.push_back(b + 1 == nb && last ? last : block);
    csizes.push_back(word64());
  }
  std::vector<std::string> blocks;
  for (const std::uint64_t c : csizes) {
    blocks.push_back(file.substr(at, c));
    at += c;
  }
  return {sizes, blocks};
}

}  // namespace

class VtkXmlCompressors : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(VtkXmlCompressors, RoundTripAtEveryLevel) {
  const auto [kind, enc, codec] = GetParam();
  const Dataset ds = rich(kind);
  const std::string ext(vtk_xml_extension(ds));
  const int max_level = codec == 0 ? 0 : 12;
  for (const int level : {0, 1, 6, max_level}) {
    SCOPED_TRACE(level);
    const std::string text = write_codec(ds, kEncodings[enc], codec, codec ? level : 0);
    const char* attribute = codec == 2   ? "compressor=\"vtkLZ4DataCompressor\""
                            : codec == 1 ? "compressor=\"vtkZLibDataCompressor\""
                                         : "compressor=";
    EXPECT_EQ(text.find(attribute) != std::string::npos, codec != 0);
    EXPECT_EQ(read_string(text, "rt" + ext), ds);
  }
}

std::string compressor_test_name(const ::testing::TestParamInfo<std::tuple<int, int, int>>& info) {
  static const char* kinds[] = {"image", "structured", "poly", "ugrid"};
  return std::string(kinds[std::get<0>(info.param)]) + "_" +
         kEncodingName[std::get<1>(info.param)] + "_" + kCompressorName[std::get<2>(info.param)];
}

INSTANTIATE_TEST_SUITE_P(AllTypes, VtkXmlCompressors,
                         ::testing::Combine(::testing::Range(0, 4), ::testing::Values(1, 2),
                                            ::testing::Range(0, 3)),
                         compressor_test_name);

TEST(VtkXmlCompressors, ManyBlocksSameBytesForAnyThreadCount) {
  const ImageData img = blocky_image();
  for (const int codec : {1, 2}) {
    for (const VtkXmlEncoding enc : {VtkXmlEncoding::Appended, VtkXmlEncoding::Base64}) {
      SCOPED_TRACE(std::to_string(codec) + kEncodingName[static_cast<int>(enc)]);
      std::string one, many;
      {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = write_codec(img, enc, codec);
      }
      {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
        many = write_codec(img, enc, codec);
      }
      EXPECT_EQ(one, many);
      EXPECT_EQ(read_string(many, "many.vti"), Dataset(img));
      {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        EXPECT_EQ(read_string(many, "many.vti"), Dataset(img));
      }
      // zlib: smaller than the raw arrays (the smooth field compresses; LZ4 does not shrink the
      // random doubles and may grow them a little, which is why it is not checked).
      if (codec == 1) {
        EXPECT_LT(many.size(), write_codec(img, enc, 0).size());
      }
    }
  }
}

// The writer's block size (docs/algorithms/vtk_xml_io.md: 256 KiB, chosen from the measured
// size curve; VTK's readers take any).
constexpr std::size_t kWriterBlock = std::size_t{1} << 18;

TEST(VtkXmlCompressors, ZlibBlocksAreZlibStreams) {
  // What vtkZLibDataCompressor reads: every block inflates with zlib's uncompress() to exactly
  // its size (123k floats: 481 KiB in 2 blocks of 256 KiB, the last shorter), at every level.
  const ImageData img = blocky_image();
  const std::size_t n = img.num_points() * sizeof(float);
  for (const int level : {1, 6, 9, 12}) {
    const auto [sizes, blocks] = first_array_blocks(write_codec(img, VtkXmlEncoding::Appended, 1, level));
    ASSERT_EQ(blocks.size(), (n + kWriterBlock - 1) / kWriterBlock);
    ASSERT_EQ(sizes[0], kWriterBlock);
    std::string all;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      std::string out(sizes[b], '\0');
      uLongf got = static_cast<uLongf>(out.size());
      ASSERT_EQ(::uncompress(reinterpret_cast<Bytef*>(out.data()), &got,
                             reinterpret_cast<const Bytef*>(blocks[b].data()), blocks[b].size()),
                Z_OK)
          << "level " << level << " block " << b;
      EXPECT_EQ(got, sizes[b]);
      all += out;
    }
    EXPECT_EQ(all, std::string(reinterpret_cast<const char*>(
                                   img.point_data.get("smooth").bytes()), n));
  }
  // Higher levels are no larger (the smooth field: 12 well below 1).
  const auto size_at = [&](int level) {
    std::size_t t = 0;
    for (const auto& b : first_array_blocks(write_codec(img, VtkXmlEncoding::Appended, 1, level)).second)
      t += b.size();
    return t;
  };
  EXPECT_LT(size_at(12), size_at(1));
}

TEST(VtkXmlCompressors, Lz4BlocksAreLz4Blocks) {
  const ImageData img = blocky_image();
  for (const int level : {1, 2, 12}) {
    const auto [sizes, blocks] = first_array_blocks(write_codec(img, VtkXmlEncoding::Appended, 2, level));
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      std::string out(sizes[b], '\0');
      ASSERT_EQ(LZ4_decompress_safe(blocks[b].data(), out.data(), static_cast<int>(blocks[b].size()),
                                    static_cast<int>(out.size())),
                static_cast<int>(sizes[b]))
          << "level " << level << " block " << b;
      EXPECT_EQ(out, std::string(reinterpret_cast<const char*>(img.point_data.get("smooth").bytes()) +
                                     b * kWriterBlock,
                                 sizes[b]));
    }
  }
}

TEST(VtkXmlCompressors, LevelOutOfRange) {
  const Dataset ds = rich(2);
  for (const int codec : {1, 2}) {
    for (const int level : {-1, 13}) {
      try {
        (void)write_codec(ds, VtkXmlEncoding::Appended, codec, level);
        ADD_FAILURE() << codec << " " << level;
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("level " + std::to_string(level) + " is out of range 1-12"),
                  std::string::npos)
            << e.what();
      }
    }
  }
  // Without compression the level is not used.
  EXPECT_NO_THROW((void)write_codec(ds, VtkXmlEncoding::Appended, 0, 99));
}

namespace {

/// kTriangle's points (9 floats, 36 bytes) as `codec` blocks of 16 bytes (16, 16, 4) inline in
/// base64, with UInt32 headers. `edit(b, block)` may change a compressed block first.
std::string codec_triangle(const char* compressor,
                           const std::function<std::string(const std::string&)>& compress,
                           const std::function<void(std::size_t, std::string&)>& edit = {}) {
  const std::vector<float> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::string raw = raw_bytes(pts, false);
  Enc e;
  std::string header = word(3, e) + word(16, e) + word(4, e), body;
  for (std::size_t b = 0; b < 3; ++b) {
    std::string c = compress(raw.substr(b * 16, 16));
    if (edit) edit(b, c);
    header += word(c.size(), e);
    body += c;
  }
  std::string f =
      replace(kTriangle, "byte_order=", std::string("compressor=\"") + compressor + "\" byte_order=");
  return replace(f, R"(format="ascii">0 0 0 1 0 0 0 1 0<)",
                 "format=\"binary\">" + b64(header) + b64(body) + "<");
}

std::string lzma_compress(const std::string& raw) {
  std::string out(lzma_stream_buffer_bound(raw.size()), '\0');
  std::size_t pos = 0;
  EXPECT_EQ(lzma_easy_buffer_encode(6, LZMA_CHECK_CRC32, nullptr,
                                    reinterpret_cast<const std::uint8_t*>(raw.data()), raw.size(),
                                    reinterpret_cast<std::uint8_t*>(out.data()), &pos, out.size()),
            LZMA_OK);
  out.resize(pos);
  return out;
}

std::string lz4_compress(const std::string& raw) {
  std::string out(static_cast<std::size_t>(LZ4_compressBound(static_cast<int>(raw.size()))), '\0');
  out.resize(static_cast<std::size_t>(
      LZ4_compress_default(raw.data(), out.data(), static_cast<int>(raw.size()),
                           static_cast<int>(out.size()))));
  return out;
}

std::string zlib_compress(const std::string& raw) {
  std::string out(compressBound(raw.size()), '\0');
  uLongf n = out.size();
  EXPECT_EQ(::compress(reinterpret_cast<Bytef*>(out.data()), &n,
                       reinterpret_cast<const Bytef*>(raw.data()), raw.size()),
            Z_OK);
  out.resize(n);
  return out;
}

}  // namespace

TEST(VtkXmlCompressors, CorruptAndTruncatedBlocksOfEveryCodec) {
  struct Codec {
    const char* vtk;
    const char* label;
    std::function<std::string(const std::string&)> compress;
  };
  const Codec codecs[] = {{"vtkZLibDataCompressor", "zlib", zlib_compress},
                          {"vtkLZ4DataCompressor", "LZ4", lz4_compress},
                          {"vtkLZMADataCompressor", "LZMA", lzma_compress}};
  const Dataset good = read_string(kTriangle);
  for (const Codec& c : codecs) {
    SCOPED_TRACE(c.label);
    EXPECT_EQ(read_string(codec_triangle(c.vtk, c.compress)), good);
    const std::string error = std::string(c.label) + " error in compressed block 1 of 3";
    // Block 1 overwritten with 0xFF bytes: no codec accepts it (zlib: a bad header; LZ4: a
    // literal run longer than the block; LZMA: no .xz magic).
    expect_read_error(codec_triangle(c.vtk, c.compress,
                                     [](std::size_t b, std::string& s) {
                                       if (b == 1) s.assign(s.size(), '\xff');
                                     }),
                      "ff.vtp", {"Points/DataArray", error});
    // Block 1 cut short by one byte.
    expect_read_error(codec_triangle(c.vtk, c.compress,
                                     [](std::size_t b, std::string& s) {
                                       if (b == 1) s.pop_back();
                                     }),
                      "short.vtp", {"Points/DataArray", error});
    // Block 2 holds 16 bytes where the header says 4: more than the header says.
    expect_read_error(codec_triangle(c.vtk, c.compress,
                                     [&](std::size_t b, std::string& s) {
                                       if (b == 2) s = c.compress(std::string(16, 'x'));
                                     }),
                      "long.vtp", {"compressed block 2 of 3"});
  }
  // LZMA data checks its CRC32: one flipped byte in the middle is caught.
  expect_read_error(codec_triangle("vtkLZMADataCompressor", lzma_compress,
                                   [](std::size_t b, std::string& s) {
                                     if (b == 0) s[s.size() / 2] ^= 0x20;
                                   }),
                    "flip.vtp", {"LZMA error in compressed block 0 of 3"});
}

TEST(VtkXmlCompressors, TruncatedFileOfEveryWrittenCodec) {
  const ImageData img = blocky_image();
  for (const int codec : {1, 2}) {
    const std::string text = write_codec(img, VtkXmlEncoding::Appended, codec);
    expect_read_error(text.substr(0, text.size() / 2), "half.vti", {"truncated", "DataArray"});
  }
}

TEST(VtkXmlCompressors, BlockDecoderTakesEveryCodec) {
  const std::string raw(100, 'a');
  Enc e;
  for (const auto& [codec, compress] :
       std::vector<std::pair<io_detail::BlockCodec, std::function<std::string(const std::string&)>>>{
           {io_detail::BlockCodec::Zlib, zlib_compress},
           {io_detail::BlockCodec::Lz4, lz4_compress},
           {io_detail::BlockCodec::Lzma, lzma_compress}}) {
    const std::string c = compress(raw);
    const std::string text = word(1, e) + word(100, e) + word(0, e) + word(c.size(), e) + c;
    io_detail::VtkXmlBlockFormat f{false, true, false, false, codec};
    const auto out = io_detail::decode_vtk_xml_block(std::as_bytes(std::span(text.data(), text.size())),
                                                     f, 100, 1, "t.vtu");
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(out.data()), out.size()), raw);
  }
}

namespace {

/// An output stream that cannot seek (a pipe, a socket): the writer keeps the compressed blocks
/// until the XML is done instead of filling places in afterwards.
class UnseekableBuf : public std::streambuf {
 public:
  std::string text;

 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) text += static_cast<char>(c);
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    text.append(s, static_cast<std::size_t>(n));
    return n;
  }
};

}  // namespace

// Compressed appended data is streamed to a seekable output slice by slice (offsets and block
// sizes filled in afterwards): the same bytes as the buffered path, up to the padding of the
// offset attributes, for arrays of several slices with a short last block.
TEST(VtkXmlCompressors, StreamedAndBufferedWritesHoldTheSameBytes) {
  ImageData img;
  img.dims = {128, 128, 41};  // 671k points: 16 MB of Float64 vectors, 5 slices of 4 MiB
  DataArray v("v", ScalarType::Float64, 3, img.num_points());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (auto& x : v.values<double>()) x = std::round(u(rng) * 100) / 100;
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  DataArray s("s", ScalarType::Float32, 1, img.num_points());
  auto sv = s.values<float>();
  for (std::size_t i = 0; i < sv.size(); ++i) sv[i] = static_cast<float>(i % 1000) * 0.5f;
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  for (const int codec : {1, 2}) {
    SCOPED_TRACE(codec);
    const VtkXmlWriteOptions o = codec_options(VtkXmlEncoding::Appended, codec, 0);
    std::ostringstream seekable;
    write_vtk_xml(img, seekable, o);
    UnseekableBuf buf;
    std::ostream pipe(&buf);
    write_vtk_xml(img, pipe, o);
    std::string streamed = seekable.str();
    const std::size_t xml_end = streamed.find("<AppendedData");
    ASSERT_NE(xml_end, std::string::npos);
    // The offsets stand in padded fields: `offset="N"` and spaces before the tag's end.
    EXPECT_NE(streamed.substr(0, xml_end).find("\"                 "), std::string::npos);
    std::string xml = streamed.substr(0, xml_end);
    for (std::size_t p; (p = xml.find(" /")) != std::string::npos;) xml.erase(p, 1);
    EXPECT_EQ(xml + streamed.substr(xml_end), buf.text);
    EXPECT_EQ(read_string(streamed, "streamed.vti"), Dataset(img));
    EXPECT_EQ(read_string(buf.text, "buffered.vti"), Dataset(img));
  }
}

// Cell ids are written as Int32 when they fit (Auto, Int32) or as Int64: in every encoding, with
// and without compression, streamed and buffered, over several slices and pieces (1.2M ids, a
// short last one); each file reads back as the dataset.
TEST(VtkXmlWrite, CellIdsAsInt32OrInt64InEveryEncoding) {
  PolyData pd;
  const std::size_t side = 300, tris = 2 * (side - 1) * (side - 1) + 1;  // 179k triangles...
  pd.points = Points(0, ScalarType::Float32);
  for (std::size_t j = 0; j < side; ++j) {
    for (std::size_t i = 0; i < side; ++i) {
      pd.points.push_back({static_cast<double>(i), static_cast<double>(j), 0.0});
    }
  }
  for (std::size_t j = 0; j + 1 < side; ++j) {
    for (std::size_t i = 0; i + 1 < side; ++i) {
      const auto a = static_cast<Index>(j * side + i);
      const auto n = static_cast<Index>(side);
      pd.polys.add({a, a + 1, a + n + 1});
      pd.polys.add({a, a + n + 1, a + n});
    }
  }
  pd.polys.add({0, static_cast<Index>(side * side - 1), static_cast<Index>(side - 1)});
  // ... and 1.2M ids in lines of 5 points: the connectivity spans two slices of 4 MiB.
  for (std::size_t c = 0; c < 190'000; ++c) {
    const auto a = static_cast<Index>((c * 7919) % (side * side - 5));
    pd.lines.add({a, a + 1, a + 2, a + 3, a + 4});
  }
  ASSERT_EQ(pd.polys.size(), tris);
  const std::size_t ids = pd.polys.connectivity().size() + pd.polys.size() +
                          pd.lines.connectivity().size() + pd.lines.size();
  const Dataset ds(pd);
  for (const VtkXmlEncoding enc :
       {VtkXmlEncoding::Ascii, VtkXmlEncoding::Base64, VtkXmlEncoding::Appended}) {
    for (const int codec : {0, 1, 2}) {
      if (enc == VtkXmlEncoding::Ascii && codec > 0) continue;
      std::map<VtkXmlIdType, std::size_t> sizes;
      for (const VtkXmlIdType type :
           {VtkXmlIdType::Auto, VtkXmlIdType::Int32, VtkXmlIdType::Int64}) {
        SCOPED_TRACE(testing::Message() << "encoding " << static_cast<int>(enc) << " codec "
                                        << codec << " type " << static_cast<int>(type));
        VtkXmlWriteOptions o = codec_options(enc, codec, 0);
        o.id_type = type;
        std::ostringstream seekable;
        write_vtk_xml(ds, seekable, o);
        UnseekableBuf buf;
        std::ostream pipe(&buf);
        write_vtk_xml(ds, pipe, o);
        const std::string text = seekable.str();
        const char* want = type == VtkXmlIdType::Int64 ? "Int64" : "Int32";
        const char* other = type == VtkXmlIdType::Int64 ? "Int32" : "Int64";
        for (const char* name : {"connectivity", "offsets"}) {
          EXPECT_NE(text.find("type=\"" + std::string(want) + "\" Name=\"" + name + "\""),
                    std::string::npos);
          EXPECT_EQ(text.find("type=\"" + std::string(other) + "\" Name=\"" + name + "\""),
                    std::string::npos);
        }
        EXPECT_EQ(read_string(text, "seekable.vtp"), ds);
        EXPECT_EQ(read_string(buf.text, "pipe.vtp"), ds);
        sizes[type] = buf.text.size() - buf.text.find("<AppendedData");  // all if inline
      }
      EXPECT_EQ(sizes[VtkXmlIdType::Auto], sizes[VtkXmlIdType::Int32]);
      if (enc == VtkXmlEncoding::Ascii) {
        EXPECT_EQ(sizes[VtkXmlIdType::Int32], sizes[VtkXmlIdType::Int64]);  // the same digits
      } else if (enc == VtkXmlEncoding::Appended && codec == 0) {
        // Raw: exactly 4 bytes less per id and per offset.
        EXPECT_EQ(sizes[VtkXmlIdType::Int64] - sizes[VtkXmlIdType::Int32], 4 * ids);
      } else {
        EXPECT_LT(sizes[VtkXmlIdType::Int32], sizes[VtkXmlIdType::Int64]);
      }
    }
  }
}

// ASCII arrays of 2^16 values or more are parsed in parallel: the same values, and a bad value
// or a wrong count reported as the serial parser reports it.
TEST(VtkXmlAscii, BigArraysParseInParallelWithTheSameErrors) {
  ImageData img;
  img.dims = {80, 60, 30};  // 144k points
  DataArray f("f", ScalarType::Float32, 1, img.num_points());
  auto fv = f.values<float>();
  for (std::size_t i = 0; i < fv.size(); ++i) fv[i] = static_cast<float>(i % 977) * 0.125f - 3.0f;
  img.point_data.add(std::move(f), AttributeRole::Scalars);
  DataArray k("k", ScalarType::Int32, 2, img.num_points());
  auto kv = k.values<std::int32_t>();
  for (std::size_t i = 0; i < kv.size(); ++i) kv[i] = static_cast<std::int32_t>(i) - 100000;
  img.point_data.add(std::move(k));
  VtkXmlWriteOptions o;
  o.encoding = VtkXmlEncoding::Ascii;
  std::ostringstream out;
  write_vtk_xml(img, out, o);
  const std::string text = out.str();
  EXPECT_EQ(read_string(text, "big.vti"), Dataset(img));

  const std::string value = " 99000 ";  // a value of 'k', far into the array (value 199000)
  const std::size_t at = text.find(value);
  ASSERT_NE(at, std::string::npos);
  const auto expect_error = [&](const std::string& replacement, const std::string& message) {
    std::string bad = text;
    bad.replace(at, value.size(), replacement);
    try {
      (void)read_string(bad, "bad.vti");
      ADD_FAILURE() << "no error for " << replacement;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  expect_error(" 99x00 ", "ascii value 199000 '99x00' is not a valid Int32");
  expect_error(" 99000 1 ", "ascii data holds more than the 288000 values");
}
