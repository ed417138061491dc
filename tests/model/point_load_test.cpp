// The Boussinesq point-load field: its closed form against the known results (the axis, the
// trace, the free surface, equilibrium by finite differences, mirror symmetry), the sampled grid
// (the singular sample, von Mises scalar) and its errors.

#include "isoforge/model/point_load.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "support/expect_error.hpp"

using isoforge::test::expect_error;

using namespace isoforge;

namespace {

constexpr double kPi = std::numbers::pi;

// σ in the box's frame (z up, the load at the origin): depth = −z.
std::array<double, 9> stress_at(double x, double y, double z, double load = 2.5, double nu = 0.3) {
  return boussinesq_stress(x, y, -z, load, nu);
}

}  // namespace

TEST(PointLoad, OnTheAxis) {
  const double P = 2.5, nu = 0.3;
  for (const double d : {0.1, 1.0, 7.0}) {
    const auto s = boussinesq_stress(0, 0, d, P, nu);
    const double scale = P / (d * d);
    EXPECT_NEAR(s[8], -3 * P / (2 * kPi * d * d), 1e-14 * scale);  // compression under the load
    // The horizontal stresses are equal and tensile, (1 − 2ν) P / (4π d²) (Timoshenko & Goodier).
    EXPECT_NEAR(s[0], (1 - 2 * nu) * P / (4 * kPi * d * d), 1e-14 * scale);
    EXPECT_NEAR(s[4], s[0], 1e-14 * scale);
    for (const int c : {1, 2, 3, 5, 6, 7}) EXPECT_NEAR(s[size_t(c)], 0, 1e-15 * scale);
  }
}

TEST(PointLoad, TraceFreeSurfaceAndSymmetry) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-3, 3);
  const double P = 2.5, nu = 0.3;
  for (int trial = 0; trial < 500; ++trial) {
    const double x = u(rng), y = u(rng), d = std::abs(u(rng)) + 1e-3;
    const double rho = std::sqrt(x * x + y * y + d * d);
    const auto s = boussinesq_stress(x, y, d, P, nu);
    const double scale = P / (rho * rho);
    EXPECT_NEAR(s[0] + s[4] + s[8], -(1 + nu) * P * d / (kPi * rho * rho * rho), 1e-12 * scale);
    EXPECT_EQ(s[1], s[3]);
    EXPECT_EQ(s[2], s[6]);
    EXPECT_EQ(s[5], s[7]);
    // Mirror x → −x: the xy and xz shears change sign, nothing else.
    const auto m = boussinesq_stress(-x, y, d, P, nu);
    for (int c = 0; c < 9; ++c) {
      const double sign = (c == 1 || c == 3 || c == 2 || c == 6) ? -1 : 1;
      EXPECT_NEAR(m[size_t(c)], sign * s[size_t(c)], 1e-14 * scale);
    }
    // Swapping x and y swaps the xx and yy stresses.
    const auto w = boussinesq_stress(y, x, d, P, nu);
    EXPECT_NEAR(w[0], s[4], 1e-13 * scale);
    EXPECT_NEAR(w[5], s[2], 1e-13 * scale);
    // The surface is free of traction away from the load.
    const auto f = boussinesq_stress(x, y, 0, P, nu);
    EXPECT_NEAR(f[8], 0, 1e-15 * scale);
    EXPECT_NEAR(f[2], 0, 1e-15 * scale);
    EXPECT_NEAR(f[5], 0, 1e-15 * scale);
  }
}

TEST(PointLoad, IsInEquilibrium) {
  // div σ = 0 in the body, by central differences in the box's frame.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-2, 2);
  const double h = 1e-4;
  for (int trial = 0; trial < 200; ++trial) {
    const double x = u(rng), y = u(rng), z = -(std::abs(u(rng)) + 0.2);
    const double rho = std::sqrt(x * x + y * y + z * z);
    double div[3] = {0, 0, 0};
    for (int j = 0; j < 3; ++j) {
      const double dx = j == 0 ? h : 0, dy = j == 1 ? h : 0, dz = j == 2 ? h : 0;
      const auto p = stress_at(x + dx, y + dy, z + dz), m = stress_at(x - dx, y - dy, z - dz);
      for (int i = 0; i < 3; ++i) div[i] += (p[size_t(3 * i + j)] - m[size_t(3 * i + j)]) / (2 * h);
    }
    const double scale = 2.5 / (rho * rho * rho);  // the size of one derivative
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(div[i], 0, 1e-6 * scale) << trial << " row " << i;
  }
}

TEST(PointLoad, SampledGridWithTheSingularPoint) {
  PointLoadOptions o;
  o.dims = {5, 5, 5};  // (0, 0, 1), the load point, is a sample
  o.load = 3;
  o.poisson_ratio = 0.25;
  const auto [img, stats] = point_load(o);
  EXPECT_EQ(img.dims, (Dims{5, 5, 5}));
  EXPECT_EQ(stats.singular, 1u);
  const DataArray& t = img.point_data.get("stress");
  const DataArray& s = img.point_data.get("effective_stress");
  const DataArray& v = img.point_data.get("vtkValidPointMask");
  EXPECT_EQ(img.point_data.active(AttributeRole::Tensors), &t);
  EXPECT_EQ(img.point_data.active(AttributeRole::Scalars), &s);
  double max_vm = 0;
  for (Index k = 0; k < 5; ++k)
    for (Index j = 0; j < 5; ++j)
      for (Index i = 0; i < 5; ++i) {
        const auto p = static_cast<std::size_t>(i + 5 * (j + 5 * k));
        const Vec3 q = img.point(Index(p));
        if (i == 2 && j == 2 && k == 4) {
          EXPECT_EQ(v.get(p), 0);
          for (int c = 0; c < 9; ++c) EXPECT_EQ(t.get(p, c), 0);
          EXPECT_EQ(s.get(p), 0);
          continue;
        }
        EXPECT_EQ(v.get(p), 1);
        const auto e = boussinesq_stress(q.x, q.y, 1 - q.z, 3, 0.25);
        for (int c = 0; c < 9; ++c) EXPECT_FLOAT_EQ(float(t.get(p, c)), float(e[size_t(c)]));
        const double a = e[0] - e[4], b = e[4] - e[8], c = e[8] - e[0];
        const double vm = std::sqrt(0.5 * (a * a + b * b + c * c) +
                                    3 * (e[1] * e[1] + e[2] * e[2] + e[5] * e[5]));
        EXPECT_FLOAT_EQ(float(s.get(p)), float(vm));
        max_vm = std::max(max_vm, double(float(vm)));
      }
  EXPECT_FLOAT_EQ(float(stats.max_effective_stress), float(max_vm));
  // Without the scalar; a box whose top centre is not a sample has no singular point.
  o.scalars = "";
  o.dims = {4, 4, 4};
  const auto r = point_load(o);
  EXPECT_EQ(r.stats.singular, 0u);
  EXPECT_FALSE(r.output.point_data.has("effective_stress"));
  EXPECT_EQ(r.output.point_data.active(AttributeRole::Scalars), nullptr);
}

TEST(PointLoad, RejectsBadOptions) {
  PointLoadOptions o;
  o.load = -1;
  expect_error([&] { (void)point_load(o); }, "the load must be finite and >= 0, got -1");
  o.load = NAN;
  expect_error([&] { (void)point_load(o); }, "the load must be finite");
  o.load = 1;
  o.poisson_ratio = 0.6;
  expect_error([&] { (void)point_load(o); }, "Poisson's ratio must be in [0, 0.5], got 0.6");
  o.poisson_ratio = 0.3;
  o.dims = {5, 1, 5};
  expect_error([&] { (void)point_load(o); }, "dims must be at least 2");
  o.dims = {5, 5, 5};
  o.bounds.max.z = o.bounds.min.z;
  expect_error([&] { (void)point_load(o); }, "positive extent along every axis (axis z: -1 .. -1)");
  o.bounds.max.z = 1;
  o.scalars = "stress";
  expect_error([&] { (void)point_load(o); }, "need distinct names");
  o.scalars = "effective_stress";
  o.dims = {100000, 100000, 100000};
  expect_error([&] { (void)point_load(o); }, "point load");
}

TEST(PointLoad, RefusesStressBeyondFloat32) {
  PointLoadOptions o;
  o.dims = {5, 5, 5};
  o.load = 1e308;  // finite stresses in double, inf once stored as Float32
  expect_error([&] { (void)point_load(o); },
               "exceeds the Float32 range (3.4e38): lower the load (1e+308)");
  o.load = 1;  // a sample 1e-20 below the load point: 3P/(2π ρ²) ≈ 5e39
  o.bounds = {{-1, -1, -1e-20}, {1, 1, 0}};
  o.dims = {3, 3, 2};
  expect_error([&] { (void)point_load(o); }, "at sample (1, 1, 0) = (0, 0, -1e-20) exceeds");
  o.load = 1e-10;  // the same samples hold a smaller load
  const auto [field, stats] = point_load(o);
  EXPECT_EQ(stats.singular, 1u);
  EXPECT_GT(stats.max_effective_stress, 1e28);
  EXPECT_TRUE(std::isfinite(stats.max_effective_stress));
}
