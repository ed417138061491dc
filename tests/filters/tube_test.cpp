#include "isoforge/filters/tube.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "isoforge/core/mesh_topology.hpp"
#include "support/expect_error.hpp"
#include "support/surface_checks.hpp"

using namespace isoforge;

namespace {

double polygon_area(int r, double R) { return 0.5 * r * R * R * std::sin(2 * std::numbers::pi / r); }

// The same triangles on points merged by exact position (caps are copies of the end rings).
PolyData merged(const PolyData& pd) {
  std::map<std::tuple<double, double, double>, Index> ids;
  std::vector<Index> map(pd.num_points());
  PolyData m;
  for (std::size_t i = 0; i < pd.num_points(); ++i) {
    const Vec3 p = pd.points[i];
    const auto [it, fresh] = ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<Index>(m.num_points()));
    if (fresh) m.points.push_back(p);
    map[i] = it->second;
  }
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto v = pd.polys.cell(c);
    m.polys.add({map[static_cast<std::size_t>(v[0])], map[static_cast<std::size_t>(v[1])],
                 map[static_cast<std::size_t>(v[2])]});
  }
  return m;
}

PolyData polyline(const std::vector<Vec3>& pts) {
  PolyData pd;
  std::vector<Index> ids;
  for (const Vec3& p : pts) {
    ids.push_back(static_cast<Index>(pd.num_points()));
    pd.points.push_back(p);
  }
  pd.lines.add(ids);
  return pd;
}

Vec3 normal_at(const PolyData& pd, std::size_t i) {
  const DataArray& n = pd.point_data.get("Normals");
  return {n.get(i, 0), n.get(i, 1), n.get(i, 2)};
}

}  // namespace

TEST(Tube, StraightCappedTubeIsAClosedPrism) {
  const PolyData line = polyline({{0, 0, 0}, {2, 0, 0}, {4, 0, 0}});
  TubeOptions o;
  o.radius = 0.5;
  o.sides = 8;
  const auto [out, stats] = tube(line, o);
  EXPECT_EQ(stats.tubes, 1u);
  ASSERT_EQ(out.num_points(), 3u * 8 + 2 * 8);       // 3 rings + 2 cap rings
  ASSERT_EQ(out.polys.size(), 2u * 8 * 2 + 2 * 6);   // 2 segments of 16, 2 caps of 6
  const PolyData m = merged(out);
  EXPECT_EQ(m.num_points(), 24u);
  test::expect_closed_manifold(m, "capped tube");
  EXPECT_NEAR(test::signed_volume(m), polygon_area(8, 0.5) * 4, 1e-5);  // outward
  for (std::size_t i = 0; i < 24; ++i) {
    const Vec3 p = out.points[i];
    EXPECT_NEAR(std::hypot(p.y, p.z), 0.5, 1e-6);
    const Vec3 n = normal_at(out, i);
    EXPECT_NEAR(n.x, 0, 1e-6);
    EXPECT_NEAR(dot(n, Vec3{0, p.y, p.z}), 0.5, 1e-6);  // radial, unit
    // No twist: ring point j lies at the same angle on every ring.
    EXPECT_NEAR(norm(Vec3{0, p.y, p.z} - Vec3{0, out.points[i % 8].y, out.points[i % 8].z}), 0, 1e-6);
  }
  EXPECT_EQ(normal_at(out, 24), (Vec3{-1, 0, 0}));  // start cap
  EXPECT_EQ(normal_at(out, 39), (Vec3{1, 0, 0}));   // end cap
  EXPECT_NO_THROW(out.validate());
  // Without caps: the two end rings are borders.
  o.capping = false;
  const auto open = tube(line, o).output;
  EXPECT_EQ(open.num_points(), 24u);
  EXPECT_EQ(open.polys.size(), 32u);
  EXPECT_EQ(analyze_topology(open).border_edges, 16u);
}

TEST(Tube, HelixStaysClosedAndRoundAndCarriesAttributes) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.2 * i;
    pts.push_back({std::cos(t), std::sin(t), 0.1 * t});
  }
  PolyData helix = polyline(pts);
  DataArray s("s", ScalarType::Float64, 1, pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) s.set(i, 0, static_cast<double>(i));
  helix.point_data.add(std::move(s));
  helix.cell_data.add(DataArray::from_vector<std::int32_t>("line", 1, {42}));
  TubeOptions o;
  o.radius = 0.05;
  o.sides = 6;
  const auto [out, stats] = tube(helix, o);
  ASSERT_EQ(out.num_points(), 61u * 6 + 12);
  const PolyData m = merged(out);
  test::expect_closed_manifold(m, "helix tube");
  EXPECT_GT(test::signed_volume(m), 0);
  for (std::size_t i = 0; i < 61 * 6; ++i) {
    const auto line_point = static_cast<std::size_t>(out.point_data.get("s").get(i));
    EXPECT_EQ(line_point, i / 6);
    EXPECT_NEAR(norm(out.points[i] - pts[line_point]), 0.05, 1e-6);
  }
  EXPECT_EQ(out.cell_data.get("line").tuples(), out.polys.size());
  EXPECT_EQ(out.cell_data.get("line").get(100), 42.0);
}

TEST(Tube, RadiusByScalarMapsTheRangeToRadiusMaxRadius) {
  PolyData line = polyline({{0, 0, 0}, {10, 0, 0}, {20, 0, 0}});
  line.point_data.add(DataArray::from_vector<float>("r", 1, {0, 1, 2}));
  TubeOptions o;
  o.radius = 0.5;  // max radius 10 x 0.5 = 5: radii 0.5, 2.75, 5
  o.sides = 4;
  o.radius_array = "r";
  const auto [out, stats] = tube(line, o);
  EXPECT_NEAR(std::hypot(out.points[0].y, out.points[0].z), 0.5, 1e-6);
  EXPECT_NEAR(std::hypot(out.points[4].y, out.points[4].z), 2.75, 1e-6);
  EXPECT_NEAR(std::hypot(out.points[8].y, out.points[8].z), 5, 1e-6);
  EXPECT_DOUBLE_EQ(stats.max_radius, 5);
  o.max_radius = 1;
  o.scalar_range = std::array<double, 2>{1, 2};  // 0 clamps to 1: radii 0.5, 0.5, 1
  const auto b = tube(line, o).output;
  EXPECT_NEAR(std::hypot(b.points[4].y, b.points[4].z), 0.5, 1e-6);
  EXPECT_NEAR(std::hypot(b.points[8].y, b.points[8].z), 1, 1e-6);
  test::expect_closed_manifold(merged(b), "cone-like tube");
}

TEST(Tube, SharpTurnsRepeatsAndShortLines) {
  PolyData pd;
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{5, 5, 5}})
    pd.points.push_back(p);
  pd.lines.add({0, 1, 2, 3});  // a right angle; the repeated point is dropped
  pd.lines.add({4, 4});        // two equal points: no tube
  pd.lines.add({1, 2});        // two points at the same place: no tube
  TubeOptions o;
  o.sides = 5;
  o.radius = 0.1;
  const auto [out, stats] = tube(pd, o);
  EXPECT_EQ(stats.tubes, 1u);
  EXPECT_EQ(stats.skipped_lines, 2u);
  EXPECT_EQ(out.num_points(), 3u * 5 + 10);
  const PolyData m = merged(out);
  test::expect_closed_manifold(m, "bent tube");
  EXPECT_GT(test::signed_volume(m), 0);
}

TEST(Tube, BadOptionsAreErrors) {
  const PolyData line = polyline({{0, 0, 0}, {1, 0, 0}});
  TubeOptions o;
  o.radius = 0;
  test::expect_error([&] { (void)tube(line, o); }, "radius must be a finite number > 0");
  o.radius = std::nan("");
  test::expect_error([&] { (void)tube(line, o); }, "radius must be a finite number > 0");
  o = {};
  o.sides = 2;
  test::expect_error([&] { (void)tube(line, o); }, "sides must be >= 3");
  o = {};
  o.radius_array = "nope";
  test::expect_error([&] { (void)tube(line, o); }, "radius by 'nope': no such point array");
  o = {};
  o.sides = 2000000000;  // 4e9 ring points: refused before anything is allocated
  test::expect_error([&] { (void)tube(line, o); }, "tube: 1 tubes of 2000000000 sides needs");
  o = {};
  o.scalar_range = std::array<double, 2>{2, 1};
  test::expect_error([&] { (void)tube(line, o); }, "MIN < MAX");
}

TEST(Ribbon, StraightLineWithoutNormalsIsAFlatStripOfTheWidth) {
  PolyData line = polyline({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  DataArray s("s", ScalarType::Float32, 1, 5);
  for (std::size_t i = 0; i < 5; ++i) s.set(i, 0, double(i));
  line.point_data.add(std::move(s));
  RibbonOptions o;
  o.width = 0.5;
  const auto [out, stats] = ribbon(line, o);
  EXPECT_EQ(stats.ribbons, 1u);
  EXPECT_FALSE(stats.oriented);
  ASSERT_EQ(out.num_points(), 8u);  // 4 distinct points, 2 each
  ASSERT_EQ(out.polys.size(), 6u);
  const DataArray& n = out.point_data.get("Normals");
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    const Vec3 p = out.points[i];
    EXPECT_NEAR(std::hypot(p.y, p.z), 0.25, 1e-6);  // width/2 from the line
    const Vec3 ni{n.get(i, 0), n.get(i, 1), n.get(i, 2)};
    EXPECT_NEAR(norm(ni), 1, 1e-6);
    EXPECT_NEAR(ni.x, 0, 1e-6);
    EXPECT_NEAR(dot(ni, Vec3{0, p.y, p.z}), 0, 1e-6);  // the strip lies in its normal's plane
  }
  // Both sides of point i carry the line's value at i; point 3 was a repeat of point 2.
  const DataArray& c = out.point_data.get("s");
  EXPECT_EQ(c.get(4), 2.0);
  EXPECT_EQ(c.get(7), 4.0);
  // Triangles face along the normals.
  for (std::size_t t = 0; t < out.polys.size(); ++t) {
    const auto v = out.polys.cell(t);
    const Vec3 a = out.points[std::size_t(v[0])], b = out.points[std::size_t(v[1])],
               d = out.points[std::size_t(v[2])];
    const Vec3 face = cross(b - a, d - a);
    EXPECT_GT(dot(face, Vec3{n.get(std::size_t(v[0]), 0), n.get(std::size_t(v[0]), 1),
                             n.get(std::size_t(v[0]), 2)}),
              0);
  }
}

TEST(Ribbon, NormalsAndAngleOrientIt) {
  PolyData line = polyline({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  DataArray normals("Normals", ScalarType::Float32, 3, 3);
  DataArray after("after", ScalarType::Int32, 1, 3);  // an array after the normals is carried too
  for (std::size_t i = 0; i < 3; ++i) {
    normals.set(i, 0, 0.7);  // along the line: projected away
    normals.set(i, 2, 1.0);
    after.set(i, 0, double(10 + i));
  }
  line.point_data.add(std::move(normals), AttributeRole::Normals);
  line.point_data.add(std::move(after));
  for (const double angle : {0.0, 90.0}) {
    RibbonOptions o;
    o.width = 2;
    o.angle = angle;
    const auto [out, stats] = ribbon(line, o);  // the active normals
    EXPECT_TRUE(stats.oriented);
    for (std::size_t i = 0; i < out.num_points(); ++i) {
      const Vec3 p = out.points[i];
      // Normal +z: the ribbon spans y; turned by 90° about +x it spans z.
      EXPECT_NEAR(std::abs(angle == 0 ? p.y : p.z), 1, 1e-6);
      EXPECT_NEAR(angle == 0 ? p.z : p.y, 0, 1e-6);
      EXPECT_EQ(out.point_data.get("after").get(i), double(10 + i / 2));
    }
    // The ribbon's normals replace the lines'.
    EXPECT_NEAR(std::abs(out.point_data.normals()->get(0, angle == 0 ? 2 : 1)), 1, 1e-6);
  }
  RibbonOptions named;
  named.normals = "Normals";
  EXPECT_TRUE(ribbon(line, named).stats.oriented);
}

TEST(Ribbon, BadOptionsAreErrors) {
  const PolyData line = polyline({{0, 0, 0}, {1, 0, 0}});
  RibbonOptions o;
  o.width = 0;
  test::expect_error([&] { (void)ribbon(line, o); }, "ribbon: width must be a finite number > 0");
  o.width = NAN;
  test::expect_error([&] { (void)ribbon(line, o); }, "ribbon: width must be a finite number > 0");
  o.width = 1;
  o.angle = INFINITY;
  test::expect_error([&] { (void)ribbon(line, o); }, "ribbon: the angle must be finite");
  o.angle = 0;
  o.normals = "nope";
  test::expect_error([&] { (void)ribbon(line, o); }, "ribbon: normals 'nope': no such point array");
  PolyData scalar = line;
  scalar.point_data.add(DataArray("one", ScalarType::Float32, 1, 2));
  o.normals = "one";
  test::expect_error([&] { (void)ribbon(scalar, o); }, "have 1 components, 3 needed");
}
