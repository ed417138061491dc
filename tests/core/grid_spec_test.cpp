#include "isoforge/core/grid_spec.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

TEST(GridSpec, FromBoundsPutsSamplesOnTheCorners) {
  Bounds b;
  b.min = {-1, 0, 2};
  b.max = {1, 4, 2};
  const GridSpec g = GridSpec::from_bounds(b, {5, 3, 1});
  EXPECT_EQ(g.spacing, (Vec3{0.5, 2, 1}));  // a flat axis of one sample keeps spacing 1
  EXPECT_EQ(g.point(4, 2, 0), (Vec3{1, 4, 2}));
  EXPECT_EQ(g.num_points(), 15u);
  const ImageData img = g.image();
  EXPECT_EQ(img.dims, g.dims);
  EXPECT_EQ(img.point(4, 2, 0), g.point(4, 2, 0));
  expect_error([&] { (void)GridSpec::from_bounds(b, {5, 3, 2}); }, "axis 2 has zero extent");
  expect_error([&] { (void)GridSpec::from_bounds(Bounds{}, {2, 2, 2}); }, "empty or not finite");
}

TEST(GridSpec, ValidateNamesTheProblem) {
  GridSpec g;
  g.dims = {4, 4, 1};
  g.spacing = {1, 1, 0};
  EXPECT_NO_THROW(g.validate("sample"));  // the flat axis needs no spacing
  expect_error([&] { g.validate("distance", true); }, "distance: spacing along axis 2 is 0");
  g.spacing = {1, NAN, 1};
  expect_error([&] { g.validate("sample"); }, "spacing along axis 1");
  g.spacing = {1, 1, 1};
  g.origin = {INFINITY, 0, 0};
  expect_error([&] { g.validate("sample"); }, "origin is not finite");
  g.origin = {};
  g.dims = {0, 4, 4};
  EXPECT_THROW(g.validate("sample"), Error);
}

TEST(CubicGrid, CoversThePaddedBoxWithCubes) {
  Bounds b;
  b.min = {0, 0, 0};
  b.max = {1, 0.5, 0.25};
  const GridSpec g = cubic_grid(b, 0.1, 0.05);
  EXPECT_EQ(g.spacing, (Vec3{0.1, 0.1, 0.1}));
  EXPECT_EQ(g.origin, (Vec3{-0.05, -0.05, -0.05}));
  for (int a = 0; a < 3; ++a) EXPECT_GE(g.coordinate(a, g.dims[a] - 1), b.max[a] + 0.05 - 1e-12);
  EXPECT_EQ(g.dims, (Dims{12, 7, 5}));  // ceil(1.1 / 0.1) + 1, ceil(0.6 / 0.1) + 1, ...
  expect_error([&] { (void)cubic_grid(b, 0); }, "voxel size");
  expect_error([&] { (void)cubic_grid(b, 0.1, -1); }, "padding");
  expect_error([&] { (void)cubic_grid(b, 1e-12); }, "2^30");
}
