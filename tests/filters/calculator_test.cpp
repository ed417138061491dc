// The array calculator: values of every operator and function on known arrays, vector results,
// component access, coordinates, cell data, and errors naming the column.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "isoforge/filters/calculator.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

// 3000 points on a line (enough for three blocks) with scalars P (float), D (int32), vectors V
// (double), a 2-component T and a 6-component S; a cell array C.
PolyData sample() {
  PolyData pd;
  const std::size_t n = 3000;
  DataArray p("P", ScalarType::Float32, 1, n), d("Density", ScalarType::Int32, 1, n),
      v("V", ScalarType::Float64, 3, n), t("T", ScalarType::Float32, 2, n),
      s("S", ScalarType::Float64, 6, n), odd("my array", ScalarType::Float64, 1, n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = double(i) * 0.01;
    pd.points.push_back({x, 2 * x, -x});
    p.set(i, 0, 1 + x);
    d.set(i, 0, double(i % 7 + 1));
    v.set(i, 0, x), v.set(i, 1, 1), v.set(i, 2, -2 * x);
    t.set(i, 0, x), t.set(i, 1, -x);
    for (int k = 0; k < 6; ++k) s.set(i, k, k + x);
    odd.set(i, 0, 3 * x);
  }
  pd.point_data.add(std::move(p), AttributeRole::Scalars);
  pd.point_data.add(std::move(d));
  pd.point_data.add(std::move(v), AttributeRole::Vectors);
  pd.point_data.add(std::move(t));
  pd.point_data.add(std::move(s));
  pd.point_data.add(std::move(odd));
  pd.verts.add({0});
  pd.verts.add({1});
  DataArray c("C", ScalarType::Float64, 1, 2);
  c.set(0, 0, 10), c.set(1, 0, 20);
  pd.cell_data.add(std::move(c));
  return pd;
}

double p_at(std::size_t i) { return double(float(1 + double(i) * 0.01)); }  // P as stored

}  // namespace

TEST(Calculator, ScalarArithmeticAndPrecedence) {
  const PolyData pd = sample();
  const DataArray r = calculate(pd, "r", "P / Density + 2 * -P ^ 2 - (1 - 3)");
  ASSERT_EQ(r.tuples(), 3000u);
  ASSERT_EQ(r.components(), 1);
  EXPECT_EQ(r.type(), ScalarType::Float64);
  for (std::size_t i = 0; i < 3000; i += 37) {
    const double p = p_at(i), d = double(i % 7 + 1);
    // Unary minus binds tighter than ^ on its right operand only: 2 * -(P^2).
    EXPECT_DOUBLE_EQ(r.get(i), p / d + 2 * -(p * p) + 2) << i;
  }
}

TEST(Calculator, FunctionsAndConstants) {
  const PolyData pd = sample();
  const DataArray r = calculate(
      pd, "r", "sqrt(P) + exp(0) + log(1) + log10(100) + sin(pi/2) + cos(0) + abs(-P) + "
               "floor(2.5) + ceil(2.5) + min(P, 0) + max(P, 0) + atan2(1, 1) + pow(2, 3) + "
               "tanh(0) + cosh(0) + sinh(0) + asin(1) + acos(1) + atan(0) + tan(0)");
  for (std::size_t i = 0; i < 3000; i += 101) {
    const double p = p_at(i);
    const double expect = std::sqrt(p) + 1 + 0 + 2 + 1 + 1 + p + 2 + 3 + 0 + p +
                          std::numbers::pi / 4 + 8 + 0 + 1 + 0 + std::numbers::pi / 2 + 0 + 0 + 0;
    EXPECT_NEAR(r.get(i), expect, 1e-12) << i;
  }
}

TEST(Calculator, VectorsComponentsAndCoordinates) {
  const PolyData pd = sample();
  const DataArray mag = calculate(pd, "m", "mag(V)");
  const DataArray v2 = calculate(pd, "v2", "2 * V - [1, 0, coordsX] / 2");
  const DataArray d = calculate(pd, "d", "dot(V, [0, 0, 1]) + V[1] + T[1] + S[5] + \"my array\"");
  const DataArray c = calculate(pd, "c", "cross(V, coords)");
  const DataArray u = calculate(pd, "u", "norm(V)[2] + cross(V, V)[0]");
  ASSERT_EQ(v2.components(), 3);
  ASSERT_EQ(c.components(), 3);
  for (std::size_t i = 0; i < 3000; i += 53) {
    const double x = double(i) * 0.01;
    const Vec3 V{x, 1, -2 * x}, P{x, 2 * x, -x};
    EXPECT_NEAR(mag.get(i), norm(V), 1e-12);
    EXPECT_NEAR(v2.get(i, 0), 2 * x - 0.5, 1e-12);
    EXPECT_NEAR(v2.get(i, 1), 2, 1e-12);
    EXPECT_NEAR(v2.get(i, 2), -4 * x - double(float(x)) / 2, 1e-12);  // points are float
    EXPECT_NEAR(d.get(i), -2 * x + 1 + double(float(-x)) + (5 + x) + 3 * x, 1e-6);
    const Vec3 cp = cross(V, Vec3{double(float(P.x)), double(float(P.y)), double(float(P.z))});
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.get(i, k), cp[k], 1e-12);
    EXPECT_NEAR(u.get(i), -2 * x / norm(V), 1e-12);
  }
}

TEST(Calculator, CellArraysAndFloat32Result) {
  const PolyData pd = sample();
  CalculatorOptions o;
  o.cells = true;
  o.type = ScalarType::Float32;
  const DataArray r = calculate(pd, "half", "C / 2", o);
  ASSERT_EQ(r.tuples(), 2u);
  EXPECT_EQ(r.type(), ScalarType::Float32);
  EXPECT_EQ(r.get(0), 5.0);
  EXPECT_EQ(r.get(1), 10.0);
  expect_error([&] { (void)calculate(pd, "x", "coordsX", o); },
               "column 1: coords are point coordinates: not available over cells");
  expect_error([&] { (void)calculate(pd, "x", "P", o); },
               "column 1: no cell array 'P' (cell arrays: 'C')");
}

TEST(Calculator, ImageDataCoordinatesOverManyBlocks) {
  ImageData img;
  img.dims = {40, 30, 20};
  img.origin = {1, 2, 3};
  img.spacing = {0.5, 0.25, 2};
  const DataArray r = calculate(img, "r", "coordsX + 10 * coordsY + 100 * coordsZ");
  ASSERT_EQ(r.tuples(), img.num_points());
  for (std::size_t i = 0; i < r.tuples(); i += 97) {
    const Vec3 p = img.point(Index(i));
    EXPECT_DOUBLE_EQ(r.get(i), p.x + 10 * p.y + 100 * p.z);
  }
}

TEST(Calculator, ErrorsNameTheColumn) {
  const PolyData pd = sample();
  auto err = [&](const char* e, const std::string& text) {
    expect_error([&] { (void)calculate(pd, "r", e); }, text);
  };
  err("P + Presure", "column 5: no point array 'Presure' (point arrays: 'P', 'Density'");
  err("P + V", "column 3: cannot add a scalar and a vector");
  err("V * V", "column 3: cannot multiply two vectors: use dot() or cross()");
  err("P / V", "column 3: cannot divide by a vector");
  err("mag(P)", "column 5: mag() needs a vector, got a scalar");
  err("sqrt(V)", "column 6: sqrt() needs a scalar, got a vector");
  err("T + 1", "column 1: array 'T' has 2 components: use 'T[i]' for one of them");
  err("V[3]", "column 2: component 3 of 3 components (they count from 0)");
  err("P[0]", "column 2: a scalar has no components");
  err("min(P)", "column 1: min() takes 2 arguments, got 1");
  err("foo(P)", "column 1: unknown function 'foo'");
  err("(P + 1", "column 7: expected ')' to close '(' at the end");
  err("P +", "column 4: expected a value at the end");
  err("P $ 2", "column 3: unexpected '$'");
  err("", "column 1: the expression is empty");
  err("[1, 2]", "column 6: expected ',' between a vector's values, got ']'");
  err("1e999", "column 1: not a finite number");
  err("\"unclosed", "column 1: unterminated quoted array name");
  std::string deep(150, '(');
  deep += "1" + std::string(150, ')');
  err(deep.c_str(), "nested more than 100 levels deep");
  expect_error([&] { (void)calculate(pd, "", "P"); }, "the result array needs a name");
  CalculatorOptions o;
  o.type = ScalarType::Int32;
  expect_error([&] { (void)calculate(pd, "r", "P", o); }, "must be Float32 or Float64");
}
