// The accuracy checks on inputs built to pass them and inputs built to fail them: side check,
// samplers, distances to analytic surfaces and between meshes (both one-sided directions),
// convergence order, borders on the domain boundary, surface identity; and the case-result
// helpers and the report writer that turn them into pass/fail rows.

#include "accuracy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "catalogue.hpp"
#include "mesh_distance.hpp"
#include "report.hpp"

using namespace isoforge;
using namespace isoforge::verify;
using F = ImplicitFunction;

namespace {

constexpr double kPi = std::numbers::pi;

// Latitude-longitude sphere (n rings of m quads, split), outward, every vertex on the sphere.
// With `upper_only`, only the faces of the upper hemisphere (an open cap).
PolyData uv_sphere(const Vec3& c, double r, int n, int m, bool upper_only = false) {
  PolyData pd;
  pd.points.push_back(c + Vec3{0, 0, r});
  for (int i = 1; i < n; ++i) {
    const double t = kPi * i / n;
    for (int j = 0; j < m; ++j) {
      const double p = 2 * kPi * j / m;
      pd.points.push_back(
          c + Vec3{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)} * r);
    }
  }
  pd.points.push_back(c + Vec3{0, 0, -r});
  const auto id = [&](int ring, int j) { return Index(1 + (ring - 1) * m + (j % m)); };
  const Index south = Index(pd.points.size() - 1);
  for (int j = 0; j < m; ++j) pd.polys.add({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i + 1 < n; ++i) {
    if (upper_only && 2 * (i + 1) > n) break;
    for (int j = 0; j < m; ++j) {
      pd.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      pd.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  if (!upper_only) {
    for (int j = 0; j < m; ++j) pd.polys.add({id(n - 1, j), south, id(n - 1, j + 1)});
  }
  return pd;
}

PolyData square(double z, double lo, double hi) {
  PolyData pd;
  pd.points.push_back({lo, lo, z});
  pd.points.push_back({hi, lo, z});
  pd.points.push_back({hi, hi, z});
  pd.points.push_back({lo, hi, z});
  pd.polys.add({0, 1, 2});
  pd.polys.add({0, 2, 3});
  return pd;
}

Bounds unit_box() {
  Bounds b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  return b;
}

}  // namespace

// ---- side -------------------------------------------------------------------------------------

TEST(SideCheck, ToleranceIsUlpsOfTheStorageTimesTheGradient) {
  const double ulp1 = std::nextafter(1.0f, 2.0f) - 1.0f;  // 2^-23
  EXPECT_DOUBLE_EQ(side_tolerance({1, 0.5, -0.25}, ScalarType::Float32, {0, 0, 1}, 4), 4 * ulp1);
  EXPECT_DOUBLE_EQ(side_tolerance({-1, 0.5, 0}, ScalarType::Float32, {0, 3, 4}, 1), 5 * ulp1);
  EXPECT_DOUBLE_EQ(side_tolerance({1, 0, 0}, ScalarType::Float64, {1, 0, 0}, 1), 0x1p-52);
  // The scale floors the magnitude (points interpolated between larger coordinates).
  EXPECT_DOUBLE_EQ(side_tolerance({1e-3, 0, 0}, ScalarType::Float32, {1, 0, 0}, 1, 1.0), ulp1);
}

TEST(SideCheck, PointsInsideAndOutside) {
  const F sphere = F::sphere({0.1, 0, 0}, 0.5);
  Points pts;
  pts.push_back({0.1, 0, 0});
  pts.push_back({0.3, 0.2, -0.1});
  pts.push_back({0.1, 0.45, 0});
  SideReport in = check_side(pts, sphere, Side::Inside);
  EXPECT_EQ(in.points, 3u);
  EXPECT_EQ(in.violations, 0u);
  EXPECT_LT(in.worst_ratio, 0);
  // The same points fail "outside", and a point outside fails "inside".
  EXPECT_EQ(check_side(pts, sphere, Side::Outside).violations, 3u);
  pts.push_back({0.1, 0.7, 0});
  in = check_side(pts, sphere, Side::Inside);
  EXPECT_EQ(in.violations, 1u);
  EXPECT_EQ(in.worst_point, 3u);
  EXPECT_NEAR(in.worst_value, 0.2, 1e-6);
  EXPECT_GT(in.worst_ratio, 1);
}

TEST(SideCheck, OnTheSurfaceWithinFloatRounding) {
  // The plane x = 0.7 + 1e-9 (between floats): 0.7f is within half an ulp of it, passes "on"
  // and "inside" (F <= tol) and "outside" (F >= -tol); 0.7f moved by 16 ulps fails all but one.
  const double x0 = 0.7 + 1e-9;
  const F plane = F::plane({x0, 0, 0}, {1, 0, 0});
  Points on;
  on.push_back({0.7, 0.3, -0.6});
  const SideReport r = check_side(on, plane, Side::On, 1);
  EXPECT_EQ(r.violations, 0u);
  EXPECT_EQ(r.within_tolerance, 1u);  // not exactly on the plane: only within rounding
  EXPECT_GT(r.worst_ratio, 0);
  EXPECT_LE(r.worst_ratio, 1);
  EXPECT_EQ(check_side(on, plane, Side::Inside, 1).violations, 0u);
  EXPECT_EQ(check_side(on, plane, Side::Outside, 1).violations, 0u);
  float x = 0.7f;
  for (int i = 0; i < 16; ++i) x = std::nextafter(x, 1.0f);
  Points off;
  off.push_back({x, 0.3, -0.6});
  EXPECT_EQ(check_side(off, plane, Side::On, 4).violations, 1u);
  EXPECT_EQ(check_side(off, plane, Side::Inside, 4).violations, 1u);
  EXPECT_EQ(check_side(off, plane, Side::Outside, 4).violations, 0u);
  // Double storage has a 2^29 times tighter tolerance: 0.7 itself is off the plane by 1e-9.
  Points dbl(1, ScalarType::Float64);
  dbl.set(0, {0.7, 0.3, -0.6});
  EXPECT_EQ(check_side(dbl, plane, Side::On, 4).violations, 1u);
}

TEST(SideCheck, ScaleAllowsTheRoundingOfTheInputCoordinates) {
  const F plane = F::plane({0, 0, 0}, {0, 0, 1});
  Points pts;
  pts.push_back({1e-3, 2e-3, 1e-8});  // 1e-8 off: far beyond the ulps of 2e-3 (2e-10)
  EXPECT_EQ(check_side(pts, plane, Side::On, 4).violations, 1u);
  EXPECT_EQ(check_side(pts, plane, Side::On, 4, 1.0).violations, 0u);  // 4 ulp(1) = 4.8e-7
}

// ---- samplers ---------------------------------------------------------------------------------

TEST(Samplers, MeshSamplesCoverTrianglesWithAreaWeights) {
  PolyData tri;
  tri.points.push_back({0, 0, 0});
  tri.points.push_back({1, 0, 0});
  tri.points.push_back({0, 1, 0});
  tri.polys.add({0, 1, 2});
  const Samples s = sample_mesh(tri, 0.3, 2);  // n = ceil(sqrt(2) / 0.3) = 5 -> 6: 28 + centroid
  EXPECT_EQ(s.points.size(), 29u);
  double w = 0;
  for (double x : s.weights) w += x;
  EXPECT_NEAR(w, 0.5, 1e-15);
  const auto has = [&](const Vec3& p) {
    return std::any_of(s.points.begin(), s.points.end(),
                       [&](const Vec3& q) { return norm(q - p) < 1e-15; });
  };
  EXPECT_TRUE(has({0.5, 0.5, 0}));  // edge midpoints are samples
  EXPECT_TRUE(has({0.5, 0, 0}));
  EXPECT_TRUE(has({1.0 / 3, 1.0 / 3, 0}));
  EXPECT_EQ(sample_mesh(tri, 10, 2).points.size(), 7u);  // n = 2: corners, midpoints, centroid
}

TEST(Samplers, SphereSamplesAreOnTheSphereAndAreaUniform) {
  const AnalyticSurface s = sphere_surface({0.1, -0.2, 0.3}, 0.8);
  EXPECT_NEAR(s.area, 4 * kPi * 0.64, 1e-14);
  EXPECT_NEAR(s.volume, 4.0 / 3.0 * kPi * 0.512, 1e-14);
  const auto p = s.sample(0.02);
  EXPECT_NEAR(static_cast<double>(p.size()), s.area / 0.0004, 1.0);
  Vec3 mean{};
  std::size_t band = 0;
  for (const Vec3& q : p) {
    ASSERT_LT(std::abs(s.sdf.value(q)), 1e-14);
    mean += q;
    band += std::abs(q.z - 0.3) < 0.4 ? 1 : 0;  // |z| < r / 2: half the area (Archimedes)
  }
  mean = mean / static_cast<double>(p.size());
  EXPECT_LT(norm(mean - Vec3{0.1, -0.2, 0.3}), 1e-3);
  EXPECT_NEAR(static_cast<double>(band) / static_cast<double>(p.size()), 0.5, 1e-3);
}

TEST(Samplers, TorusSamplesAreOnTheTorusAndAreaUniform) {
  const Vec3 c{0.05, 0, -0.1}, axis{0.3, -0.2, 1};
  const double R = 0.55, r = 0.24;
  const AnalyticSurface s = torus_surface(c, axis, R, r);
  EXPECT_NEAR(s.area, 4 * kPi * kPi * R * r, 1e-14);
  EXPECT_NEAR(s.volume, 2 * kPi * kPi * R * r * r, 1e-14);
  const auto p = s.sample(0.01);
  const Vec3 a = axis / norm(axis);
  std::size_t outer = 0;
  for (const Vec3& q : p) {
    ASSERT_LT(std::abs(s.sdf.value(q)), 1e-14);
    const Vec3 d = q - c;
    const double rho = norm(d - a * dot(d, a));
    outer += rho > R ? 1 : 0;
  }
  // The outer half of the tube (cos v > 0) holds (pi R + 2 r) / (2 pi R) of the area.
  EXPECT_NEAR(static_cast<double>(outer) / static_cast<double>(p.size()),
              (kPi * R + 2 * r) / (2 * kPi * R), 2e-3);
  EXPECT_THROW((void)torus_surface(c, axis, 0.2, 0.3), Error);
}

// ---- distances --------------------------------------------------------------------------------

TEST(MeshDistance, ExactDistancesToATriangle) {
  PolyData tri;
  tri.points.push_back({0, 0, 0});
  tri.points.push_back({1, 0, 0});
  tri.points.push_back({0, 1, 0});
  tri.polys.add({0, 1, 2});
  const MeshDistance d(tri);
  EXPECT_EQ(d.triangles(), 1u);
  const std::vector<Vec3> q = {{0.2, 0.2, 0.5}, {-3, -4, 0}, {1, 1, 0}, {0.25, 0.25, 0}};
  const auto r = d.distances(q);
  EXPECT_DOUBLE_EQ(r[0], 0.5);
  EXPECT_DOUBLE_EQ(r[1], 5.0);
  EXPECT_NEAR(r[2], std::sqrt(0.5), 1e-15);
  EXPECT_EQ(r[3], 0.0);
  PolyData flat;  // collinear only
  flat.points.push_back({0, 0, 0});
  flat.points.push_back({1, 0, 0});
  flat.points.push_back({2, 0, 0});
  flat.polys.add({0, 1, 2});
  EXPECT_THROW((void)MeshDistance(flat), Error);
}

TEST(DistanceToSurface, InscribedSphereMeshIsCloseBothWays) {
  const Vec3 c{0.1, 0, 0};
  const PolyData mesh = uv_sphere(c, 1.0, 64, 128);
  const DistanceReport d = distance_to_surface(mesh, sphere_surface(c, 1.0), 0.01, 0.01);
  // Chords of a unit circle subtending 2 pi / 128 sag by 1 - cos(pi / 128) = 3.0e-4; the quads
  // near the equator reach about twice that at their centres.
  EXPECT_GT(d.max_a_to_b, 2e-4);
  EXPECT_LT(d.max_a_to_b, 1e-3);
  EXPECT_LT(d.max_b_to_a, 1e-3);
  EXPECT_LT(d.rms_a_to_b, d.max_a_to_b);
  EXPECT_GT(d.samples_a, 0u);
  EXPECT_GT(d.samples_b, 0u);
}

TEST(DistanceToSurface, WrongRadiusFailsBothWays) {
  const PolyData mesh = uv_sphere({0, 0, 0}, 1.0, 64, 128);
  const DistanceReport d = distance_to_surface(mesh, sphere_surface({0, 0, 0}, 1.05), 0.01, 0.01);
  EXPECT_NEAR(d.max_a_to_b, 0.05, 1e-3);
  EXPECT_NEAR(d.max_b_to_a, 0.05, 1e-3);
  EXPECT_NEAR(d.rms_a_to_b, 0.05, 1e-3);
}

TEST(DistanceToSurface, MissingHalfIsSeenOnlyFromTheSurface) {
  // A hemisphere lies on the sphere (mesh -> surface small) but does not cover it: from the
  // lower pole the nearest mesh point is on the rim, sqrt(2) away.
  const PolyData cap = uv_sphere({0, 0, 0}, 1.0, 64, 128, true);
  const DistanceReport d = distance_to_surface(cap, sphere_surface({0, 0, 0}, 1.0), 0.01, 0.01);
  EXPECT_LT(d.max_a_to_b, 1e-3);
  EXPECT_NEAR(d.max_b_to_a, std::sqrt(2.0), 2e-2);
  EXPECT_NEAR(d.hausdorff(), d.max_b_to_a, 0);
}

TEST(DistanceToSurface, TorusWithTheWrongTubeRadius) {
  // A parametric torus mesh of tube 0.25 measured against the analytic torus of tube 0.24.
  const Vec3 c{0, 0, 0}, axis{0, 0, 1};
  const double R = 0.55;
  PolyData pd;
  const int n = 256, m = 96;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * kPi * i / n, v = 2 * kPi * j / m;
      pd.points.push_back({(R + 0.25 * std::cos(v)) * std::cos(u),
                           (R + 0.25 * std::cos(v)) * std::sin(u), 0.25 * std::sin(v)});
    }
  const auto id = [&](int i, int j) { return Index((i % n) * m + (j % m)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      pd.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      pd.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  const DistanceReport ok = distance_to_surface(pd, torus_surface(c, axis, R, 0.25), 0.005, 0.005);
  EXPECT_LT(ok.hausdorff(), 1e-3);
  const DistanceReport bad = distance_to_surface(pd, torus_surface(c, axis, R, 0.24), 0.005, 0.005);
  EXPECT_NEAR(bad.max_a_to_b, 0.01, 1e-3);
  EXPECT_NEAR(bad.max_b_to_a, 0.01, 1e-3);
}

TEST(MeshToMesh, ScaledAndHalvedSpheres) {
  const PolyData a = uv_sphere({0, 0, 0}, 1.0, 48, 96);
  const PolyData b = uv_sphere({0, 0, 0}, 1.1, 48, 96);
  const DistanceReport d = mesh_to_mesh_distance(a, b, 0.02);
  EXPECT_NEAR(d.max_a_to_b, 0.1, 2e-3);
  EXPECT_NEAR(d.max_b_to_a, 0.1, 2e-3);
  const DistanceReport same = mesh_to_mesh_distance(a, a, 0.02);
  EXPECT_LT(same.hausdorff(), 1e-12);
  const PolyData cap = uv_sphere({0, 0, 0}, 1.0, 48, 96, true);
  const DistanceReport half = mesh_to_mesh_distance(cap, a, 0.02);
  EXPECT_LT(half.max_a_to_b, 1e-12);                   // the cap lies on the sphere mesh
  EXPECT_NEAR(half.max_b_to_a, std::sqrt(2.0), 3e-2);  // the sphere mesh is not covered
}

// ---- errors and convergence -------------------------------------------------------------------

TEST(Convergence, OrderIsTheLeastSquaresSlope) {
  const std::vector<double> h = {0.1, 0.05, 0.025, 0.0125};
  std::vector<double> e2, e1, noisy;
  for (std::size_t i = 0; i < h.size(); ++i) {
    e2.push_back(3 * h[i] * h[i]);
    e1.push_back(0.5 * h[i]);
    noisy.push_back(3 * h[i] * h[i] * (i % 2 ? 1.1 : 0.9));
  }
  EXPECT_NEAR(convergence_order(h, e2), 2.0, 1e-12);
  EXPECT_NEAR(convergence_order(h, e1), 1.0, 1e-12);  // first order fails [1.8, 2.3]
  const double o = convergence_order(h, noisy);
  EXPECT_NEAR(o, 2.0, 0.15);
  EXPECT_NE(o, 2.0);
  EXPECT_THROW((void)convergence_order(std::vector<double>{0.1}, std::vector<double>{1.0}), Error);
  EXPECT_THROW((void)convergence_order(h, std::vector<double>{1, 2, 0, 4}), Error);
  EXPECT_THROW((void)convergence_order(std::vector<double>{0.1, 0.1}, std::vector<double>{1, 2}),
               Error);
  EXPECT_DOUBLE_EQ(relative_error(1.01, 1.0), 0.010000000000000009);
  EXPECT_DOUBLE_EQ(relative_error(-2.0, -1.0), 1.0);
}

TEST(AreaVolume, OfAUnitCubeOfTriangles) {
  PolyData cube;
  for (int i = 0; i < 8; ++i)
    cube.points.push_back({double(i & 1), double((i >> 1) & 1), double(i >> 2)});
  const Index f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : f) cube.polys.add({q[0], q[1], q[2], q[3]});  // quads, fan-triangulated
  const AreaVolume av = area_and_volume(cube);
  EXPECT_DOUBLE_EQ(av.area, 6.0);
  EXPECT_DOUBLE_EQ(av.volume, 1.0);
}

// ---- borders and identity ---------------------------------------------------------------------

TEST(Borders, OnlyOnTheDomainBoundary) {
  const BorderReport inside = check_borders(square(0.0, -0.5, 0.5), unit_box(), 1e-6);
  EXPECT_EQ(inside.border_edges, 4u);
  EXPECT_EQ(inside.off_boundary, 4u);
  const BorderReport face = check_borders(square(-1.0, -0.5, 0.5), unit_box(), 1e-6);
  EXPECT_EQ(face.border_edges, 4u);
  EXPECT_EQ(face.off_boundary, 0u);
  // A square across the domain, cut by its faces x = +-1 and y = +-1: every border on a face.
  const BorderReport across = check_borders(square(0.3, -1.0, 1.0), unit_box(), 1e-6);
  EXPECT_EQ(across.off_boundary, 0u);
  // One corner lifted off the face plane by more than the tolerance.
  PolyData lifted = square(-1.0, -0.5, 0.5);
  lifted.points.set(2, {0.5, 0.5, -1.0 + 1e-5});
  EXPECT_EQ(check_borders(lifted, unit_box(), 1e-6).off_boundary, 2u);
  EXPECT_EQ(check_borders(lifted, unit_box(), 1e-4).off_boundary, 0u);
  // A closed surface has no border at all.
  EXPECT_EQ(check_borders(uv_sphere({0, 0, 0}, 0.5, 8, 16), unit_box(), 1e-6).border_edges, 0u);
}

TEST(CompareSurfaces, IdenticalUpToNumberingAndRotation) {
  const PolyData a = uv_sphere({0, 0, 0}, 0.5, 8, 16);
  // b: points in reverse order, triangles in reverse order, each rotated by one corner.
  PolyData b;
  const std::size_t np = a.points.size();
  for (std::size_t i = 0; i < np; ++i) b.points.push_back(a.points[np - 1 - i]);
  for (std::size_t c = a.polys.size(); c-- > 0;) {
    const auto t = a.polys.cell(c);
    const auto m = [&](Index id) { return Index(np - 1 - static_cast<std::size_t>(id)); };
    b.polys.add({m(t[1]), m(t[2]), m(t[0])});
  }
  SurfaceComparison c = compare_surfaces(a, b);
  EXPECT_TRUE(c.identical());
  EXPECT_EQ(c.triangles_a, c.triangles_b);
  EXPECT_EQ(c.points_a, np);
  // One coordinate moved by one float ulp: neither the points nor the triangles match.
  PolyData moved = b;
  const Vec3 p = moved.points[3];
  moved.points.set(3, {p.x, p.y, std::nextafter(static_cast<float>(p.z), 2.0f)});
  c = compare_surfaces(a, moved);
  EXPECT_FALSE(c.same_points);
  EXPECT_FALSE(c.same_triangles);
  // One triangle flipped: same points, different oriented triangles.
  PolyData flipped = b;
  std::swap(flipped.polys.cell(0)[1], flipped.polys.cell(0)[2]);
  c = compare_surfaces(a, flipped);
  EXPECT_TRUE(c.same_points);
  EXPECT_FALSE(c.same_triangles);
  // One triangle missing.
  PolyData fewer;
  fewer.points = a.points;
  for (std::size_t t = 1; t < a.polys.size(); ++t) fewer.polys.add(a.polys.cell(t));
  c = compare_surfaces(a, fewer);
  EXPECT_NE(c.triangles_a, c.triangles_b);
  EXPECT_FALSE(c.identical());
}

// ---- case results and the report ----------------------------------------------------------------

TEST(CaseResult, EveryHelperCanFail) {
  CaseResult r;
  EXPECT_FALSE(r.pass());  // no checks: not a pass
  r.equal("eq", std::size_t{1}, std::size_t{1});
  r.at_most("max", 1.0, 1.0);
  r.at_least("min", 1.0, 1.0);
  r.within("range", 2.0, 1.8, 2.3);
  r.is_true("yes", true);
  EXPECT_TRUE(r.pass());
  for (int k = 0; k < 5; ++k) {
    CaseResult f = r;
    switch (k) {
      case 0:
        f.equal("eq", 1, 2);
        break;
      case 1:
        f.at_most("max", 1.0 + 1e-12, 1.0);
        break;
      case 2:
        f.at_least("min", 1.0 - 1e-12, 1.0);
        break;
      case 3:
        f.within("range", 1.79, 1.8, 2.3);
        break;
      default:
        f.is_true("yes", false);
        break;
    }
    EXPECT_FALSE(f.pass()) << k;
  }
  CaseResult e = r;
  e.error = "thrown";
  EXPECT_FALSE(e.pass());
  EXPECT_FALSE([] {
    CaseResult n;
    n.within("nan", std::nan(""), 0, 1);
    return n.pass();
  }());
}

TEST(Report, ListsFailuresAndEveryCheck) {
  CaseResult ok, bad;
  ok.name = "group/ok";
  ok.at_most("error", 0.5, 1.0);
  ok.note("size", "12 triangles");
  bad.name = "group/bad";
  bad.at_most("error | pipe", 2.0, 1.0);
  const auto dir = std::filesystem::temp_directory_path() / "isoforge-verify-report-test";
  write_report(dir, {ok, bad}, {"isoforge-verify --case x", 1.5});
  const auto read_text = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string md = read_text(dir / "report.md");
  EXPECT_NE(md.find("1 of 2 cases passed"), std::string::npos);
  EXPECT_NE(md.find("## Failures"), std::string::npos);
  EXPECT_NE(md.find("`group/bad`: error \\| pipe: measured 2, required <= 1"), std::string::npos);
  EXPECT_NE(md.find("| group/ok | error | 0.5 | <= 1 | pass |"), std::string::npos);
  EXPECT_NE(md.find("  - size: 12 triangles"), std::string::npos);
  EXPECT_NE(md.find("`isoforge-verify --case x`"), std::string::npos);
  const std::string js = read_text(dir / "report.json");
  EXPECT_NE(js.find("\"passed\": 1"), std::string::npos);
  EXPECT_NE(js.find("\"name\": \"group/bad\""), std::string::npos);
  EXPECT_NE(js.find("\"value\": \"12 triangles\""), std::string::npos);
  std::filesystem::remove_all(dir);
}
