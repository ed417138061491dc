// Tests for the glTF binary (.glb) writer and reader. Every file written here is also checked by
// the Khronos glTF validator (npm gltf-validator, run through node): 0 errors.

#include "isoforge/io/gltf.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/draco.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/ply.hpp"
#include "isoforge/model/attractor.hpp"
#include "support/mutate.hpp"
#include "support/scratch.hpp"

using namespace isoforge;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("gltf", name);
}

GltfWriteOptions with_codec(GltfCodec codec) {
  GltfWriteOptions o;
  o.codec = codec;
  return o;
}
const GltfWriteOptions kPlain = with_codec(GltfCodec::None);

// Runs the Khronos validator on `path`; fails the test unless it reports 0 errors. No node or
// no validator is a failure, not a skip: `make test` installs them (make deps).
void expect_valid(const fs::path& path) {
  const std::string node = ISOFORGE_NODE;
  ASSERT_FALSE(node.empty()) << "node (Node.js) was not found when configuring: install it "
                                "(make deps) and reconfigure; the glTF validator runs on node";
  const fs::path script = ISOFORGE_GLTF_VALIDATE;
  ASSERT_TRUE(
      fs::exists(fs::path(script).parent_path().parent_path() / "node_modules" / "gltf-validator"))
      << "npm package gltf-validator missing: run `make deps` (npm ci in viewer/)";
  const std::string cmd = "'" + node + "' '" + script.string() + "' '" + path.string() + "' 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = ::pclose(pipe);
  EXPECT_EQ(status, 0) << "validator: " << out;
  EXPECT_NE(out.find(": 0 errors"), std::string::npos) << out;
}

// A unit square (a quad: 2 triangles), a polyline through 3 points (2 segments) and one vertex
// cell, with a scalar, a vector, RGB colours (the active scalars) and a cell array.
PolyData sample_mesh() {
  PolyData pd;
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1},
                       Vec3{0.5, 0, 2}, Vec3{1, 0, 1.25}}) {
    pd.points.push_back(p);
  }
  pd.polys.add({0, 1, 2, 3});
  pd.lines.add({4, 5, 6});
  pd.verts.add({5});
  pd.point_data.add(DataArray::from_vector<float>("Elevation", 1, {0, 1, 2, 3, 4.5f, 5.25f, -6}));
  pd.point_data.add(DataArray::from_vector<double>(
      "Velocity", 3, {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 0.5, 0.25, 0.125, 2, 3, 4, -1, -2, -3}));
  pd.point_data.add(DataArray::from_vector<std::int32_t>("Label", 1, {7, 8, 9, 10, 11, 12, -13}));
  pd.point_data.add(
      DataArray::from_vector<std::uint8_t>(
          "Colors", 3, {255, 0, 0, 0, 255, 0, 0, 0, 255, 9, 9, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9}),
      AttributeRole::Scalars);
  pd.cell_data.add(DataArray::from_vector<float>("Area", 1, {1, 0, 0}));
  return pd;
}

// Triangles as sorted-rotation triples (meshopt's index codec may rotate a triangle's corners,
// keeping its orientation), sorted.
std::vector<std::array<Index, 3>> triangles(const PolyData& pd) {
  std::vector<std::array<Index, 3>> out;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto t = pd.polys.cell(c);
    EXPECT_EQ(t.size(), 3u);
    std::array<Index, 3> r{t[0], t[1], t[2]};
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
    out.push_back(r);
  }
  std::sort(out.begin(), out.end());
  return out;
}

CellArray cells(const std::vector<Index>& offsets, const std::vector<Index>& ids) {
  return CellArray(offsets, ids);
}

void expect_same_arrays(const PolyData& a, const PolyData& b) {
  for (const char* name : {"Elevation", "Velocity", "Label", "Colors"}) {
    const DataArray* x = a.point_data.find(name);
    const DataArray* y = b.point_data.find(name);
    ASSERT_TRUE(x && y) << name;
    EXPECT_EQ(x->type(), y->type()) << name;  // restored from the file's extras
    EXPECT_EQ(x->components(), y->components()) << name;
    ASSERT_EQ(x->size(), y->size()) << name;
    for (std::size_t i = 0; i < x->tuples(); ++i) {
      for (int c = 0; c < x->components(); ++c) EXPECT_EQ(x->get(i, c), y->get(i, c)) << name;
    }
  }
}

TEST(Gltf, CountsOfATinyMesh) {
  const PolyData pd = sample_mesh();
  const auto path = scratch("tiny") / "tiny.glb";
  const GltfWriteStats stats = write_gltf(pd, path, kPlain);
  EXPECT_EQ(stats.meshes, 1u);
  EXPECT_EQ(stats.vertices, 7u);
  EXPECT_EQ(stats.triangles, 2u);  // the quad, fan-triangulated
  EXPECT_EQ(stats.segments, 2u);   // a polyline of 3 points
  EXPECT_EQ(stats.points, 1u);
  EXPECT_EQ(stats.bytes, fs::file_size(path));
  EXPECT_EQ(stats.normals_replaced, 3u);  // points 4, 5, 6 (line and vertex) are on no triangle
  ASSERT_EQ(stats.arrays_skipped.size(), 1u);  // the cell array
  EXPECT_NE(stats.arrays_skipped[0].find("Area (cell data"), std::string::npos);
  expect_valid(path);
}

TEST(Gltf, PlainRoundTripKeepsValuesNamesAndCells) {
  const PolyData pd = sample_mesh();
  const auto path = scratch("plain") / "mesh.glb";
  (void)write_gltf(pd, path, kPlain);
  expect_valid(path);
  const GltfContent content = read_gltf(path);
  ASSERT_EQ(content.meshes.size(), 1u);
  EXPECT_EQ(content.meshes[0].name, "mesh");  // the file's stem
  const PolyData& back = content.meshes[0].mesh;
  ASSERT_EQ(back.num_points(), 7u);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(back.points[i], pd.points[i]);
  EXPECT_EQ(back.polys, cells({0, 3, 6}, {0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(back.lines, cells({0, 2, 4}, {4, 5, 5, 6}));
  EXPECT_EQ(back.verts, cells({0, 1}, {5}));
  expect_same_arrays(pd, back);
  ASSERT_NE(back.point_data.scalars(), nullptr);
  EXPECT_EQ(back.point_data.scalars()->name(), "Colors");
  // Normals: computed from the triangles (+z, right-hand rule), (0,0,1) elsewhere.
  const DataArray* n = back.point_data.normals();
  ASSERT_NE(n, nullptr);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(n->get(i, 2), 1.0);
  EXPECT_TRUE(back.cell_data.empty());
}

// Plain views are made and written a slice (about 4 MiB) at a time, straight from the dataset:
// a mesh whose streams and index views each span several slices, with cells that themselves
// cross slice boundaries (a 500k-point polygon, a 400k-point strip, a 600k-point polyline, a
// 1.1M-point poly-vertex), comes back whole, for the plain and the meshopt codec. Progress
// advances through the BIN chunk, and cancelling there leaves nothing behind.
TEST(Gltf, ViewsOfManySlicesComeBackWhole) {
  constexpr std::size_t n = 600000;
  PolyData pd;
  pd.points = Points(n);
  auto xyz = pd.points.floats();
  std::vector<std::uint8_t> rgba(4 * n);
  std::vector<float> pair(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto f = static_cast<float>(i);
    xyz[3 * i] = f, xyz[3 * i + 1] = 0.5f * f, xyz[3 * i + 2] = float(i % 977);
    for (std::size_t k = 0; k < 4; ++k)
      rgba[4 * i + k] = static_cast<std::uint8_t>((i + 61 * k) % 256);
    pair[2 * i] = -f, pair[2 * i + 1] = float(i % 13);
  }
  pd.point_data.add(DataArray::from_vector<std::uint8_t>("Colors", 4, rgba),
                    AttributeRole::Scalars);
  pd.point_data.add(DataArray::from_vector<float>("Pair", 2, pair));
  std::vector<Index> polygon(500000), strip(400000), polyline(n), poly_vertex(1100000);
  for (std::size_t i = 0; i < polygon.size(); ++i) polygon[i] = Index(i);
  for (std::size_t i = 0; i < strip.size(); ++i) strip[i] = Index(n - 1 - i);
  for (std::size_t i = 0; i < polyline.size(); ++i) polyline[i] = Index((7 * i) % n);
  for (std::size_t i = 0; i < poly_vertex.size(); ++i) poly_vertex[i] = Index((13 * i) % n);
  pd.polys.add({1, 2, 3});
  pd.polys.add(polygon);
  pd.polys.add({4, 5, 6, 7});
  pd.strips.add(strip);
  pd.lines.add(polyline);
  pd.verts.add(poly_vertex);
  // The expected primitives: polygons as fans, strips alternating (core's strip_triangle).
  std::vector<std::array<Index, 3>> expected_triangles;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto cell = pd.polys.cell(c);
    for (std::size_t k = 1; k + 1 < cell.size(); ++k)
      expected_triangles.push_back({cell[0], cell[k], cell[k + 1]});
  }
  for (std::size_t k = 0; k + 2 < strip.size(); ++k) {
    const bool odd = k % 2;
    expected_triangles.push_back({strip[k + odd], strip[k + 1 - odd], strip[k + 2]});
  }
  for (const GltfCodec codec : {GltfCodec::None, GltfCodec::Meshopt}) {
    SCOPED_TRACE(std::string(gltf_codec_name(codec)));
    GltfWriteOptions options = with_codec(codec);
    std::vector<double> reported;
    options.progress = [&](double f) {
      reported.push_back(f);
      return true;
    };
    const auto path = scratch("slices") / (std::string(gltf_codec_name(codec)) + ".glb");
    const GltfWriteStats stats = write_gltf(pd, path, options);
    EXPECT_EQ(stats.triangles, expected_triangles.size());
    EXPECT_EQ(stats.segments, n - 1);
    EXPECT_EQ(stats.points, poly_vertex.size());
    EXPECT_EQ(stats.bytes, fs::file_size(path));
    ASSERT_FALSE(reported.empty());
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
    EXPECT_EQ(reported.back(), 1.0);
    if (codec == GltfCodec::None) {  // slice by slice: positions alone are 7.2 MB
      EXPECT_GT(std::count_if(reported.begin(), reported.end(),
                              [](double f) { return f > 0.5 && f < 1; }),
                6);
    }
    const GltfContent content = read_gltf(path);
    ASSERT_EQ(content.meshes.size(), 1u);
    const PolyData& back = content.meshes[0].mesh;
    ASSERT_EQ(back.num_points(), n);
    EXPECT_TRUE(std::equal(xyz.begin(), xyz.end(), back.points.floats().begin()));
    const DataArray* colors = back.point_data.find("Colors");
    const DataArray* pairs = back.point_data.find("Pair");
    ASSERT_TRUE(colors && pairs);
    EXPECT_TRUE(std::equal(rgba.begin(), rgba.end(), colors->values<std::uint8_t>().begin()));
    EXPECT_TRUE(std::equal(pair.begin(), pair.end(), pairs->values<float>().begin()));
    ASSERT_EQ(back.polys.size(), expected_triangles.size());
    std::size_t wrong = 0;
    for (std::size_t t = 0; t < expected_triangles.size(); ++t) {
      const auto c = back.polys.cell(t);
      std::array<Index, 3> got{c[0], c[1], c[2]}, want = expected_triangles[t];
      // meshopt's index codec may rotate a triangle's corners, keeping its orientation
      std::rotate(got.begin(), std::min_element(got.begin(), got.end()), got.end());
      std::rotate(want.begin(), std::min_element(want.begin(), want.end()), want.end());
      wrong += got != want;
    }
    EXPECT_EQ(wrong, 0u);
    ASSERT_EQ(back.lines.size(), n - 1);
    wrong = 0;
    for (std::size_t s = 0; s + 1 < n; ++s) {
      const auto c = back.lines.cell(s);
      wrong += c.size() != 2 || c[0] != polyline[s] || c[1] != polyline[s + 1];
    }
    EXPECT_EQ(wrong, 0u);
    ASSERT_EQ(back.verts.size(), poly_vertex.size());
    wrong = 0;
    for (std::size_t v = 0; v < poly_vertex.size(); ++v)
      wrong += back.verts.cell(v)[0] != poly_vertex[v];
    EXPECT_EQ(wrong, 0u);
  }
  // Cancelled while the BIN chunk is written: no file, no temporary file.
  const auto dir = scratch("slices_cancel");
  GltfWriteOptions cancel = kPlain;
  cancel.progress = [](double f) { return f < 0.75; };
  EXPECT_THROW((void)write_gltf(pd, dir / "cancelled.glb", cancel), Cancelled);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(Gltf, MeshoptRoundTripIsLosslessAndSmaller) {
  const PolyData bunny = read_ply(isoforge::test::data_path("bunny.ply"));
  const auto dir = scratch("meshopt");
  const GltfWriteOptions plain = kPlain, meshopt = with_codec(GltfCodec::Meshopt);
  const auto a = write_gltf(bunny, dir / "plain.glb", plain);
  const auto b = write_gltf(bunny, dir / "meshopt.glb", meshopt);
  expect_valid(dir / "plain.glb");
  expect_valid(dir / "meshopt.glb");
  EXPECT_EQ(b.triangles, 69451u);
  EXPECT_EQ(a.raw_bytes, b.raw_bytes);  // the same data, laid out the same way
  EXPECT_LT(b.bytes, a.bytes);          // the codec shrinks it
  const PolyData x = read_gltf(dir / "plain.glb").meshes.at(0).mesh;
  const PolyData y = read_gltf(dir / "meshopt.glb").meshes.at(0).mesh;
  ASSERT_EQ(x.num_points(), bunny.num_points());
  EXPECT_EQ(x.points, y.points);  // lossless: bit for bit
  EXPECT_EQ(triangles(x), triangles(y));
  EXPECT_EQ(x.point_data, y.point_data);

  // The tiny mesh (lines and points use the index-sequence codec).
  const PolyData pd = sample_mesh();
  (void)write_gltf(pd, dir / "tiny.glb", meshopt);
  expect_valid(dir / "tiny.glb");
  const PolyData back = read_gltf(dir / "tiny.glb").meshes.at(0).mesh;
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(back.points[i], pd.points[i]);
  EXPECT_EQ(triangles(back), (std::vector<std::array<Index, 3>>{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(back.lines, cells({0, 2, 4}, {4, 5, 5, 6}));
  EXPECT_EQ(back.verts, cells({0, 1}, {5}));
  expect_same_arrays(pd, back);
}

TEST(Gltf, EverySrgbColourCodeRoundTrips) {
  // COLOR_0 is stored linear (uint16); each of the 256 sRGB codes must come back as itself.
  PolyData pd;
  std::vector<std::uint8_t> rgba;
  for (int i = 0; i < 256; ++i) {
    pd.points.push_back(Vec3{double(i), 0, 0});
    pd.verts.add({i});
    rgba.insert(rgba.end(),
                {std::uint8_t(i), std::uint8_t(255 - i), std::uint8_t(i / 2), std::uint8_t(i)});
  }
  pd.point_data.add(DataArray::from_vector<std::uint8_t>("RGBA", 4, rgba), AttributeRole::Scalars);
  const auto dir = scratch("colours");
  for (const auto& [file, options] :
       {std::pair{"plain.glb", kPlain}, std::pair{"meshopt.glb", with_codec(GltfCodec::Meshopt)}}) {
    (void)write_gltf(pd, dir / file, options);
    expect_valid(dir / file);
    const PolyData back = read_gltf(dir / file).meshes.at(0).mesh;
    const DataArray* colours = back.point_data.scalars();
    ASSERT_NE(colours, nullptr);
    EXPECT_EQ(colours->name(), "RGBA");
    ASSERT_EQ(colours->type(), ScalarType::UInt8);
    EXPECT_TRUE(std::ranges::equal(colours->values<std::uint8_t>(), rgba)) << file;
  }
}

TEST(Gltf, SeveralNamedMeshesUnitsAndLegend) {
  PolyData tri;
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 3, 0}}) tri.points.push_back(p);
  tri.polys.add({0, 1, 2});
  PolyData cloud;  // points without cells: one POINTS primitive over every point
  for (int i = 0; i < 5; ++i) cloud.points.push_back(Vec3{double(i), 1, 2});
  GltfLegend legend{
      "Elevation", "viridis", -1.5,
      2.5,         false,     {{{68, 1, 84, 255}}, {{33, 145, 140, 255}}, {{253, 231, 37, 255}}}};
  const std::vector<GltfMesh> meshes = {{"triangle", tri, legend}, {"cloud", cloud}};
  const auto path = scratch("named") / "two.glb";
  GltfWriteOptions options = kPlain;
  options.units = "mm";
  const auto stats = write_gltf(meshes, path, options);
  EXPECT_EQ(stats.meshes, 2u);
  EXPECT_EQ(stats.triangles, 1u);
  EXPECT_EQ(stats.points, 5u);
  expect_valid(path);
  const GltfContent content = read_gltf(path);
  EXPECT_EQ(content.units, "mm");
  ASSERT_EQ(content.meshes.size(), 2u);
  EXPECT_EQ(content.meshes[0].name, "triangle");
  EXPECT_EQ(content.meshes[1].name, "cloud");
  EXPECT_EQ(content.meshes[0].mesh.polys.size(), 1u);
  EXPECT_EQ(content.meshes[1].mesh.verts.size(), 5u);
  ASSERT_TRUE(content.meshes[0].legend.has_value());
  EXPECT_EQ(content.meshes[0].legend->colormap, "viridis");
  EXPECT_EQ(content.meshes[0].legend->min, -1.5);
  EXPECT_EQ(content.meshes[0].legend->max, 2.5);
  EXPECT_EQ(content.meshes[0].legend->colors, legend.colors);
  EXPECT_FALSE(content.meshes[1].legend.has_value());
  // The io dispatch appends every mesh: 3 + 5 points.
  const Dataset ds = read(path);
  EXPECT_EQ(num_points(ds), 8u);
  EXPECT_EQ(num_cells(ds), 6u);
}

TEST(Gltf, DracoRoundTripMeetsTheBudget) {
  // Draco (the default codec) with a position budget of 1e-4 of the diagonal, sequential
  // connectivity (keeps the point order, so points compare one to one).
  const PolyData bunny = read_ply(isoforge::test::data_path("bunny.ply"));
  const auto dir = scratch("draco");
  GltfWriteOptions o;
  EXPECT_EQ(o.codec, GltfCodec::Draco);
  o.draco.max_position_error_relative = 1e-4;
  o.draco.method = DracoMethod::Sequential;
  const auto stats = write_gltf(bunny, dir / "bunny.glb", o);
  expect_valid(dir / "bunny.glb");
  ASSERT_EQ(stats.draco.size(), 1u);
  const Bounds b = bunny.bounds();
  const double budget = 1e-4 * norm(b.max - b.min);
  EXPECT_LE(stats.draco[0].max_position_error, budget);
  EXPECT_LT(stats.bytes,
            write_gltf(bunny, dir / "meshopt.glb", with_codec(GltfCodec::Meshopt)).bytes);
  const PolyData back = read_gltf(dir / "bunny.glb").meshes.at(0).mesh;
  ASSERT_EQ(back.num_points(), bunny.num_points());
  EXPECT_EQ(back.polys.size(), 69451u - stats.draco[0].lost_triangles);
  EXPECT_EQ(stats.draco[0].lost_triangles, 0u);  // the budget refines until none is lost
  double worst = 0;
  for (std::size_t i = 0; i < bunny.num_points(); ++i)
    worst = std::max(worst, norm(back.points[i] - bunny.points[i]));
  EXPECT_LE(worst, budget);
  EXPECT_NE(back.point_data.find("confidence"), nullptr);  // names kept
  EXPECT_NE(back.point_data.find("intensity"), nullptr);

  // Lines and points stay plain beside the Draco triangles; colours and names survive.
  const PolyData pd = sample_mesh();
  const auto s2 = write_gltf(pd, dir / "tiny.glb", GltfWriteOptions{});
  expect_valid(dir / "tiny.glb");
  EXPECT_EQ(s2.triangles, 2u);
  const PolyData tiny = read_gltf(dir / "tiny.glb").meshes.at(0).mesh;
  EXPECT_EQ(tiny.polys.size(), 2u);
  EXPECT_EQ(tiny.lines.size(), 2u);
  EXPECT_EQ(tiny.verts.size(), 1u);
  for (const char* name : {"Elevation", "Velocity", "Label", "Colors"}) {
    EXPECT_NE(tiny.point_data.find(name), nullptr) << name;
  }
}

// The transfer formats on the kinds of data the project ships: a scan (bunny), a textured mesh
// (fran_cut), a quad mesh (Torso), a CT isosurface (headsq) and the Lorenz attractor surface.
// Draco with a budget of 1e-4 of the diagonal (sequential: points compared one to one), and
// .glb with each codec: counts, array names and values within the budget, every file valid.
TEST(Gltf, SharedDataRoundTripsThroughDracoAndGlb) {
  std::vector<std::pair<std::string, PolyData>> inputs;
  for (const char* name : {"bunny.ply", "fran_cut.vtk", "Torso.vtp"}) {
    inputs.emplace_back(name, std::get<PolyData>(read(isoforge::test::data_path(name))));
  }
  {
    const Dataset head = read(isoforge::test::data_path("headsq/quarter.nhdr"));
    ContourOptions co;
    co.values = {1150};
    co.flip = true;
    inputs.emplace_back("headsq skin", contour(head, co).output);
  }
  {
    AttractorOptions ao;
    ao.trajectory.steps = 400'000;
    ao.trajectory.dims = {48, 48, 48};
    ao.value = 5;
    inputs.emplace_back("attractor", lorenz_attractor(ao).output.surface);
  }
  const auto dir = scratch("shared");
  for (const auto& input : inputs) {
    const PolyData& mesh = input.second;
    SCOPED_TRACE(input.first);
    ASSERT_GT(mesh.polys.size(), 100u);
    const std::size_t triangles = triangulate_faces(mesh).size();
    const Bounds b = mesh.bounds();
    const double budget = 1e-4 * norm(b.max - b.min);
    auto same_names = [&](const PolyData& back) {
      for (std::size_t a = 0; a < mesh.point_data.size(); ++a) {
        const DataArray& in = mesh.point_data[a];
        const DataArray* out = back.point_data.find(in.name());
        ASSERT_NE(out, nullptr) << in.name();
        EXPECT_EQ(out->components(), in.components()) << in.name();
      }
    };

    DracoWriteOptions d;
    d.max_position_error_relative = 1e-4;
    d.method = DracoMethod::Sequential;
    const DracoStats ds = write_draco(mesh, dir / "m.drc", d);
    const PolyData drc = read_draco(dir / "m.drc");
    ASSERT_EQ(drc.num_points(), mesh.num_points());
    EXPECT_EQ(drc.polys.size(), triangles - ds.lost_triangles);
    EXPECT_EQ(ds.lost_triangles, ds.degenerate_input_triangles);
    double worst = 0;
    for (std::size_t i = 0; i < mesh.num_points(); ++i) {
      worst = std::max(worst, norm(drc.points[i] - mesh.points[i]));
    }
    EXPECT_LE(worst, budget);
    EXPECT_GT(worst, 0.0);  // quantized, not stored exactly
    same_names(drc);

    GltfWriteOptions g;
    g.draco.max_position_error_relative = 1e-4;
    const auto gs = write_gltf(mesh, dir / "m.glb", g);
    expect_valid(dir / "m.glb");
    ASSERT_EQ(gs.draco.size(), 1u);
    EXPECT_LE(gs.draco[0].max_position_error, budget);
    const PolyData glb = read_gltf(dir / "m.glb").meshes.at(0).mesh;
    EXPECT_EQ(glb.polys.size(), triangles - gs.draco[0].lost_triangles);
    same_names(glb);

    for (GltfCodec codec : {GltfCodec::Meshopt, GltfCodec::None}) {
      write_gltf(mesh, dir / "l.glb", with_codec(codec));
      expect_valid(dir / "l.glb");
      const PolyData exact = read_gltf(dir / "l.glb").meshes.at(0).mesh;
      ASSERT_EQ(exact.num_points(), mesh.num_points());
      for (std::size_t i = 0; i < mesh.num_points(); ++i) {
        ASSERT_EQ(exact.points[i], mesh.points[i]) << i;
      }
      EXPECT_EQ(exact.polys.size(), triangles);
      same_names(exact);
    }
  }
}

TEST(Gltf, DispatchByExtension) {
  const PolyData pd = sample_mesh();
  const auto path = scratch("dispatch") / "x.glb";
  EXPECT_EQ(format_from_path(path), FileFormat::Glb);
  WriteOptions o;
  o.gltf_codec = GltfCodec::Meshopt;
  write(pd, path, o);
  expect_valid(path);
  const PolyData back = std::get<PolyData>(read(path));
  EXPECT_EQ(back.num_points(), 7u);
  EXPECT_EQ(back.polys.size(), 2u);
  EXPECT_THROW(write(ImageData{}, path), Error);  // polydata only
}

TEST(Gltf, BadInputsAreErrors) {
  const auto dir = scratch("bad");
  PolyData empty;
  EXPECT_THROW((void)write_gltf(empty, dir / "e.glb", kPlain), Error);
  PolyData nan = sample_mesh();
  nan.points.set(2, Vec3{0, std::nan(""), 0});
  try {
    (void)write_gltf(nan, dir / "n.glb", kPlain);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 2 has a non-finite coordinate"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "n.glb"));
  // Finite doubles that float32 cannot hold: the first such point is named, past many others.
  PolyData huge;
  huge.points = Points(100000, ScalarType::Float64);
  huge.points.set(70001, Vec3{0, 1e300, 0});
  huge.points.set(90000, Vec3{-1e300, 0, 0});
  huge.verts.add({0});
  try {
    (void)write_gltf(huge, dir / "h.glb", kPlain);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 70001 is beyond the float32 range"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "h.glb"));
  const PolyData good_mesh = sample_mesh();
  GltfMesh bad_colors{"m", good_mesh, std::nullopt, "Elevation"};  // a float array
  EXPECT_THROW((void)write_gltf(std::span(&bad_colors, 1), dir / "c.glb", kPlain), Error);
  EXPECT_THROW((void)gltf_codec_from_name("zip"), Error);

  auto expect_read_error = [](std::vector<std::byte> bytes, const std::string& part) {
    try {
      (void)read_gltf(bytes, "f.glb");
      ADD_FAILURE() << "no error for '" << part << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  (void)write_gltf(sample_mesh(), dir / "ok.glb", kPlain);
  const auto good = read_file_bytes(dir / "ok.glb");
  expect_read_error({good.begin(), good.begin() + 10}, "f.glb: byte 4: truncated");
  auto magic = good;
  magic[0] = std::byte{'x'};
  expect_read_error(magic, "not a binary glTF");
  expect_read_error({good.begin(), good.end() - 40}, "truncated: the header says");
}

TEST(Gltf, CorruptFilesGiveErrorsOnly) {
  // Random damage to plain and meshopt files: an Error or a valid result, nothing else.
  const auto dir = scratch("fuzz");
  (void)write_gltf(sample_mesh(), dir / "a.glb", kPlain);
  (void)write_gltf(sample_mesh(), dir / "b.glb", with_codec(GltfCodec::Meshopt));
  (void)write_gltf(sample_mesh(), dir / "c.glb", with_codec(GltfCodec::Draco));
  std::mt19937 rng(13);
  int rejected = 0;
  for (const char* f : {"a.glb", "b.glb", "c.glb"}) {
    const auto good = read_file_bytes(dir / f);
    for (int i = 0; i < 300; ++i) {
      const auto bad = isoforge::test::mutate(good, rng, 1 + i % 4, "{}[]\":,0123456789");
      rejected += isoforge::test::rejects_only_with_error(
          [](const std::vector<std::byte>& b) { return read_gltf(b, "fuzz.glb"); }, bad, f);
      // The summary of `info` (its own pass over the same structure) accepts or rejects the
      // same files; where both accept, it describes what read() gives.
      const fs::path damaged = dir / "damaged.glb";
      {
        std::ofstream out(damaged, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bad.data()),
                  static_cast<std::streamsize>(bad.size()));
      }
      std::optional<DatasetSummary> summary, of_read;
      try {
        summary = summarize_file(damaged);
      } catch (const Error&) {
      }
      try {
        of_read = summarize(read(damaged));
      } catch (const Error&) {
      }
      ASSERT_EQ(summary.has_value(), of_read.has_value()) << f << " mutation " << i;
      if (summary) {
        EXPECT_EQ(summary->points, of_read->points);
        EXPECT_EQ(summary->cell_types, of_read->cell_types);
      }
    }
  }
  EXPECT_GT(rejected, 0);
}

}  // namespace
