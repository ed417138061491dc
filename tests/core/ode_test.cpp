#include "isoforge/core/ode.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "isoforge/core/vec.hpp"

using namespace isoforge;

namespace {

// y' = (-y, x, 0): a rotation about z; after time 1 the exact solution is a rotation by 1 rad.
template <class Step>
double error_after_unit_time(Step step, int steps) {
  const auto f = [](const Vec3& y) { return Vec3{-y.y, y.x, 0}; };
  Vec3 y{1, 0, 0};
  const double h = 1.0 / steps;
  for (int i = 0; i < steps; ++i) y = step(f, y, h);
  return norm(y - Vec3{std::cos(1.0), std::sin(1.0), 0});
}

}  // namespace

TEST(Ode, Rk4IsFourthOrder) {
  const auto rk4 = [](auto&& f, const Vec3& y, double h) { return rk4_step(f, y, h); };
  const double e1 = error_after_unit_time(rk4, 10), e2 = error_after_unit_time(rk4, 20);
  EXPECT_LT(e1, 1e-6);
  EXPECT_NEAR(e1 / e2, 16.0, 1.0);  // halving h divides the error by 2^4
}

TEST(Ode, Rk2IsSecondOrder) {
  const auto rk2 = [](auto&& f, const Vec3& y, double h) { return rk2_step(f, y, h); };
  const double e1 = error_after_unit_time(rk2, 20), e2 = error_after_unit_time(rk2, 40);
  EXPECT_LT(e1, 1e-3);
  EXPECT_NEAR(e1 / e2, 4.0, 0.3);  // halving h divides the error by 2^2
}

TEST(Ode, StepsWorkOnScalars) {
  // y' = y from 1: e after unit time.
  double y = 1;
  for (int i = 0; i < 100; ++i) y = rk4_step([](double v) { return v; }, y, 0.01);
  EXPECT_NEAR(y, std::exp(1.0), 1e-9);
}
