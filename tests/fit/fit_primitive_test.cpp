// fit_primitive: exact shapes are recovered to rounding, robust losses ignore outliers that pull
// plain least squares away, the returned function and expression agree, bad input is refused.

#include "isoforge/fit/fit_primitive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "isoforge/implicit/parse.hpp"
#include "support/expect_error.hpp"

namespace isoforge {
namespace {

using test::expect_error;

constexpr double kExact = 1e-9;  // noise-free data: parameters to (well above) rounding

// A point cloud (no cells) with float64 coordinates, so exact shapes stay exact.
PolyData cloud(const std::vector<Vec3>& pts, const std::vector<Vec3>& normals = {}) {
  PolyData pd;
  pd.points = Points(pts.size(), ScalarType::Float64);
  for (std::size_t i = 0; i < pts.size(); ++i) pd.points.set(i, pts[i]);
  if (!normals.empty()) {
    std::vector<double> v;
    for (const Vec3& n : normals) v.insert(v.end(), {n.x, n.y, n.z});
    pd.point_data.add(DataArray::from_vector("Normals", 3, v));
  }
  return pd;
}

// Options of `kind` with members set: options(kind, &FitOptions::loss, RobustLoss::None, ...).
FitOptions options(PrimitiveKind kind) {
  FitOptions o;
  o.kind = kind;
  return o;
}
template <class M, class V, class... Rest>
FitOptions options(PrimitiveKind kind, M FitOptions::*member, V value, Rest... rest) {
  FitOptions o = options(kind, rest...);
  o.*member = value;
  return o;
}

Vec3 unit(const Vec3& v) {
  return v / norm(v);
}

// Two unit vectors perpendicular to `a` and to each other.
std::pair<Vec3, Vec3> frame(const Vec3& a) {
  const Vec3 t = std::abs(a.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = unit(cross(a, t));
  return {u, cross(a, u)};
}

// The returned function is ≈ 0 on the (exact) points and its expression evaluates the same.
void expect_consistent(const FitResult& r, const std::vector<Vec3>& pts, double tol) {
  const ImplicitFunction parsed = parse_implicit(r.output.expression);
  for (const Vec3& p : pts) {
    EXPECT_NEAR(r.output.function.value(p), 0, tol);
    EXPECT_EQ(parsed.value(p), r.output.function.value(p)) << r.output.expression;
  }
}

std::vector<Vec3> sphere_points(const Vec3& c, double r, int n, std::mt19937& rng) {
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) out.push_back(c + r * unit({g(rng), g(rng), g(rng)}));
  return out;
}

TEST(FitPrimitive, PlaneExact) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-2, 2);
  const Vec3 n = unit({1, 2, 3});
  const double d = 0.7;
  const auto [e1, e2] = frame(n);
  std::vector<Vec3> pts;
  for (int i = 0; i < 50; ++i) pts.push_back(d * n + u(rng) * e1 + u(rng) * e2);
  const auto r = fit_primitive(cloud(pts), options(PrimitiveKind::Plane));
  ASSERT_EQ(r.output.parameters.size(), 4u);
  // Without normals the sign makes the largest component (z) positive.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.output.parameters[i], n[i], kExact);
  EXPECT_NEAR(r.output.parameters[3], d, kExact);
  EXPECT_LT(r.stats.max_abs, kExact);
  EXPECT_EQ(r.stats.points, 50u);
  expect_consistent(r, pts, kExact);
}

TEST(FitPrimitive, PlaneOrientedByNormals) {
  // All normals point to −z: the fitted normal follows them (and the offset changes sign).
  std::vector<Vec3> pts, normals;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      pts.push_back({double(i), double(j), 2});
      normals.push_back({0, 0, -1});
    }
  const auto r = fit_primitive(cloud(pts, normals), options(PrimitiveKind::Plane));
  EXPECT_NEAR(r.output.parameters[2], -1, kExact);
  EXPECT_NEAR(r.output.parameters[3], -2, kExact);
  // n = −z: the signed distance n·x − d is positive below z = 2 (the origin: 0 − (−2) = 2).
  EXPECT_NEAR(r.output.function.value({0, 0, 0}), 2, kExact);
}

TEST(FitPrimitive, SphereExact) {
  std::mt19937 rng(2);
  const Vec3 c{1, -2, 0.5};
  const auto pts = sphere_points(c, 2.5, 200, rng);
  const auto r = fit_primitive(cloud(pts), options(PrimitiveKind::Sphere));
  ASSERT_EQ(r.output.parameters.size(), 4u);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.output.parameters[i], c[i], kExact);
  EXPECT_NEAR(r.output.parameters[3], 2.5, kExact);
  EXPECT_TRUE(r.stats.converged);
  EXPECT_EQ(r.stats.inliers, 200u);
  expect_consistent(r, pts, kExact);
}

TEST(FitPrimitive, SphereFromAPatch) {
  // A 60° cap: the linear initialisation is biased only by rounding; still exact.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> pts;
  for (int i = 0; i < 100; ++i) {
    const double th = std::acos(1 - u(rng) * 0.5), ph = 2 * std::numbers::pi * u(rng);
    pts.push_back(Vec3{3, 0, 0} + 0.5 * Vec3{std::sin(th) * std::cos(ph),
                                             std::sin(th) * std::sin(ph), std::cos(th)});
  }
  const auto r = fit_primitive(cloud(pts), options(PrimitiveKind::Sphere));
  EXPECT_NEAR(r.output.parameters[0], 3, kExact);
  EXPECT_NEAR(r.output.parameters[3], 0.5, kExact);
  expect_consistent(r, pts, kExact);
}

struct Cyl {
  std::vector<Vec3> pts, normals;
};
Cyl cylinder_points(const Vec3& p0, const Vec3& a, double radius, int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const auto [e1, e2] = frame(a);
  Cyl c;
  for (int i = 0; i < n; ++i) {
    const double ph = 2 * std::numbers::pi * u(rng), h = -2 + 4 * u(rng);
    const Vec3 radial = std::cos(ph) * e1 + std::sin(ph) * e2;
    c.pts.push_back(p0 + h * a + radius * radial);
    c.normals.push_back(radial);
  }
  return c;
}

void expect_cylinder(const FitResult& r, const Vec3& p0, const Vec3& a, double radius) {
  ASSERT_EQ(r.output.parameters.size(), 7u);
  const auto& q = r.output.parameters;
  const Vec3 p{q[0], q[1], q[2]}, fa{q[3], q[4], q[5]};
  EXPECT_NEAR(norm(fa), 1, kExact);
  EXPECT_NEAR(std::abs(dot(fa, a)), 1, kExact);
  EXPECT_LT(norm(cross(p - p0, a)), kExact);  // the fitted point lies on the true axis
  EXPECT_NEAR(q[6], radius, kExact);
}

TEST(FitPrimitive, CylinderExactWithAndWithoutNormals) {
  std::mt19937 rng(4);
  const Vec3 p0{0.5, 1, -1}, a = unit({1, -1, 2});
  const auto c = cylinder_points(p0, a, 0.8, 300, rng);
  const auto with = fit_primitive(cloud(c.pts, c.normals), options(PrimitiveKind::Cylinder));
  expect_cylinder(with, p0, a, 0.8);
  expect_consistent(with, c.pts, kExact);
  const auto without = fit_primitive(cloud(c.pts), options(PrimitiveKind::Cylinder));
  expect_cylinder(without, p0, a, 0.8);
  expect_consistent(without, c.pts, kExact);
}

TEST(FitPrimitive, ConeExactWithAndWithoutNormals) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 apex{1, 2, 3}, a = unit({0.3, 1, -0.5});
  const double half = 25 * std::numbers::pi / 180;
  const auto [e1, e2] = frame(a);
  std::vector<Vec3> pts, normals;
  for (int i = 0; i < 300; ++i) {
    const double ph = 2 * std::numbers::pi * u(rng), h = 0.5 + 2 * u(rng);
    const Vec3 radial = std::cos(ph) * e1 + std::sin(ph) * e2;
    pts.push_back(apex + h * a + h * std::tan(half) * radial);
    normals.push_back(std::cos(half) * radial - std::sin(half) * a);
  }
  for (const bool use : {true, false}) {
    const auto r = fit_primitive(cloud(pts, use ? normals : std::vector<Vec3>{}),
                                 options(PrimitiveKind::Cone));
    const auto& q = r.output.parameters;
    ASSERT_EQ(q.size(), 7u);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q[i], apex[i], kExact) << "normals " << use;
    // The axis points from the apex towards the points.
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q[3 + i], a[i], kExact) << "normals " << use;
    EXPECT_NEAR(q[6], 25, kExact);
    expect_consistent(r, pts, kExact);
  }
}

TEST(FitPrimitive, QuadricExactEllipsoid) {
  // x²/4 + y² + z²/9 = 1, shifted by (1, 0, -1).
  std::mt19937 rng(6);
  std::normal_distribution<double> g;
  std::vector<Vec3> pts;
  for (int i = 0; i < 400; ++i) {
    const Vec3 s = unit({g(rng), g(rng), g(rng)});
    pts.push_back({1 + 2 * s.x, s.y, -1 + 3 * s.z});
  }
  const auto r = fit_primitive(cloud(pts), options(PrimitiveKind::Quadric));
  const auto& q = r.output.parameters;
  ASSERT_EQ(q.size(), 10u);
  // Expected up to scale: x²/4 + y² + z²/9 − x/2 + 2z/9 + (1/4 + 1/9 − 1).
  const double want[10] = {0.25, 1, 1.0 / 9, 0, 0, 0, -0.5, 0, 2.0 / 9, 0.25 + 1.0 / 9 - 1};
  const double k = q[1];  // the y² coefficient; the others relative to it
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(q[i] / k, want[i], kExact) << "a" << i;
  EXPECT_LT(r.output.function.value({1, 0, -1}), 0);  // the center is inside
  EXPECT_LT(r.stats.max_abs, kExact);
  expect_consistent(r, pts, kExact);
}

// Noisy sphere with 10% gross outliers: the robust losses recover it, plain least squares not.
TEST(FitPrimitive, RobustLossesIgnoreOutliers) {
  std::mt19937 rng(7);
  const Vec3 c{0.2, -0.1, 0.3};
  auto pts = sphere_points(c, 1, 900, rng);
  std::normal_distribution<double> noise(0, 0.005);
  for (Vec3& p : pts) p += Vec3{noise(rng), noise(rng), noise(rng)};
  std::uniform_real_distribution<double> box(0, 3);  // outliers on one side: they pull
  for (int i = 0; i < 100; ++i) pts.push_back({box(rng), box(rng), box(rng)});
  const auto error = [&](RobustLoss loss) {
    const auto r =
        fit_primitive(cloud(pts), options(PrimitiveKind::Sphere, &FitOptions::loss, loss));
    const auto& q = r.output.parameters;
    return std::max(norm(Vec3{q[0], q[1], q[2]} - c), std::abs(q[3] - 1));
  };
  const double plain = error(RobustLoss::None), huber = error(RobustLoss::Huber),
               cauchy = error(RobustLoss::Cauchy);
  EXPECT_GT(plain, 0.05);
  EXPECT_LT(huber, 0.01);
  EXPECT_LT(cauchy, 0.005);
  const auto r = fit_primitive(
      cloud(pts), options(PrimitiveKind::Sphere, &FitOptions::loss, RobustLoss::Cauchy));
  // The 900 sphere points are inliers (within 2.5 σ ≈ 3.5 noise σ), the far outliers not.
  EXPECT_GE(r.stats.inliers, 850u);
  EXPECT_LE(r.stats.inliers, 920u);
  EXPECT_GT(r.stats.max_abs, 0.5);
}

TEST(FitPrimitive, RobustPlaneAndCylinder) {
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0, 0.002);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> plane;
  for (int i = 0; i < 450; ++i) plane.push_back({u(rng), u(rng), noise(rng)});
  for (int i = 0; i < 50; ++i) plane.push_back({u(rng), u(rng), 0.5 + 0.5 * std::abs(u(rng))});
  const auto tilt = [](const FitResult& r) { return std::acos(std::abs(r.output.parameters[2])); };
  const auto none = fit_primitive(
      cloud(plane), options(PrimitiveKind::Plane, &FitOptions::loss, RobustLoss::None));
  const auto cauchy = fit_primitive(
      cloud(plane), options(PrimitiveKind::Plane, &FitOptions::loss, RobustLoss::Cauchy));
  EXPECT_GT(std::abs(none.output.parameters[3]), 0.05);  // pulled up by the outliers
  EXPECT_LT(std::abs(cauchy.output.parameters[3]), 0.002);
  EXPECT_LT(tilt(cauchy), 0.005);

  const Vec3 p0{0, 0, 0}, a{0, 0, 1};
  auto c = cylinder_points(p0, a, 1, 450, rng);
  for (Vec3& p : c.pts) p += Vec3{noise(rng), noise(rng), noise(rng)};
  for (int i = 0; i < 50; ++i) {
    c.pts.push_back({1.5 + u(rng) * 0.5, u(rng) * 0.5, u(rng)});
    c.normals.push_back({1, 0, 0});
  }
  const auto cyl = [&](RobustLoss loss) {
    const auto r = fit_primitive(cloud(c.pts, c.normals),
                                 options(PrimitiveKind::Cylinder, &FitOptions::loss, loss));
    const auto& q = r.output.parameters;
    return std::max(
        {norm(cross(Vec3{q[0], q[1], q[2]} - p0, a)), std::abs(q[6] - 1), 1 - std::abs(q[5])});
  };
  EXPECT_GT(cyl(RobustLoss::None), 0.05);
  EXPECT_LT(cyl(RobustLoss::Huber), 0.01);
  EXPECT_LT(cyl(RobustLoss::Cauchy), 0.005);
}

TEST(FitPrimitive, ExplicitLossScaleAndImage) {
  // Any dataset: the points of an image lie on the plane z = 0.
  ImageData img;
  img.dims = {4, 5, 1};
  img.origin = {1, 2, 0};
  const auto r = fit_primitive(img, options(PrimitiveKind::Plane, &FitOptions::loss_scale, 0.1));
  EXPECT_NEAR(std::abs(r.output.parameters[2]), 1, kExact);
  EXPECT_NEAR(r.output.parameters[3], 0, kExact);
}

TEST(FitPrimitive, Progress) {
  std::mt19937 rng(9);
  const auto pts = sphere_points({0, 0, 0}, 1, 50, rng);
  double last = -1;
  bool monotone = true;
  FitOptions o = options(PrimitiveKind::Sphere);
  o.progress = [&](double f) {
    monotone = monotone && f >= last;
    last = f;
    return true;
  };
  (void)fit_primitive(cloud(pts), o);
  EXPECT_TRUE(monotone);
  EXPECT_EQ(last, 1);
  o.progress = [](double) { return false; };
  EXPECT_THROW((void)fit_primitive(cloud(pts), o), Cancelled);
}

TEST(FitPrimitive, Errors) {
  const std::vector<Vec3> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  expect_error([&] { (void)fit_primitive(cloud(line), options(PrimitiveKind::Plane)); },
               "plane: the points are collinear");
  const std::vector<Vec3> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 3, 0}};
  expect_error([&] { (void)fit_primitive(cloud(flat), options(PrimitiveKind::Sphere)); },
               "sphere: the points are coplanar");
  expect_error([&] { (void)fit_primitive(cloud(flat), options(PrimitiveKind::Cylinder)); },
               "cylinder: needs at least 9 points, got 5");
  std::vector<Vec3> grid;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) grid.push_back({double(i), double(j), 1});
  expect_error([&] { (void)fit_primitive(cloud(grid), options(PrimitiveKind::Quadric)); },
               "quadric: the points do not determine a quadric");
  expect_error([&] { (void)fit_primitive(cloud(grid), options(PrimitiveKind::Cylinder)); },
               "cylinder: the points do not determine a quadric");
  auto bad = grid;
  bad[7].y = std::nan("");
  expect_error([&] { (void)fit_primitive(cloud(bad), options(PrimitiveKind::Plane)); },
               "point 7 is not finite");
  expect_error(
      [&] {
        (void)fit_primitive(cloud(grid),
                            options(PrimitiveKind::Plane, &FitOptions::loss_scale, -1));
      },
      "loss_scale must be a finite number >= 0");
  expect_error(
      [&] {
        (void)fit_primitive(cloud(grid),
                            options(PrimitiveKind::Plane, &FitOptions::max_iterations, 0));
      },
      "max_iterations must be >= 1");
  expect_error([&] { (void)fit_primitive(PolyData{}, options(PrimitiveKind::Sphere)); },
               "sphere: needs at least 4 points, got 0");
}

TEST(FitPrimitive, Names) {
  EXPECT_STREQ(to_string(PrimitiveKind::Cone), "cone");
  EXPECT_STREQ(to_string(RobustLoss::Cauchy), "cauchy");
}

}  // namespace
}  // namespace isoforge
