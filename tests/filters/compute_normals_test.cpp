#include "isoforge/filters/compute_normals.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "isoforge/core/mesh_topology.hpp"
#include "support/expect_error.hpp"
#include "support/meshes.hpp"
#include "support/surface_checks.hpp"

using namespace isoforge;

namespace {

// The unit cube [0, 1]^3 as 12 triangles on 8 shared points, outward.
PolyData cube() {
  PolyData pd;
  for (int i = 0; i < 8; ++i) {
    pd.points.push_back({static_cast<double>(i & 1), static_cast<double>((i >> 1) & 1),
                         static_cast<double>((i >> 2) & 1)});
  }
  const Index q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    pd.polys.add({f[0], f[1], f[2]});
    pd.polys.add({f[0], f[2], f[3]});
  }
  return pd;
}

void reverse_cell(PolyData& pd, std::size_t c) {
  auto ids = pd.polys.cell(c);
  std::reverse(ids.begin() + 1, ids.end());
}

Vec3 normal_at(const PolyData& pd, std::size_t i) {
  const DataArray& n = pd.point_data.get("Normals");
  return {n.get(i, 0), n.get(i, 1), n.get(i, 2)};
}

}  // namespace

TEST(ComputeNormals, ClosedCubeWithFlippedFacesComesOutOutward) {
  PolyData pd = cube();
  reverse_cell(pd, 1);
  reverse_cell(pd, 6);
  reverse_cell(pd, 7);
  pd.point_data.add(DataArray::from_vector<double>("id", 1, {0, 1, 2, 3, 4, 5, 6, 7}));
  const auto [out, stats] = compute_normals(pd);
  EXPECT_EQ(stats.surfaces, 1u);
  EXPECT_EQ(stats.closed_surfaces, 1u);
  EXPECT_EQ(stats.flipped_polygons, 3u);  // exactly the three reversed ones
  EXPECT_EQ(stats.inconsistent_edges, 0u);
  EXPECT_NEAR(test::signed_volume(out), 1.0, 1e-9);
  // Every edge of a cube is 90 degrees: each corner splits into 3 (one per face), 16 new points.
  EXPECT_EQ(stats.split_points, 16u);
  ASSERT_EQ(out.num_points(), 24u);
  // Split points keep their coordinates and point data; point normals are face normals.
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    const Vec3 p = out.points[i];
    const auto orig = static_cast<std::size_t>(out.point_data.get("id").get(i));
    EXPECT_EQ(p, pd.points[orig]);
    const Vec3 n = normal_at(out, i);
    EXPECT_NEAR(norm(n), 1, 1e-6);
    EXPECT_NEAR(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1, 1e-6);  // axis-aligned
    EXPECT_GT(dot(n, p - Vec3{0.5, 0.5, 0.5}), 0);  // outward
  }
  // Cell normals: the face normals, outward.
  const DataArray& cn = out.cell_data.get("Normals");
  EXPECT_EQ(out.cell_data.active_name(AttributeRole::Normals), "Normals");
  EXPECT_EQ((Vec3{cn.get(0, 0), cn.get(0, 1), cn.get(0, 2)}), (Vec3{0, 0, -1}));
  EXPECT_EQ((Vec3{cn.get(6, 0), cn.get(6, 1), cn.get(6, 2)}), (Vec3{0, 1, 0}));
  // Without splitting, the 8 corners keep their ids and their normals point out of the cube.
  NormalsOptions o;
  o.split = false;
  const auto smooth = compute_normals(pd, o);
  ASSERT_EQ(smooth.output.num_points(), 8u);
  test::expect_closed_manifold(smooth.output, "cube");
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_GT(dot(normal_at(smooth.output, i), pd.points[i] - Vec3{0.5, 0.5, 0.5}), 0.5);
  }
}

TEST(ComputeNormals, InsideOutSphereIsTurnedOutAndSmoothOnesAreNotSplit) {
  PolyData s = test::polar_surface({0, 0, -1}, {0, 0, 1}, 12, 16, [](int i, int j) {
    const double t = std::numbers::pi * i / 12, f = 2 * std::numbers::pi * j / 16;
    return Vec3{std::sin(t) * std::cos(f), std::sin(t) * std::sin(f), -std::cos(t)};
  });
  for (std::size_t c = 0; c < s.polys.size(); ++c) reverse_cell(s, c);
  ASSERT_LT(test::signed_volume(s), 0);
  const auto [out, stats] = compute_normals(s);
  EXPECT_EQ(stats.flipped_polygons, s.polys.size());
  EXPECT_EQ(stats.split_points, 0u);  // neighbouring faces differ by ~15-23 degrees < 30
  EXPECT_GT(test::signed_volume(out), 0);
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    EXPECT_GT(dot(normal_at(out, i), out.points[i]), 0.99);  // the sphere's own normal
  }
  // With a feature angle below the faces' angles every point splits, but the surface stays
  // outward.
  NormalsOptions o;
  o.feature_angle = 5;
  const auto sharp = compute_normals(s, o);
  EXPECT_GT(sharp.stats.split_points, 0u);
  EXPECT_GT(test::signed_volume(sharp.output), 0);
}

TEST(ComputeNormals, OpenSurfaceTakesTheMajorityOrientation) {
  // 3 x 3 quads in the z = 0 plane, counter-clockwise from +z, one reversed.
  PolyData pd;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) pd.points.push_back({static_cast<double>(i), static_cast<double>(j), 0});
  for (Index j = 0; j < 3; ++j)
    for (Index i = 0; i < 3; ++i) pd.polys.add({4 * j + i, 4 * j + i + 1, 4 * j + i + 5, 4 * j + i + 4});
  reverse_cell(pd, 4);
  const auto [out, stats] = compute_normals(pd);
  EXPECT_EQ(stats.closed_surfaces, 0u);
  EXPECT_EQ(stats.flipped_polygons, 1u);
  EXPECT_EQ(stats.split_points, 0u);
  for (std::size_t i = 0; i < out.num_points(); ++i) EXPECT_EQ(normal_at(out, i), (Vec3{0, 0, 1}));
  // flip reverses everything afterwards.
  NormalsOptions o;
  o.flip = true;
  const auto flipped = compute_normals(pd, o);
  EXPECT_EQ(flipped.stats.flipped_polygons, 8u);
  for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(normal_at(flipped.output, i), (Vec3{0, 0, -1}));
  // Without consistency the reversed quad stays, its normal opposes its neighbours', and its
  // edges are sharp (180 degrees): its 4 corners get copies.
  o = {};
  o.consistency = false;
  const auto raw = compute_normals(pd, o);
  EXPECT_EQ(raw.stats.flipped_polygons, 0u);
  EXPECT_EQ(raw.stats.split_points, 4u);
}

TEST(ComputeNormals, TwoSurfacesNonManifoldEdgesAndMobius) {
  PolyData two = cube();
  PolyData other = cube();
  for (std::size_t c = 0; c < other.polys.size(); ++c) reverse_cell(other, c);
  for (std::size_t i = 0; i < 8; ++i) two.points.push_back(other.points[i] + Vec3{3, 0, 0});
  for (std::size_t c = 0; c < other.polys.size(); ++c) {
    const auto ids = other.polys.cell(c);
    two.polys.add({ids[0] + 8, ids[1] + 8, ids[2] + 8});
  }
  const auto a = compute_normals(two);
  EXPECT_EQ(a.stats.surfaces, 2u);
  EXPECT_EQ(a.stats.closed_surfaces, 2u);
  EXPECT_EQ(a.stats.flipped_polygons, 12u);
  EXPECT_NEAR(test::signed_volume(a.output), 2.0, 1e-9);
  // Three triangles on one edge: a non-manifold edge, never crossed.
  PolyData fin;
  fin.points.push_back({0, 0, 0});
  fin.points.push_back({0, 0, 1});
  fin.points.push_back({1, 0, 0});
  fin.points.push_back({0, 1, 0});
  fin.points.push_back({-1, -1, 0});
  fin.polys.add({0, 1, 2});
  fin.polys.add({0, 1, 3});
  fin.polys.add({0, 1, 4});
  const auto b = compute_normals(fin);
  EXPECT_EQ(b.stats.non_manifold_edges, 1u);
  EXPECT_EQ(b.stats.surfaces, 3u);
  // A Möbius strip of 6 quads cannot be oriented: one edge stays inconsistent.
  PolyData mobius;
  const int n = 6;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n, h = t / 2;
    const Vec3 c{std::cos(t), std::sin(t), 0};
    const Vec3 d{std::cos(h) * std::cos(t), std::cos(h) * std::sin(t), std::sin(h)};
    mobius.points.push_back(c - d * 0.3);
    mobius.points.push_back(c + d * 0.3);
  }
  for (Index i = 0; i < n; ++i) {
    const Index a0 = 2 * i, a1 = 2 * i + 1;
    Index b0 = 2 * ((i + 1) % n), b1 = b0 + 1;
    if (i == n - 1) std::swap(b0, b1);  // the half twist
    mobius.polys.add({a0, b0, b1, a1});
  }
  const auto m = compute_normals(mobius);
  EXPECT_EQ(m.stats.surfaces, 1u);
  EXPECT_EQ(m.stats.inconsistent_edges, 1u);
}

TEST(ComputeNormals, StripsBecomeTrianglesAndOtherCellsStay) {
  PolyData pd;
  for (int i = 0; i < 5; ++i) pd.points.push_back({static_cast<double>(i / 2), static_cast<double>(i % 2), 0});
  pd.verts.add({0});
  pd.lines.add({0, 1});
  pd.strips.add({0, 1, 2, 3, 4});  // 3 triangles, alternating order in the strip
  pd.cell_data.add(DataArray::from_vector<std::int32_t>("c", 1, {7, 8, 9}));
  const auto [out, stats] = compute_normals(pd);
  EXPECT_EQ(out.strips.size(), 0u);
  EXPECT_EQ(out.polys.size(), 3u);
  EXPECT_EQ(out.verts.size(), 1u);
  EXPECT_EQ(out.lines.size(), 1u);
  ASSERT_EQ(out.cell_data.get("c").tuples(), 5u);
  EXPECT_EQ(out.cell_data.get("c").get(4), 9.0);
  EXPECT_EQ(out.cell_data.get("c").get(1), 8.0);
  const DataArray& cn = out.cell_data.get("Normals");
  EXPECT_EQ((Vec3{cn.get(0, 0), cn.get(0, 1), cn.get(0, 2)}), (Vec3{0, 0, 0}));  // the vertex
  const double z = cn.get(2, 2);
  EXPECT_NEAR(std::abs(z), 1, 1e-12);
  EXPECT_EQ(cn.get(3, 2), z);
  EXPECT_EQ(cn.get(4, 2), z);
  EXPECT_EQ(stats.flipped_polygons, 0u);  // the strip's triangles already agree
  EXPECT_NO_THROW(out.validate());
}

TEST(ComputeNormals, FeatureAngleOutOfRangeIsAnError) {
  NormalsOptions o;
  o.feature_angle = 200;
  test::expect_error([&] { (void)compute_normals(cube(), o); }, "feature angle must be in [0, 180]");
  o.feature_angle = std::nan("");
  test::expect_error([&] { (void)compute_normals(cube(), o); }, "feature angle");
}
