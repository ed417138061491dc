#include "support/result.hpp"
#include "support/surface_checks.hpp"
#include "isoforge/contour/contour_sparse.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/implicit/sample_sparse.hpp"
#include "isoforge/sparse/convert.hpp"
#include "isoforge/sparse/grid.hpp"

using namespace isoforge;
using isoforge::test::cube_grid;
using isoforge::test::expect_closed_manifold;
using isoforge::test::signed_volume;
using F = ImplicitFunction;

namespace {


GridSpec cone_grid(Index nx) {
  // The ice cream cone's natural bounds [-0.1, 2.0] x [-0.7, 0.7]², cubic voxels.
  const double h = 2.1 / static_cast<double>(nx - 1);
  GridSpec g;
  g.origin = {-0.1, -0.7, -0.7};
  g.spacing = {h, h, h};
  const auto ny = static_cast<Index>(std::floor(1.4 / h)) + 1;
  g.dims = {nx, ny, ny};
  return g;
}

using P3 = std::array<float, 3>;

P3 point_of(const PolyData& pd, Index id) {
  const auto f = pd.points.floats();
  const auto i = static_cast<std::size_t>(id);
  return {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
}

// Points with their scalar value (and normal when present), sorted.
std::vector<std::array<float, 7>> point_records(const PolyData& pd) {
  const DataArray* s = pd.point_data.scalars();
  const DataArray* n = pd.point_data.find("Normals");
  std::vector<std::array<float, 7>> r(pd.points.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    const P3 p = point_of(pd, static_cast<Index>(i));
    r[i] = {p[0], p[1], p[2], s ? s->values<float>()[i] : 0.0f, 0, 0, 0};
    if (n) {
      for (std::size_t c = 0; c < 3; ++c) r[i][4 + c] = n->values<float>()[3 * i + c];
    }
  }
  std::sort(r.begin(), r.end());
  return r;
}

// Triangles as coordinate triples, rotated to start at their smallest point (keeps orientation),
// sorted.
std::vector<std::array<P3, 3>> triangle_records(const PolyData& pd) {
  std::vector<std::array<P3, 3>> r;
  r.reserve(pd.polys.size());
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    EXPECT_EQ(ids.size(), 3u);
    std::array<P3, 3> t = {point_of(pd, ids[0]), point_of(pd, ids[1]), point_of(pd, ids[2])};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    r.push_back(t);
  }
  std::sort(r.begin(), r.end());
  return r;
}

// Same points (coordinates, values, normals), same oriented triangles.
void expect_same_surface(const PolyData& sparse, const PolyData& dense, const std::string& what) {
  ASSERT_GT(dense.polys.size(), 0u) << what;
  EXPECT_EQ(sparse.points.size(), dense.points.size()) << what;
  EXPECT_EQ(sparse.polys.size(), dense.polys.size()) << what;
  const auto ps = point_records(sparse), pd = point_records(dense);
  EXPECT_TRUE(ps == pd) << what << ": point sets differ";
  const auto ts = triangle_records(sparse), td = triangle_records(dense);
  EXPECT_TRUE(ts == td) << what << ": triangle sets differ";
}


void expect_closed_genus(const PolyData& pd, long genus, const std::string& what) {
  const SurfaceTopology t = analyze_topology(pd);
  EXPECT_EQ(t.border_edges, 0u) << what;
  EXPECT_EQ(t.non_manifold_edges, 0u) << what;
  EXPECT_EQ(t.non_manifold_vertices, 0u) << what;
  EXPECT_EQ(t.inconsistent_edges, 0u) << what;
  EXPECT_EQ(t.repeated_vertex_faces, 0u) << what;
  EXPECT_EQ(t.vertices, pd.points.size()) << what;  // every point is used
  ASSERT_EQ(t.components.size(), 1u) << what;
  EXPECT_TRUE(t.components[0].closed) << what;
  if (genus >= 0) {
    EXPECT_EQ(t.components[0].genus, genus) << what;
  }
}

struct Shape {
  const char* name;
  F f;
  GridSpec grid;
  long genus;  // -1: not checked
};

std::vector<Shape> shapes() {
  GridSpec offset = cube_grid(-1, 1, 57);
  offset.origin = {-1.013, -0.987, -1.021};  // leaves straddle the surface differently
  return {
      {"ice cream cone", ice_cream_cone(), cone_grid(81), 0},
      {"ice cream cone fine", ice_cream_cone(), cone_grid(150), 0},
      {"sphere", F::sphere({0.03, -0.02, 0.01}, 0.71), cube_grid(-1, 1, 61), 0},
      {"torus", F::torus({0, 0, 0}, {0, 0, 1}, 0.55, 0.22), cube_grid(-1, 1, 73), 1},
      {"tilted torus", F::torus({0.02, 0.01, 0}, {0, 1, 1}, 0.5, 0.2), offset, 1},
  };
}

// A smooth density blob (two Gaussians) on an image with dyadic origin and spacing; values below
// 1e-3 are exactly 0 (the background, so they stay inactive in the grid).
ImageData blob_image() {
  ImageData img;
  img.dims = {48, 40, 44};
  img.origin = {-1.5, -1.25, -1.375};
  img.spacing = {0.0625, 0.0625, 0.0625};
  std::vector<float> v(static_cast<std::size_t>(48 * 40 * 44));
  for (Index k = 0; k < img.dims[2]; ++k)
    for (Index j = 0; j < img.dims[1]; ++j)
      for (Index i = 0; i < img.dims[0]; ++i) {
        const Vec3 p = img.point(i, j, k);
        const Vec3 a = p - Vec3{-0.3, 0.0, 0.05}, b = p - Vec3{0.35, 0.1, -0.1};
        double d = std::exp(-dot(a, a) / 0.18) + 0.8 * std::exp(-dot(b, b) / 0.1);
        if (d < 1e-3) d = 0;
        v[static_cast<std::size_t>(i + 48 * (j + 40 * k))] = static_cast<float>(d);
      }
  img.point_data.add(DataArray::from_vector<float>("density", 1, std::move(v)),
                     AttributeRole::Scalars);
  return img;
}

}  // namespace

TEST(ContourSparse, LevelSetsMatchTheDenseContourExactly) {
  for (const Shape& s : shapes()) {
    const ImageData dense = sample_image(s.f, s.grid);
    const auto grid = sample_level_set(s.f, s.grid).output;
    VdbContourStats st;
    const PolyData sp = test::split_result(contour_vdb(*grid, {}), st);
    ContourStats dst;
    const PolyData dn = test::split_result(contour_image(dense, {}), dst);
    expect_same_surface(sp, dn, s.name);
    EXPECT_EQ(st.skipped_cells, 0u) << s.name;
    EXPECT_EQ(st.ambiguous_faces, dst.ambiguous_faces) << s.name;
    EXPECT_EQ(st.leaves, static_cast<std::size_t>(grid->tree().leafCount())) << s.name;
    EXPECT_GE(st.blocks, st.leaves) << s.name;
    EXPECT_EQ(sp.point_data.scalars()->name(), "Scalars");
    expect_closed_genus(sp, s.genus, s.name);
    EXPECT_GT(signed_volume(sp), 0) << s.name << ": level sets are oriented outward";
  }
}

TEST(ContourSparse, FlipOrientsInwardAndMatchesTheDenseFlip) {
  const F torus = F::torus({0, 0, 0}, {1, 0, 0}, 0.5, 0.25);
  const GridSpec g = cube_grid(-1, 1, 49);
  ContourOptions o;
  o.flip = true;
  o.normals = ContourNormals::Triangles;
  const PolyData sp = contour_vdb(*sample_level_set(torus, g).output, o).output;
  const PolyData dn = contour_image(sample_image(torus, g), o).output;
  expect_closed_genus(sp, 1, "flipped torus");
  EXPECT_LT(signed_volume(sp), 0);
  // Triangle normals are computed from the same triangles in another order: compare loosely.
  const auto ps = point_records(sp), pd = point_records(dn);
  ASSERT_EQ(ps.size(), pd.size());
  for (std::size_t i = 0; i < ps.size(); ++i) {
    for (std::size_t c = 0; c < 4; ++c) ASSERT_EQ(ps[i][c], pd[i][c]);
    for (std::size_t c = 4; c < 7; ++c) ASSERT_NEAR(ps[i][c], pd[i][c], 1e-5);
  }
  EXPECT_TRUE(triangle_records(sp) == triangle_records(dn));
}

TEST(ContourSparse, GradientNormalsPointOutwardOnLevelSets) {
  const Vec3 c{0.05, 0, -0.03};
  const GridSpec g = cube_grid(-1, 1, 41);
  for (bool flip : {false, true}) {
    ContourOptions o;
    o.normals = ContourNormals::Gradient;
    o.flip = flip;
    const PolyData pd = contour_vdb(*sample_level_set(F::sphere(c, 0.6), g).output, o).output;
    const DataArray* n = pd.point_data.find("Normals");
    ASSERT_NE(n, nullptr);
    ASSERT_GT(pd.points.size(), 0u);
    for (std::size_t i = 0; i < pd.points.size(); ++i) {
      const auto v = n->values<float>();
      const Vec3 nv{v[3 * i], v[3 * i + 1], v[3 * i + 2]};
      const Vec3 r = (pd.points[i] - c) / norm(pd.points[i] - c);
      EXPECT_NEAR(norm(nv), 1.0, 1e-5);
      EXPECT_GT(flip ? -dot(nv, r) : dot(nv, r), 0.98) << i;
    }
  }
}

TEST(ContourSparse, FogVolumeMatchesTheDenseContourOfItsImage) {
  const auto grid = image_to_vdb(blob_image());
  ASSERT_EQ(grid->getName(), "density");
  const ImageData dense = vdb_to_image(*grid);
  for (double iso : {0.5, 0.25, 0.7}) {
    for (bool flip : {false, true}) {
      ContourOptions o;
      o.values = {iso};
      o.flip = flip;
      o.normals = ContourNormals::Gradient;
      const PolyData sp = contour_vdb(*grid, o).output;
      const PolyData dn = contour_image(dense, o).output;
      const std::string what = "blob at " + std::to_string(iso) + (flip ? " flipped" : "");
      expect_same_surface(sp, dn, what);  // including the gradient normals
      EXPECT_EQ(sp.point_data.scalars()->name(), "density");
      const SurfaceTopology t = analyze_topology(sp);
      EXPECT_TRUE(t.closed() && t.manifold() && t.oriented()) << what;
      // High values inside: the surface faces inward unless flipped.
      EXPECT_EQ(signed_volume(sp) > 0, flip) << what;
    }
  }
}

TEST(ContourSparse, RandomFieldsMatchTheDenseContourInEveryCase) {
  // Noise exercises every cube case, both resolutions of ambiguous faces, cell-interior points
  // and edges shared across leaf boundaries; quantized values hit the isovalues exactly. The
  // image's boundary layer is below every isovalue and so is the background outside it.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  ImageData img;
  img.dims = {37, 29, 33};
  img.origin = {-2.0, 0.5, -4.25};
  img.spacing = {0.25, 0.25, 0.25};
  std::vector<float> v(static_cast<std::size_t>(37 * 29 * 33));
  for (Index k = 0; k < 33; ++k)
    for (Index j = 0; j < 29; ++j)
      for (Index i = 0; i < 37; ++i) {
        const bool border = i == 0 || j == 0 || k == 0 || i == 36 || j == 28 || k == 32;
        float x = u(rng);
        if (i % 3 == 0) x = std::round(x * 4) / 4;  // often exactly 0, 0.25, ...
        v[static_cast<std::size_t>(i + 37 * (j + 29 * k))] = border ? -1.0f : x;
      }
  img.point_data.add(DataArray::from_vector<float>("noise", 1, std::move(v)),
                     AttributeRole::Scalars);
  const auto grid = image_to_vdb(img, {"", -10.0f});
  const ImageData dense = vdb_to_image(*grid);
  ASSERT_EQ(dense.dims, img.dims);
  ContourOptions o;
  o.values = {0.0, 0.25, -0.3};
  VdbContourStats st;
  ContourStats dst;
  const PolyData sp = test::split_result(contour_vdb(*grid, o), st);
  const PolyData dn = test::split_result(contour_image(dense, o), dst);
  EXPECT_GT(st.ambiguous_faces, 1000u);
  EXPECT_EQ(st.ambiguous_faces, dst.ambiguous_faces);
  expect_same_surface(sp, dn, "noise");
  const SurfaceTopology t = analyze_topology(sp);
  EXPECT_TRUE(t.closed() && t.manifold() && t.oriented());

  // The same voxels at negative index coordinates, not aligned with the previous leaves, with
  // the translation compensating: the same surface.
  const openvdb::Coord shift(-1003, -517, -21);
  auto moved = openvdb::FloatGrid::create(-10.0f);
  moved->setName("noise");
  for (auto it = grid->cbeginValueOn(); it; ++it)
    moved->tree().setValue(it.getCoord() + shift, *it);
  moved->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  moved->transform().postTranslate(
      openvdb::Vec3d(-2.0 + 1003 * 0.25, 0.5 + 517 * 0.25, -4.25 + 21 * 0.25));
  ASSERT_EQ(moved->evalActiveVoxelBoundingBox().min(), openvdb::Coord(-1003, -517, -21));
  expect_same_surface(contour_vdb(*moved, o).output, dn, "noise at negative coordinates");
}

TEST(ContourSparse, TilesContributeTheirValues) {
  // A box of 1 surrounded by a layer of 0.2, with unaligned faces: its inside becomes tiles
  // (pruned constant leaves), read through the accessor by the neighbouring cells.
  ImageData img;
  img.dims = {48, 48, 48};
  img.spacing = {0.5, 0.5, 0.5};
  std::vector<float> v(48 * 48 * 48, 0.0f);
  for (int k = 3; k < 43; ++k)
    for (int j = 3; j < 43; ++j)
      for (int i = 3; i < 43; ++i) {
        const bool in = i >= 4 && i < 42 && j >= 4 && j < 42 && k >= 4 && k < 42;
        v[static_cast<std::size_t>(i + 48 * (j + 48 * k))] = in ? 1.0f : 0.2f;
      }
  img.point_data.add(DataArray::from_vector<float>("box", 1, std::move(v)), AttributeRole::Scalars);
  const auto grid = image_to_vdb(img);
  EXPECT_GT(grid->tree().activeTileCount(), 0u);
  ContourOptions o;
  o.values = {0.5};
  VdbContourStats st;
  const PolyData sp = test::split_result(contour_vdb(*grid, o), st);
  expect_same_surface(sp, contour_image(vdb_to_image(*grid), o).output, "box");
  EXPECT_EQ(st.skipped_cells, 0u);
  expect_closed_genus(sp, 0, "box");
}

TEST(ContourSparse, TilesStraddlingTheIsovalueAreLeftOut) {
  // An active tile of 1 beside the background 0, with one leaf touching it: the cells between
  // the tile and the background are not visited, those beside the leaf are skipped.
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->tree().addTile(1, openvdb::Coord(0, 0, 0), 1.0f, true);
  grid->tree().setValue(openvdb::Coord(3, 3, 8), 1.0f);  // a leaf above the tile
  VdbContourStats st;
  ContourOptions o;
  o.values = {0.5};
  const PolyData pd = test::split_result(contour_vdb(*grid, o), st);
  EXPECT_GT(st.skipped_cells, 0u);
  EXPECT_EQ(analyze_topology(pd).vertices, pd.points.size());
}

TEST(ContourSparse, DeterministicForAnyThreadCount) {
  const F f = F::torus({0, 0, 0}, {0, 1, 1}, 0.5, 0.2) | F::sphere({0.3, 0.2, 0.1}, 0.35);
  const auto grid = sample_level_set(f, cube_grid(-1, 1, 97)).output;
  ContourOptions o;
  o.values = {-0.02, 0.0, 0.03};
  o.normals = ContourNormals::Gradient;
  PolyData one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = contour_vdb(*grid, o).output;
  }
  for (std::size_t threads : {2u, 4u}) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    const PolyData many = contour_vdb(*grid, o).output;
    ASSERT_GT(one.points.size(), 0u);
    EXPECT_TRUE(std::ranges::equal(one.points.floats(), many.points.floats()));
    EXPECT_TRUE(std::ranges::equal(one.polys.connectivity(), many.polys.connectivity()));
    ASSERT_EQ(one.point_data.size(), many.point_data.size());
    for (std::size_t a = 0; a < one.point_data.size(); ++a) {
      EXPECT_EQ(one.point_data[a].name(), many.point_data[a].name());
      EXPECT_EQ(one.point_data[a].size_bytes(), many.point_data[a].size_bytes());
      EXPECT_TRUE(std::equal(one.point_data[a].bytes(),
                             one.point_data[a].bytes() + one.point_data[a].size_bytes(),
                             many.point_data[a].bytes()));
    }
  }
}

TEST(ContourSparse, MultipleIsovaluesAreTaggedAndEqualSeparateRuns) {
  const F sphere = F::sphere({0, 0, 0}, 0.6);
  SparseSampleOptions so;
  so.half_width = 4;
  const auto grid = sample_level_set(sphere, cube_grid(-1, 1, 45), so).output;
  ContourOptions o;
  o.values = {-0.05, 0.0, 0.07};
  VdbContourStats st;
  const PolyData all = test::split_result(contour_vdb(*grid, o), st);
  const auto index = all.point_data.get("IsovalueIndex").values<std::int32_t>();
  std::size_t at = 0, tris = 0;
  for (std::size_t v = 0; v < o.values.size(); ++v) {
    ContourOptions one;
    one.values = {o.values[v]};
    const PolyData part = contour_vdb(*grid, one).output;
    ASSERT_GT(part.points.size(), 0u);
    for (std::size_t i = 0; i < part.points.size(); ++i) {
      ASSERT_EQ(index[at + i], static_cast<std::int32_t>(v));
      ASSERT_EQ(all.points[at + i], part.points[i]);
    }
    at += part.points.size();
    tris += part.polys.size();
    expect_closed_genus(part, 0, "sphere at " + std::to_string(o.values[v]));
  }
  EXPECT_EQ(at, all.points.size());
  EXPECT_EQ(tris, all.polys.size());
  EXPECT_EQ(st.points, all.points.size());
  EXPECT_EQ(st.cells, all.polys.size());
}

TEST(ContourSparse, AttributesFollowTheOptions) {
  auto grid = sample_level_set(F::sphere({0, 0, 0}, 0.5), cube_grid(-1, 1, 33)).output;
  grid->setName("distance");
  ContourOptions o;
  const PolyData with = contour_vdb(*grid, o).output;
  ASSERT_NE(with.point_data.scalars(), nullptr);
  EXPECT_EQ(with.point_data.scalars()->name(), "distance");
  // Zero up to the crossing clamp (1/1024 of an edge whose values differ by at most 2 h).
  for (const float v : with.point_data.scalars()->values<float>()) EXPECT_NEAR(v, 0.0f, 1.3e-4f);
  EXPECT_EQ(with.point_data.find("Normals"), nullptr);
  o.interpolate_attributes = false;
  o.normals = ContourNormals::Triangles;
  const PolyData without = contour_vdb(*grid, o).output;
  EXPECT_EQ(without.point_data.find("distance"), nullptr);
  EXPECT_NE(without.point_data.find("Normals"), nullptr);
  EXPECT_NE(without.point_data.find("IsovalueIndex"), nullptr);
  EXPECT_TRUE(std::ranges::equal(with.points.floats(), without.points.floats()));
}

TEST(ContourSparse, EmptyGridGivesEmptyOutput) {
  const auto grid = openvdb::FloatGrid::create(1.0f);
  VdbContourStats st;
  const PolyData pd = test::split_result(contour_vdb(*grid, {}), st);
  EXPECT_EQ(pd.points.size(), 0u);
  EXPECT_EQ(pd.polys.size(), 0u);
  EXPECT_NE(pd.point_data.find("IsovalueIndex"), nullptr);
  EXPECT_EQ(st.leaves, 0u);
  EXPECT_EQ(st.blocks, 0u);
}

TEST(ContourSparse, BadInputIsAClearError) {
  auto grid = sample_level_set(F::sphere({0, 0, 0}, 0.5), cube_grid(-1, 1, 21)).output;
  ContourOptions o;
  o.values = {};
  EXPECT_THROW((void)contour_vdb(*grid, o), Error);
  o.values = {std::nan("")};
  EXPECT_THROW((void)contour_vdb(*grid, o), Error);
  o.values = {0.0};
  o.array = "other";
  EXPECT_THROW((void)contour_vdb(*grid, o), Error);
  o.array = "Scalars";
  EXPECT_NO_THROW((void)contour_vdb(*grid, o));

  // Non-uniform scale, rotation: errors.
  openvdb::Mat4d m = openvdb::Mat4d::identity();
  m.setToScale(openvdb::Vec3d(0.1, 0.2, 0.1));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
  EXPECT_THROW((void)contour_vdb(*grid), Error);
  auto rotated = openvdb::math::Transform::createLinearTransform(0.1);
  rotated->preRotate(0.3, openvdb::math::Y_AXIS);
  grid->setTransform(rotated);
  EXPECT_THROW((void)contour_vdb(*grid), Error);
}
