// summarize_file: the streaming summaries (VTK XML, VTK legacy, PLY, OFF, NRRD, PLOT3D, glTF)
// against the summary of the dataset read whole, on every encoding, on arrays larger than one
// streamed piece (tuples straddling pieces), and with the same errors as the readers.

#include "support/scratch.hpp"

#include <gtest/gtest.h>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "isoforge/core/summary.hpp"
#include "isoforge/io/gltf.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/ply.hpp"

using namespace isoforge;
namespace fs = std::filesystem;

namespace {

// A file in this test's scratch directory.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(ISOFORGE_TEST_TMP) / "summary" / isoforge::test::current_test_id();
  fs::create_directories(dir);
  fs::remove_all(dir / name);
  return dir / name;
}

void expect_same_attributes(const AttributesSummary& a, const AttributesSummary& b) {
  ASSERT_EQ(a.arrays.size(), b.arrays.size());
  EXPECT_EQ(a.active, b.active);
  for (std::size_t i = 0; i < a.arrays.size(); ++i) {
    const ArraySummary& x = a.arrays[i];
    const ArraySummary& y = b.arrays[i];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.components, y.components);
    EXPECT_EQ(x.tuples, y.tuples);
    for (int c = 0; c < x.components; ++c) EXPECT_EQ(x.ranges.component(c), y.ranges.component(c));
    if (x.components > 1) {
      EXPECT_EQ(x.ranges.magnitude(), y.ranges.magnitude());
    }
  }
}

/// The streamed summary of `path` equals the summary of the dataset read whole.
void expect_streamed_as_read(const fs::path& path, const ReadOptions& options = {}) {
  SCOPED_TRACE(path.string());
  const DatasetSummary s = summarize_file(path, options);
  const DatasetSummary r = summarize(read(path, options));
  EXPECT_TRUE(s.streamed);
  EXPECT_EQ(s.kind, r.kind);
  EXPECT_EQ(s.dims, r.dims);
  EXPECT_EQ(s.origin, r.origin);
  EXPECT_EQ(s.spacing, r.spacing);
  EXPECT_EQ(s.points, r.points);
  EXPECT_EQ(s.cells, r.cells);
  EXPECT_EQ(s.cell_types, r.cell_types);
  EXPECT_EQ(s.bounds.min, r.bounds.min);
  EXPECT_EQ(s.bounds.max, r.bounds.max);
  expect_same_attributes(s.point_data, r.point_data);
  expect_same_attributes(s.cell_data, r.cell_data);
  expect_same_attributes(s.field_data, r.field_data);
}

/// `read` and `summarize_file` reject `path` with the same message.
void expect_same_error(const fs::path& path, const ReadOptions& options = {}) {
  std::string from_read, from_summary;
  try {
    (void)read(path, options);
  } catch (const Error& e) {
    from_read = e.what();
  }
  try {
    (void)summarize_file(path, options);
  } catch (const Error& e) {
    from_summary = e.what();
  }
  EXPECT_FALSE(from_read.empty());
  EXPECT_EQ(from_summary, from_read);
}

std::vector<WriteOptions> xml_encodings() {
  std::vector<WriteOptions> out(4);
  out[0].xml_compressor = VtkXmlCompressor::Zlib;
  out[1].xml_compressor = VtkXmlCompressor::Lz4;
  out[2].compress = false;
  out[3].binary = false;
  return out;
}

// 9 x 7 x 5 points; a scalar with a NaN, a 3-vector, an int cell array.
ImageData small_image() {
  ImageData img;
  img.dims = {9, 7, 5};
  img.origin = {-1, 2, 0.5};
  img.spacing = {0.5, 0.25, 2};
  const std::size_t n = 9 * 7 * 5;
  DataArray s("s", ScalarType::Float32, 1, n);
  DataArray v("v", ScalarType::Float64, 3, n);
  for (std::size_t i = 0; i < n; ++i) {
    s.set(i, 0, std::sin(0.1 * static_cast<double>(i)));
    for (int c = 0; c < 3; ++c) v.set(i, c, static_cast<double>(i % (7 + c)) - 3.0);
  }
  s.set(17, 0, std::numeric_limits<double>::quiet_NaN());
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  DataArray id("id", ScalarType::Int32, 1, 8 * 6 * 4);
  for (std::size_t i = 0; i < id.tuples(); ++i) id.set(i, 0, static_cast<double>(i) - 50);
  img.cell_data.add(std::move(id));
  DataArray f("f", ScalarType::UInt16, 2, 3);
  for (std::size_t i = 0; i < 6; ++i) f.set(i / 2, static_cast<int>(i % 2), static_cast<double>(7 * i));
  img.field_data.add(std::move(f));
  return img;
}

// 4 x 3 x 2 points, sheared; an int8 scalar.
StructuredGrid small_grid() {
  StructuredGrid sg;
  sg.dims = {4, 3, 2};
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) sg.points.push_back({i + 0.1 * j, j * 2.0, k - 0.5 * i});
  DataArray q("q", ScalarType::Int8, 1, 24);
  for (std::size_t i = 0; i < 24; ++i) q.set(i, 0, static_cast<double>(i) - 12);
  sg.point_data.add(std::move(q), AttributeRole::Scalars);
  return sg;
}

PolyData mixed_polydata() {
  PolyData pd;
  for (int i = 0; i < 12; ++i) pd.points.push_back({std::cos(i), std::sin(i), 0.1 * i});
  pd.verts.add({0});
  pd.verts.add({1, 2, 3});
  pd.lines.add({0, 1});
  pd.lines.add({2, 3, 4, 5});
  pd.polys.add({0, 1, 2});
  pd.polys.add({3, 4, 5, 6});
  pd.polys.add({6, 7, 8, 9, 10});
  pd.polys.add({1, 5, 9});
  pd.strips.add({2, 4, 6, 8, 10});
  DataArray c("cell", ScalarType::Int64, 1, 9);
  for (std::size_t i = 0; i < 9; ++i) c.set(i, 0, -static_cast<double>(i * i));
  pd.cell_data.add(std::move(c));
  DataArray t("t", ScalarType::Float32, 2, 12);
  for (std::size_t i = 0; i < 24; ++i) t.set(i / 2, static_cast<int>(i % 2), 0.25 * static_cast<double>(i));
  pd.point_data.add(std::move(t), AttributeRole::TCoords);
  return pd;
}

UnstructuredGrid mixed_grid() {
  UnstructuredGrid ug;
  for (int i = 0; i < 8; ++i) ug.points.push_back({double(i & 1), double((i >> 1) & 1), double(i >> 2)});
  ug.points.push_back({0.5, 0.5, 2});
  ug.add_cell(CellType::Hexahedron, {0, 1, 3, 2, 4, 5, 7, 6});
  ug.add_cell(CellType::Pyramid, {4, 5, 7, 6, 8});
  ug.add_cell(CellType::Tetra, {0, 1, 2, 4});
  ug.add_cell(CellType::Tetra, {1, 3, 2, 7});
  ug.add_cell(CellType::Triangle, {0, 1, 2});
  DataArray p("p", ScalarType::Float32, 1, 9);
  for (std::size_t i = 0; i < 9; ++i) p.set(i, 0, static_cast<double>(i) * 1.5);
  ug.point_data.add(std::move(p));
  return ug;
}

}  // namespace

TEST(Summary, OfADatasetCountsCellTypesAndRangesIgnoringNaN) {
  const DatasetSummary s = summarize(small_image());
  EXPECT_EQ(s.points, 315u);
  EXPECT_EQ(s.cells, 192u);
  EXPECT_EQ(s.cell_types.at(CellType::Voxel), 192u);
  ASSERT_EQ(s.point_data.arrays.size(), 2u);
  const auto [lo, hi] = s.point_data.arrays[0].ranges.component(0);
  EXPECT_TRUE(std::isfinite(lo) && std::isfinite(hi));  // the NaN is skipped
  EXPECT_EQ(s.point_data.arrays[1].ranges.component(2), std::make_pair(-3.0, 5.0));
  EXPECT_EQ(s.point_data.arrays[1].ranges.magnitude().first, 0.0);  // tuple 3: (0, 0, 0)
  EXPECT_EQ(s.point_data.arrays[1].ranges.magnitude().second, std::sqrt(9.0 + 16.0 + 25.0));
  const DatasetSummary p = summarize(mixed_polydata());
  EXPECT_EQ(p.cell_types.at(CellType::Vertex), 1u);
  EXPECT_EQ(p.cell_types.at(CellType::PolyVertex), 1u);
  EXPECT_EQ(p.cell_types.at(CellType::Line), 1u);
  EXPECT_EQ(p.cell_types.at(CellType::PolyLine), 1u);
  EXPECT_EQ(p.cell_types.at(CellType::Triangle), 2u);
  EXPECT_EQ(p.cell_types.at(CellType::Quad), 1u);
  EXPECT_EQ(p.cell_types.at(CellType::Polygon), 1u);
  EXPECT_EQ(p.cell_types.at(CellType::TriangleStrip), 1u);
}

TEST(Summary, VtkXmlStreamedAsReadOnEveryEncodingAndDatasetType) {
  const StructuredGrid sg = small_grid();
  const std::vector<std::pair<std::string, Dataset>> cases = {
      {"image.vti", small_image()},
      {"grid.vts", sg},
      {"poly.vtp", mixed_polydata()},
      {"cells.vtu", mixed_grid()}};
  int e = 0;
  for (const WriteOptions& o : xml_encodings()) {
    for (const auto& [name, ds] : cases) {
      const fs::path p = scratch(std::to_string(e) + name);
      write(ds, p, o);
      expect_streamed_as_read(p);
    }
    ++e;
  }
}

TEST(Summary, VtkXmlArraysLargerThanAPieceStraddleThePieces) {
  // 3 x 8 bytes a tuple: the 8 MiB pieces end inside tuples.
  ImageData img;
  img.dims = {101, 103, 107};
  const std::size_t n = 101 * 103 * 107;
  DataArray v("v", ScalarType::Float64, 3, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) v.set(i, c, std::fmod(0.37 * static_cast<double>(i) + c, 11.0));
  }
  v.set(n / 2, 1, 123.5);
  v.set(n - 1, 2, -7.25);
  img.point_data.add(std::move(v));
  for (const WriteOptions& o : {xml_encodings()[0], xml_encodings()[2]}) {
    const fs::path p = scratch("big.vti");
    write(img, p, o);
    expect_streamed_as_read(p);
    const DatasetSummary s = summarize_file(p);
    EXPECT_EQ(s.point_data.arrays[0].ranges.component(1).second, 123.5);
    EXPECT_EQ(s.point_data.arrays[0].ranges.component(2).first, -7.25);
  }
}

TEST(Summary, VtkXmlErrorsAreTheReadersErrors) {
  const fs::path p = scratch("cut.vtp");
  WriteOptions o;
  o.compress = false;
  write(mixed_polydata(), p, o);
  const auto size = fs::file_size(p);
  for (std::uintmax_t keep : {size - 40, size / 2, std::uintmax_t{200}}) {
    fs::resize_file(p, keep);
    SCOPED_TRACE("kept " + std::to_string(keep) + " bytes");
    expect_same_error(p);
  }
}

TEST(Summary, VtkLegacyStreamedAsReadInBinaryAndAsciiOnEveryDatasetType) {
  const StructuredGrid sg = small_grid();
  PolyData pd = mixed_polydata();
  DataArray n("n", ScalarType::Float32, 3, 12);
  for (std::size_t i = 0; i < 12; ++i) n.set(i, 2, 1.0);
  pd.point_data.add(std::move(n), AttributeRole::Normals);
  pd.field_data.add(DataArray::from_vector("w", 1, std::vector<double>{4.5, -2, 9}));
  const std::vector<std::pair<std::string, Dataset>> cases = {
      {"image.vtk", small_image()}, {"grid.vtk", sg}, {"poly.vtk", pd}, {"cells.vtk", mixed_grid()}};
  for (const bool binary : {true, false}) {
    for (const std::string version : {"4.2", "5.1"}) {
      WriteOptions o;
      o.binary = binary;
      o.vtk_legacy_version = version;
      for (const auto& [name, ds] : cases) {
        const fs::path p = scratch((binary ? "b" : "a") + version + name);
        write(ds, p, o);
        expect_streamed_as_read(p);
      }
    }
  }
}

TEST(Summary, VtkLegacyArraysLargerThanAPieceAndTheReadersErrors) {
  // A big-endian Float64 x 3 array over several 8 MiB pieces, ends inside tuples; points of a
  // structured grid streamed into its bounds.
  StructuredGrid sg;
  sg.dims = {101, 103, 107};
  const std::size_t n = 101 * 103 * 107;
  for (std::size_t i = 0; i < n; ++i) {
    sg.points.push_back({double(i % 101), double((i / 101) % 103), 0.5 * double(i / (101 * 103))});
  }
  DataArray v("v", ScalarType::Float64, 3, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) v.set(i, c, std::fmod(0.37 * static_cast<double>(i) + c, 11.0));
  }
  v.set(n / 2, 1, 123.5);
  sg.point_data.add(std::move(v));
  const fs::path p = scratch("big.vtk");
  write(sg, p);
  expect_streamed_as_read(p);
  EXPECT_EQ(summarize_file(p).point_data.arrays[0].ranges.component(1).second, 123.5);
  EXPECT_EQ(summarize_file(p).bounds.max.z, 53.0);

  // Truncated files and a non-finite point: the same errors from both paths.
  const fs::path small = scratch("cut.vtk");
  for (const bool binary : {true, false}) {
    WriteOptions o;
    o.binary = binary;
    write(mixed_polydata(), small, o);
    // The second point's first coordinate made NaN (the writer refuses to write one).
    std::string text;
    {
      std::ifstream in(small, std::ios::binary);
      text.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::size_t line = text.find("POINTS ");
    const std::size_t values = text.find('\n', line) + 1;
    const bool single = text.substr(line, values - line).find("float") != std::string::npos;
    if (binary) {
      const std::string nan = single ? std::string("\x7f\xc0\x00\x00", 4)
                                     : std::string("\x7f\xf8\0\0\0\0\0\0", 8);
      text.replace(values + 3 * nan.size(), nan.size(), nan);
    } else {
      std::size_t at = values;
      for (int t = 0; t < 3; ++t) at = text.find_first_of(" \n", text.find_first_not_of(" \n", at));
      at = text.find_first_not_of(" \n", at);
      text.replace(at, text.find_first_of(" \n", at) - at, "nan");
    }
    {
      std::ofstream out(small, std::ios::binary | std::ios::trunc);
      out << text;
    }
    const auto size = fs::file_size(small);
    for (std::uintmax_t keep : {size, size - 40, size / 2, std::uintmax_t{200}}) {
      fs::resize_file(small, keep);
      SCOPED_TRACE(std::string(binary ? "binary" : "ascii") + ", kept " + std::to_string(keep));
      expect_same_error(small);
    }
  }
}

TEST(Summary, OffStreamedAsReadOverSeveralBlocksWithItsErrors) {
  // 150 001 vertices (three blocks of the summary), triangles, quads and pentagons; NOFF and
  // COFF variants with normals and colours (one colour with alpha).
  const fs::path p = scratch("mesh.off");
  for (const std::string magic : {"OFF", "NOFF", "COFF"}) {
    std::string text = magic + "\n# a comment\n150001 3 0\n";
    for (int i = 0; i < 150001; ++i) {
      text += std::to_string(0.001 * i) + " " + std::to_string(std::sin(i)) + " " +
              std::to_string(i % 7 - 3);
      if (magic == "NOFF") text += " 0 0 " + std::to_string(i % 2);
      if (magic == "COFF") text += i == 5 ? " 10 20 30 40" : " 255 0 " + std::to_string(i % 256);
      text += "\n";
    }
    text += "3 0 1 2\n4 2 3 4 5\n5 5 6 7 8 150000\n";
    {
      std::ofstream out(p, std::ios::binary | std::ios::trunc);
      out << text;
    }
    expect_streamed_as_read(p);
    const DatasetSummary s = summarize_file(p);
    EXPECT_EQ(s.cell_types.at(CellType::Quad), 1u);
    EXPECT_EQ(s.bounds.max.x, 150.0);
  }
  // Errors: an index out of range, a truncated file.
  for (const std::string text : {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                                 "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n"}) {
    {
      std::ofstream out(p, std::ios::binary | std::ios::trunc);
      out << text;
    }
    expect_same_error(p);
  }
}

TEST(Summary, BinaryPlyInWindowsOfRecordsWithGroupedProperties) {
  // More vertices than one window holds; normals and colours grouped as the reader does; a
  // face property.
  PolyData pd;
  const std::size_t n = 700'001;
  DataArray normals("Normals", ScalarType::Float32, 3, n);
  DataArray colors("Colors", ScalarType::UInt8, 3, n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.001 * static_cast<double>(i);
    pd.points.push_back({std::cos(a), std::sin(a), 1e-6 * static_cast<double>(i)});
    normals.set(i, 0, std::cos(a));
    normals.set(i, 1, std::sin(a));
    normals.set(i, 2, 0);
    for (int c = 0; c < 3; ++c) colors.set(i, c, static_cast<double>((i * (c + 1)) % 251));
  }
  pd.point_data.add(std::move(normals), AttributeRole::Normals);
  pd.point_data.add(std::move(colors), AttributeRole::Scalars);
  for (Index i = 0; i + 2 < static_cast<Index>(n); i += 2) pd.polys.add({i, i + 1, i + 2});
  const fs::path p = scratch("many.ply");
  write(pd, p);
  expect_streamed_as_read(p);
  PlyWriteOptions o;
  o.encoding = PlyEncoding::BinaryBigEndian;
  write_ply(pd, p, o);
  expect_streamed_as_read(p);
}

TEST(Summary, AsciiPlyInWindowsOfRecordsAsRead) {
  // 150 001 vertices (more than two windows of records read value by value), a list property
  // among the vertex properties, an element the reader skips, faces of 3, 4 and 5 vertices with
  // a face property, then an empty face element alone.
  const fs::path p = scratch("ascii.ply");
  const std::size_t n = 150'001;
  auto header = [](std::size_t verts, std::size_t faces) {
    return "ply\nformat ascii 1.0\ncomment made by a test\nelement vertex " +
           std::to_string(verts) +
           "\nproperty float x\nproperty float y\nproperty float z\nproperty list uchar int "
           "tags\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar "
           "red\nproperty uchar green\nproperty uchar blue\nproperty double quality\nelement "
           "edge 2\nproperty int vertex1\nproperty int vertex2\nelement face " +
           std::to_string(faces) +
           "\nproperty int material\nproperty list uchar int vertex_indices\nend_header\n";
  };
  auto vertices = [&](std::string& text, std::size_t count, const std::string& odd) {
    for (std::size_t i = 0; i < count; ++i) {
      const double a = 0.001 * static_cast<double>(i);
      text += std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " " +
              (i == 77'777 && !odd.empty() ? odd : std::to_string(1e-5 * static_cast<double>(i))) +
              " " + std::to_string(i % 3) + (i % 3 > 0 ? " 7" : "") + (i % 3 > 1 ? " 8" : "") +
              " 0 0 1 " + std::to_string(i % 256) + " 3 " + std::to_string(255 - i % 200) + " " +
              std::to_string(0.5 * static_cast<double>(i)) + "\n";
    }
    text += "0 1\n1 2\n";
  };
  const std::size_t faces = n - 4;
  auto face_lines = [&](std::string& text, std::int64_t bad) {
    for (std::size_t f = 0; f < faces; ++f) {
      const std::size_t k = 3 + f % 3;
      text += std::to_string(static_cast<int>(f % 11) - 5) + " " + std::to_string(k);
      for (std::size_t j = 0; j < k; ++j) {
        text +=
            " " + std::to_string(f == 70'001 && bad >= 0 ? bad : static_cast<std::int64_t>(f + j));
      }
      text += "\n";
    }
  };
  {
    std::string text = header(n, faces);
    vertices(text, n, "");
    face_lines(text, -1);
    std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
  }
  expect_streamed_as_read(p);
  const DatasetSummary s = summarize_file(p);
  EXPECT_EQ(s.points, n);
  EXPECT_EQ(s.cells, faces);
  EXPECT_EQ(s.cell_types.at(CellType::Triangle), (faces + 2) / 3);
  EXPECT_EQ(s.cell_types.at(CellType::Quad), (faces + 1) / 3);
  EXPECT_EQ(s.cell_types.at(CellType::Polygon), faces / 3);
  ASSERT_NE(s.point_data.find("quality"), nullptr);
  EXPECT_EQ(s.point_data.find("quality")->ranges.component(0).second,
            0.5 * static_cast<double>(n - 1));
  ASSERT_NE(s.cell_data.find("material"), nullptr);
  EXPECT_EQ(s.cell_data.find("material")->ranges.component(0).first, -5.0);

  // An empty face element still carries its property, as the reader gives it.
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty "
         "float z\nelement face 0\nproperty list uchar int vertex_indices\nproperty int "
         "material\nend_header\n1 2 3\n";
  expect_streamed_as_read(p);
  // Without a vertex element the reader's mesh is empty: no arrays either.
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      << "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nproperty "
         "int material\nend_header\n";
  expect_streamed_as_read(p);

  // Errors past the first window: an index out of range, a non-finite coordinate, a file cut
  // short. The summary names the same record and line as the reader.
  for (int k = 0; k < 3; ++k) {
    std::string text = header(n, faces);
    vertices(text, n, k == 1 ? "nan" : "");
    face_lines(text, k == 0 ? static_cast<std::int64_t>(n) : -1);
    if (k == 2) text.resize(text.size() - 100'000);
    std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
    expect_same_error(p);
  }
}

TEST(Summary, BinaryPlyWhoseFacesTurnMixedAfterTheFirstWindows) {
  // 600 000 triangles (windows decoded in parallel), then quads and a pentagon (read value by
  // value from there on), with a face property; big-endian too.
  PolyData pd;
  const Index n = 600'010;
  for (Index i = 0; i < n; ++i) {
    pd.points.push_back({static_cast<double>(i % 1000), static_cast<double>(i / 1000), 0.0});
  }
  DataArray m("material", ScalarType::Int16, 1, static_cast<std::size_t>(n - 5));
  for (Index i = 0; i + 5 < n; ++i) {
    if (i < 600'000) {
      pd.polys.add({i, i + 1, i + 2});
    } else if (i == 600'001) {
      pd.polys.add({i, i + 1, i + 2, i + 3, i + 4});
    } else {
      pd.polys.add({i, i + 1, i + 2, i + 3});
    }
    m.set(static_cast<std::size_t>(i), 0, static_cast<double>(i % 9) - (i == 600'003 ? 100 : 0));
  }
  pd.cell_data.add(std::move(m));
  const fs::path p = scratch("mixed.ply");
  write(pd, p);
  expect_streamed_as_read(p);
  const DatasetSummary s = summarize_file(p);
  EXPECT_EQ(s.cell_types.at(CellType::Triangle), 600'000u);
  EXPECT_EQ(s.cell_types.at(CellType::Polygon), 1u);
  EXPECT_EQ(s.cell_types.at(CellType::Quad), 4u);
  EXPECT_EQ(s.cell_data.find("material")->ranges.component(0).first, 600'003 % 9 - 100.0);
  PlyWriteOptions o;
  o.encoding = PlyEncoding::BinaryBigEndian;
  write_ply(pd, p, o);
  expect_streamed_as_read(p);
}

TEST(Summary, GzipNrrdWithAByteSkipStreamed) {
  const std::size_t n = 64 * 64 * 40;
  std::vector<unsigned char> raw(100 + 4 * n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const float v = static_cast<float>(std::sin(0.01 * static_cast<double>(i)) * 1000);
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    for (int b = 0; b < 4; ++b) raw[100 + 4 * i + b] = static_cast<unsigned char>(u >> (24 - 8 * b));
  }
  uLongf len = compressBound(static_cast<uLong>(raw.size()));
  std::vector<unsigned char> z(len);
  ASSERT_EQ(compress2(z.data(), &len, raw.data(), static_cast<uLong>(raw.size()), 6), Z_OK);
  const fs::path data = scratch("vol.raw.z");
  std::ofstream(data, std::ios::binary).write(reinterpret_cast<const char*>(z.data()),
                                               static_cast<std::streamsize>(len));
  const fs::path header = scratch("vol.nhdr");
  std::ofstream(header) << "NRRD0004\ntype: float\ndimension: 3\nsizes: 64 64 40\nendian: big\n"
                           "encoding: gzip\nbyte skip: 100\nspacings: 1 2 3\ndata file: vol.raw.z\n";
  expect_streamed_as_read(header);
}

namespace {

/// A PLOT3D grid (x, y, z planes, then IBLANK) and solution (fsmach alpha re time, then density,
/// momentum and energy planes) of `dims`, written with `Real` values in the host's byte order or
/// swapped; density 0 at one point (velocity 0 there), every 97th point blanked.
template <class Real>
void write_plot3d(const fs::path& xyz, const fs::path& q, Dims dims, bool swap, bool iblank) {
  const std::size_t n = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
  auto put = [swap](std::ofstream& out, auto v) {
    unsigned char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (swap) std::reverse(b, b + sizeof v);
    out.write(reinterpret_cast<const char*>(b), sizeof v);
  };
  std::ofstream g(xyz, std::ios::binary | std::ios::trunc);
  for (Index d : dims) put(g, static_cast<std::int32_t>(d));
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i);
      put(g, static_cast<Real>(a == 0 ? std::sin(1e-3 * t) * t : a == 1 ? -0.5 * t : std::cos(t)));
    }
  }
  if (iblank) {
    for (std::size_t i = 0; i < n; ++i)
      put(g, static_cast<std::int32_t>(i % 97 == 3 ? 0 : 1 + i % 2));
  }
  std::ofstream s(q, std::ios::binary | std::ios::trunc);
  for (Index d : dims) put(s, static_cast<std::int32_t>(d));
  for (double c : {0.8, 5.0, 2e6, 0.25}) put(s, static_cast<Real>(c));
  for (int var = 0; var < 5; ++var) {
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i);
      const double v = var == 0 ? (i == 1000 ? 0.0 : 1.0 + std::sin(t) * 0.5)
                                : std::cos(t * (var + 1)) * static_cast<double>(var) + 1e-6 * t;
      put(s, static_cast<Real>(v));
    }
  }
}

}  // namespace

TEST(Summary, Plot3dStreamedAsReadInBlocksWithIblankAndSolution) {
  // 90 x 60 x 55 = 297 000 points: several blocks and progress slices; float32 in the other
  // byte order and float64 in the host's, with IBLANK and the Valid cells it gives; a grid of
  // one k plane; the real combustor.
  const fs::path xyz = scratch("g.xyz"), q = scratch("g.q");
  ReadOptions with_q;
  with_q.plot3d_q = q;
  write_plot3d<float>(xyz, q, {90, 60, 55}, true, true);
  expect_streamed_as_read(xyz, with_q);
  expect_streamed_as_read(xyz);
  DatasetSummary s = summarize_file(xyz, with_q);
  EXPECT_EQ(s.cells, 89u * 59u * 54u);
  ASSERT_NE(s.cell_data.find("Valid"), nullptr);
  EXPECT_EQ(s.cell_data.find("Valid")->ranges.component(0), (std::pair<double, double>{0, 1}));
  EXPECT_EQ(s.point_data.active[static_cast<std::size_t>(AttributeRole::Scalars)], "Density");
  write_plot3d<double>(xyz, q, {90, 60, 55}, false, false);
  expect_streamed_as_read(xyz, with_q);
  write_plot3d<float>(xyz, q, {300, 250, 1}, false, true);
  expect_streamed_as_read(xyz, with_q);
  ReadOptions comb;
  comb.plot3d_q = test::data_path("combq.bin");
  expect_streamed_as_read(test::data_path("combxyz.bin"), comb);
}

TEST(Summary, Plot3dErrorsAreTheReadersErrors) {
  const fs::path xyz = scratch("g.xyz"), q = scratch("g.q");
  ReadOptions with_q;
  with_q.plot3d_q = q;
  const Dims dims{90, 60, 55};
  const std::size_t n = 90 * 60 * 55;
  // A NaN y alone; then also a NaN x in a later block: the x plane comes first in the file.
  write_plot3d<float>(xyz, q, dims, false, false);
  for (const auto& [axis, point] : {std::pair<std::size_t, std::size_t>{1, 150'000},
                                    std::pair<std::size_t, std::size_t>{0, 200'000}}) {
    {
      std::fstream f(xyz, std::ios::binary | std::ios::in | std::ios::out);
      f.seekp(static_cast<std::streamoff>(12 + 4 * (axis * n + point)));
      const float nan = std::numeric_limits<float>::quiet_NaN();
      f.write(reinterpret_cast<const char*>(&nan), 4);
    }
    expect_same_error(xyz, with_q);
    std::string msg;
    try {
      (void)summarize_file(xyz, with_q);
    } catch (const Error& e) {
      msg = e.what();
    }
    EXPECT_NE(msg.find("point " + std::to_string(point) + " "), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::string("non-finite ") + "xyz"[axis]), std::string::npos) << msg;
  }
  // A solution one value short, and one of other dimensions.
  write_plot3d<float>(xyz, q, dims, false, false);
  fs::resize_file(q, fs::file_size(q) - 4);
  expect_same_error(xyz, with_q);
  write_plot3d<float>(scratch("other.xyz"), q, {90, 60, 54}, false, false);
  expect_same_error(xyz, with_q);
}

TEST(Summary, VtkLegacyCellSectionsStreamedWithTheReadersErrors) {
  // Cell lists larger than a streamed piece (8 MiB binary, 64 Ki values of text), cells across
  // piece boundaries, in both layouts and encodings.
  PolyData pd;
  const int n = 200'000;
  for (int i = 0; i < n; ++i) pd.points.push_back({std::cos(i), std::sin(i), 1e-3 * i});
  for (Index i = 0; i + 4 < n; i += 3) {
    pd.polys.add({i, i + 1, i + 2});
    if (i % 9 == 0) pd.polys.add({i, i + 2, i + 3, i + 4});
    if (i % 15 == 0) pd.lines.add({i, i + 4});
  }
  UnstructuredGrid ug;
  for (int i = 0; i < n; ++i) ug.points.push_back({double(i % 7), double(i % 11), 1e-3 * i});
  for (Index i = 0; i + 8 < n; i += 5) {
    ug.add_cell(CellType::Tetra, {i, i + 1, i + 2, i + 3});
    if (i % 4 == 0)
      ug.add_cell(CellType::Hexahedron, {i, i + 1, i + 2, i + 3, i + 4, i + 5, i + 6, i + 7});
  }
  for (const bool binary : {true, false}) {
    for (const std::string version : {"4.2", "5.1"}) {
      WriteOptions o;
      o.binary = binary;
      o.vtk_legacy_version = version;
      const fs::path p = scratch(std::string(binary ? "b" : "a") + version + ".vtk");
      write(pd, p, o);
      expect_streamed_as_read(p);
      write(ug, p, o);
      expect_streamed_as_read(p);
    }
  }

  // Errors found while streaming (a section's structure), after it (ids, minimum sizes, types
  // against sizes) and with two errors in a file: the same messages as the reader's.
  const std::string head = "# vtk DataFile Version 4.2\nt\nASCII\nDATASET ";
  const std::string points = "POINTS 4 float\n0 0 0 1 0 0 0 1 0 1 1 0\n";
  const std::vector<std::string> bad = {
      "POLYDATA\n" + points + "POLYGONS 2 8\n3 0 1 2\n3 1 3 4\n",  // id out of range
      "POLYDATA\n" + points + "POLYGONS 2 7\n3 0 1 2\n2 1 3\n",    // too few points
      "POLYDATA\n" + points + "POLYGONS 2 8\n3 0 1 2\n5 1 3 2\n",  // count beyond the size
      "POLYDATA\n" + points + "POLYGONS 1 8\n3 0 1 2\n3 1 3 2\n",  // values beyond the cells
      "POLYDATA\n" + points + "POLYGONS 3 8\n3 0 1 2\n3 1 3 2\n",  // cells beyond the size
      "POLYDATA\n" + points + "POLYGONS 2 8\n3 0 1 2\n3 1 x 2\n",  // a bad token
      "POLYDATA\n" + points + "POLYGONS 1 4\n3 0 1 9\nLINES 1 3\n5 0 1\n",  // two errors
      "POLYDATA\n" + points +
          "POLYGONS 3 6\nOFFSETS vtktypeint64\n0 3 2\n"
          "CONNECTIVITY vtktypeint64\n0 1 2 1 3 2\n",  // offsets decrease
      "POLYDATA\n" + points +
          "POLYGONS 3 6\nOFFSETS vtktypeint64\n0 3 6\n"
          "CONNECTIVITY vtktypeint64\n0 1 2 1 3 7\n",  // id out of range
      "POLYDATA\n" + points +
          "POLYGONS 3 5\nOFFSETS vtktypeint64\n0 3 6\n"
          "CONNECTIVITY vtktypeint64\n0 1 2 1 3\n",  // last offset
      "POLYDATA\n" + points +
          "POLYGONS 3 6\nOFFSETS float\n0 3 6\n"
          "CONNECTIVITY vtktypeint64\n0 1 2 1 3 2\n",  // not integers
      "UNSTRUCTURED_GRID\n" + points +
          "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n5\n",  // a 4-point triangle
      "UNSTRUCTURED_GRID\n" + points + "CELLS 2 8\n3 0 1 2\n3 1 3 2\nCELL_TYPES 1\n5\n",
      "UNSTRUCTURED_GRID\n" + points +
          "CELLS 2 7\nOFFSETS vtktypeint64\n0 3\n"
          "CONNECTIVITY vtktypeint64\n0 -1 2\nCELL_TYPES 1\n5\n",
      "UNSTRUCTURED_GRID\n" + points + "CELL_TYPES 1\n10\nCELLS 1 4\n3 0 1 2\n",  // types first
  };
  const fs::path p = scratch("bad.vtk");
  for (const std::string& body : bad) {
    SCOPED_TRACE(body);
    std::ofstream(p, std::ios::binary | std::ios::trunc) << head << body;
    expect_same_error(p);
  }
  // The binary layout: a point id and a cell size changed in place.
  for (const std::string version : {"4.2", "5.1"}) {
    WriteOptions o;
    o.vtk_legacy_version = version;
    for (int change = 0; change < 2; ++change) {
      write(mixed_grid(), p, o);
      std::string text;
      {
        std::ifstream in(p, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), {});
      }
      const std::size_t at =
          text.find('\n', text.find(version == "4.2" ? "CELLS " : "CONNECTIVITY")) + 1;
      // 4.2: the hexahedron's count (8 -> 7) or its first id; 5.1: the first id (int64).
      const std::size_t width = version == "4.2" ? 4 : 8;
      const std::size_t where =
          at + (change == 1 && version == "4.2" ? 0 : (version == "4.2" ? width : 0));
      text[where + width - 1] = static_cast<char>(change == 1 && version == "4.2" ? 7 : 99);
      std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
      SCOPED_TRACE(version + " change " + std::to_string(change));
      expect_same_error(p);
    }
  }
  // Points after the cells (their ids checked once the points are known), valid and not; two
  // POINTS sections, the ids checked against the last.
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      << head << "POLYDATA\nPOLYGONS 2 8\n3 0 1 2\n3 1 3 2\n"
      << points << "CELL_DATA 2\nSCALARS c int 1\nLOOKUP_TABLE default\n4 5\n";
  expect_streamed_as_read(p);
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      << head << "POLYDATA\nPOLYGONS 2 8\n3 0 1 2\n3 1 3 4\n"
      << points;
  expect_same_error(p);
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      << head << "POLYDATA\nPOINTS 5 float\n0 0 0 1 0 0 0 1 0 1 1 0 2 2 2\nPOLYGONS 1 4\n3 0 1 4\n"
      << points;
  expect_same_error(p);
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      << head << "POLYDATA\n"
      << points << "POLYGONS 1 4\n3 0 1 4\n"
      << "POINTS 5 float\n0 0 0 1 0 0 0 1 0 1 1 0 2 2 2\n";
  expect_streamed_as_read(p);
}

namespace {

// A .glb of `json` and the binary chunk `bin` (both padded to 4 bytes).
void write_glb(const fs::path& path, std::string json, std::vector<std::uint8_t> bin) {
  while (json.size() % 4 != 0) json += ' ';
  while (bin.size() % 4 != 0) bin.push_back(0);
  std::string out;
  auto u32 = [&out](std::size_t v) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
  };
  out += "glTF";
  u32(2);
  u32(12 + 8 + json.size() + 8 + bin.size());
  u32(json.size());
  out += "JSON";
  out += json;
  u32(bin.size());
  out += std::string("BIN") + '\0';
  out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
  std::ofstream(path, std::ios::binary | std::ios::trunc) << out;
}

template <class T>
void put(std::vector<std::uint8_t>& bin, std::initializer_list<T> values) {
  for (const T v : values) {
    const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
    bin.insert(bin.end(), b, b + sizeof(T));
  }
}

}  // namespace

TEST(Summary, GltfMeshesOfEveryCodecAppendedAsRead) {
  // Two meshes with triangles, a polyline and a vertex cell; arrays that both have (kept) and
  // one that only the first has (dropped by the append, as read() drops it).
  PolyData a;
  for (int i = 0; i < 300; ++i)
    a.points.push_back({std::cos(0.1 * i), std::sin(0.1 * i), 0.01 * i});
  for (Index i = 0; i + 2 < 300; i += 3) a.polys.add({i, i + 1, i + 2});
  a.lines.add({0, 5, 9});
  a.verts.add({7});
  DataArray e("Elevation", ScalarType::Float32, 1, 300),
      only("OnlyHere", ScalarType::Int16, 1, 300);
  DataArray colors("Colors", ScalarType::UInt8, 3, 300);
  for (std::size_t i = 0; i < 300; ++i) {
    e.set(i, 0, 0.5 * static_cast<double>(i) - 20);
    only.set(i, 0, static_cast<double>(i % 17));
    for (int c = 0; c < 3; ++c) colors.set(i, c, static_cast<double>((i * (c + 3)) % 256));
  }
  a.point_data.add(std::move(e));
  a.point_data.add(std::move(only));
  a.point_data.add(std::move(colors), AttributeRole::Scalars);
  PolyData b;
  for (int i = 0; i < 40; ++i) b.points.push_back({5.0 + i, -1.0 * i, 3});
  for (Index i = 0; i + 2 < 40; ++i) b.polys.add({i, i + 1, i + 2});
  DataArray e2("Elevation", ScalarType::Float32, 1, 40), c2("Colors", ScalarType::UInt8, 3, 40);
  for (std::size_t i = 0; i < 40; ++i) {
    e2.set(i, 0, 100.0 + static_cast<double>(i));
    for (int c = 0; c < 3; ++c) c2.set(i, c, static_cast<double>(i + c));
  }
  b.point_data.add(std::move(e2));
  b.point_data.add(std::move(c2), AttributeRole::Scalars);
  const GltfMesh meshes[] = {{"a", a}, {"b", b}};
  for (const GltfCodec codec : {GltfCodec::None, GltfCodec::Meshopt, GltfCodec::Draco}) {
    const fs::path p = scratch("two_" + std::string(gltf_codec_name(codec)) + ".glb");
    GltfWriteOptions o;
    o.codec = codec;
    (void)write_gltf(meshes, p, o);
    expect_streamed_as_read(p);
    const DatasetSummary s = summarize_file(p);
    EXPECT_EQ(s.cell_types.at(CellType::Triangle), 138u);
    EXPECT_EQ(s.cell_types.at(CellType::Line), 2u);
    EXPECT_EQ(s.cell_types.at(CellType::Vertex), 1u);
    EXPECT_TRUE(s.point_data.find("Elevation"));
    EXPECT_FALSE(s.point_data.find("OnlyHere"));
  }
}

TEST(Summary, GltfPrimitiveModesSharedPositionsAndEmptyMeshes) {
  // Mesh 0: five points shared by a triangle strip, a fan, a line loop, a line strip and a
  // point primitive without indices; mesh 1: three points, a triangle list; both with _TEMP.
  std::vector<std::uint8_t> bin;
  put<float>(bin, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 2});  // 0: 60 bytes
  put<std::uint32_t>(bin, {0, 1, 2, 3, 4, 0});                           // 60: 24 bytes
  put<float>(bin, {-3, 0, 0, -2, 0, 0, -2, 4, 1});                       // 84: 36 bytes
  put<float>(bin, {7, 8, 9});                                            // 120: 12 bytes
  put<float>(bin, {1, 2, 3, 4, -5});                                     // 132: 20 bytes
  const std::string views =
      R"("buffers":[{"byteLength":152}],"bufferViews":[{"buffer":0,"byteLength":60},)"
      R"({"buffer":0,"byteOffset":60,"byteLength":24},{"buffer":0,"byteOffset":84,"byteLength":36},)"
      R"({"buffer":0,"byteOffset":120,"byteLength":12},{"buffer":0,"byteOffset":132,"byteLength":20}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":5,"type":"VEC3"},)"
      R"({"bufferView":1,"componentType":5125,"count":6,"type":"SCALAR"},)"
      R"({"bufferView":2,"componentType":5126,"count":3,"type":"VEC3"},)"
      R"({"bufferView":3,"componentType":5126,"count":3,"type":"SCALAR"},)"
      R"({"bufferView":4,"componentType":5126,"count":5,"type":"SCALAR"}],)";
  const std::string shared = R"({"attributes":{"POSITION":0,"_TEMP":4})";
  const std::string mesh0 = R"({"primitives":[)" + shared + R"(,"indices":1,"mode":5},)" + shared +
                            R"(,"indices":1,"mode":6},)" + shared + R"(,"indices":1,"mode":2},)" +
                            shared + R"(,"indices":1,"mode":3},)" + shared + R"(,"mode":0}]})";
  const std::string mesh1 = R"({"primitives":[{"attributes":{"POSITION":2,"_TEMP":3}}]})";
  const std::string head = R"({"asset":{"version":"2.0"},)" + views;
  const fs::path p = scratch("modes.glb");
  write_glb(p, head + R"("meshes":[)" + mesh0 + "," + mesh1 + "]}", bin);
  expect_streamed_as_read(p);
  const DatasetSummary s = summarize_file(p);
  EXPECT_EQ(s.points, 8u);
  // Strip and fan: 4 triangles each; the triangle list: 1. Loop: 6 segments; strip: 5. 5 points.
  EXPECT_EQ(s.cell_types.at(CellType::Triangle), 9u);
  EXPECT_EQ(s.cell_types.at(CellType::Line), 11u);
  EXPECT_EQ(s.cell_types.at(CellType::Vertex), 5u);
  ASSERT_TRUE(s.point_data.find("_TEMP"));
  EXPECT_EQ(s.point_data.find("_TEMP")->ranges.component(0), (std::pair<double, double>{-5, 9}));
  // A third mesh without primitives: an empty part, which drops the arrays.
  write_glb(p, head + R"("meshes":[)" + mesh0 + "," + mesh1 + R"(,{"primitives":[]}]})", bin);
  expect_streamed_as_read(p);
  EXPECT_TRUE(summarize_file(p).point_data.arrays.empty());
  // No meshes at all; an index past the points; a missing POSITION: read()'s errors.
  write_glb(p, head + R"("meshes":[]})", bin);
  expect_streamed_as_read(p);
  bin[60 + 4 * 3] = 9;
  write_glb(p, head + R"("meshes":[)" + mesh0 + "]}", bin);
  expect_same_error(p);
  write_glb(p, head + R"("meshes":[{"primitives":[{"attributes":{}}]}]})", bin);
  expect_same_error(p);
}
