#include "isoforge/reduce/mesh_distance.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>

#include "isoforge/core/error.hpp"

using namespace isoforge;

namespace {

// The square [x0, x1] × [y0, y1] at height z, as two triangles (double coordinates).
PolyData square(double x0, double x1, double y0, double y1, double z) {
  PolyData m;
  m.points = Points(0, ScalarType::Float64);
  m.points.push_back({x0, y0, z});
  m.points.push_back({x1, y0, z});
  m.points.push_back({x1, y1, z});
  m.points.push_back({x0, y1, z});
  m.polys.add({0, 1, 2});
  m.polys.add({0, 2, 3});
  return m;
}

// A UV sphere of radius r: n rings × 2n segments, poles shared (double coordinates).
PolyData sphere(double r, int n) {
  PolyData m;
  m.points = Points(0, ScalarType::Float64);
  m.points.push_back({0, 0, r});
  for (int i = 1; i < n; ++i) {
    const double theta = std::numbers::pi * i / n;
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = std::numbers::pi * j / n;
      m.points.push_back({r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                          r * std::cos(theta)});
    }
  }
  m.points.push_back({0, 0, -r});
  const Index south = Index(m.points.size() - 1);
  const auto id = [n](int ring, int j) { return Index(1 + (ring - 1) * 2 * n + (j % (2 * n))); };
  for (int j = 0; j < 2 * n; ++j) {
    m.polys.add({0, id(1, j), id(1, j + 1)});
    for (int i = 1; i + 1 < n; ++i) {
      m.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
    m.polys.add({id(n - 1, j), south, id(n - 1, j + 1)});
  }
  return m;
}

PolyData scaled(const PolyData& in, double s) {
  PolyData m = in;
  for (std::size_t i = 0; i < m.points.size(); ++i) m.points.set(i, m.points[i] * s);
  return m;
}

}  // namespace

// Every point of one square lies straight above/below a point of the other, at distance d:
// every sample's distance is d, so all statistics are d.
TEST(mesh_distance, ParallelSquares) {
  const double d = 0.375;
  MeshDistanceOptions options;
  options.samples = 5000;
  const MeshDistance r = mesh_distance(square(0, 1, 0, 1, 0), square(0, 1, 0, 1, d), options);
  EXPECT_NEAR(r.hausdorff, d, 1e-12);
  EXPECT_NEAR(r.rms, d, 1e-12);
  EXPECT_NEAR(r.mean, d, 1e-12);
  EXPECT_NEAR(r.max_a_to_b, d, 1e-12);
  EXPECT_NEAR(r.max_b_to_a, d, 1e-12);
  EXPECT_NEAR(r.rms_a_to_b, d, 1e-12);
  EXPECT_NEAR(r.rms_b_to_a, d, 1e-12);
  EXPECT_EQ(r.samples_a, 4u + 5000u);  // 4 vertices + the area samples
  EXPECT_EQ(r.samples_b, 4u + 5000u);
  EXPECT_DOUBLE_EQ(r.diagonal, std::sqrt(2.0));
  EXPECT_NEAR(r.relative_hausdorff(), d / std::sqrt(2.0), 1e-12);
}

TEST(mesh_distance, MeshAgainstItselfIsZero) {
  const PolyData s = sphere(1, 24);
  const MeshDistance r = mesh_distance(s, s);
  EXPECT_LT(r.hausdorff, 1e-14);  // rounding of the sample positions only
  EXPECT_LT(r.rms, 1e-15);
  // Automatic count: max(1e5, 10 × 2208 triangles) area samples plus the 1106 vertices
  // (2 poles + 23 rings of 48).
  EXPECT_EQ(r.samples_a, 100000u + 1106u);
}

// The sphere scaled by 1.01: a scaled vertex is 0.01 from its original (and no closer to the
// convex original), points on faces are 0.01 × (their face plane's distance from the center,
// > 0.99 here) from the original face, so the Hausdorff distance is 0.01 and the RMS just below.
TEST(mesh_distance, ScaledSphere) {
  const PolyData s = sphere(1, 32);
  const MeshDistance r = mesh_distance(s, scaled(s, 1.01));
  EXPECT_NEAR(r.hausdorff, 0.01, 1e-9);
  EXPECT_NEAR(r.max_a_to_b, 0.01 * 0.999, 0.01 * 0.002);  // from the original: to faces
  EXPECT_GT(r.rms, 0.0099);
  EXPECT_LT(r.rms, 0.01);
  EXPECT_GT(r.mean, 0.0099);
  EXPECT_NEAR(r.diagonal, 2 * std::sqrt(3.0), 1e-2);
}

// A small square inside a large one (same plane): every point of the small one is on the large
// one (0 to rounding), while the large one's corners are sqrt(0.25² + 0.25²) from the small one.
TEST(mesh_distance, OneSidedAsymmetry) {
  const MeshDistance r = mesh_distance(square(0.25, 0.75, 0.25, 0.75, 0), square(0, 1, 0, 1, 0));
  EXPECT_LT(r.max_a_to_b, 1e-15);
  EXPECT_NEAR(r.max_b_to_a, std::sqrt(0.125), 1e-15);
  EXPECT_EQ(r.hausdorff, r.max_b_to_a);
  EXPECT_GT(r.rms_b_to_a, 0.1);
  EXPECT_LT(r.rms_a_to_b, 1e-15);
  EXPECT_DOUBLE_EQ(r.diagonal, std::sqrt(0.5));  // of a: the small square
}

TEST(mesh_distance, SameResultForAnyThreadCountAndSeedMatters) {
  const PolyData s = sphere(1, 20), t = scaled(sphere(1, 13), 1.02);
  MeshDistance r1, r4;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    r1 = mesh_distance(s, t);
  }
  {
    tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
    r4 = mesh_distance(s, t);
  }
  EXPECT_EQ(r1.hausdorff, r4.hausdorff);
  EXPECT_EQ(r1.rms, r4.rms);
  EXPECT_EQ(r1.mean, r4.mean);
  MeshDistanceOptions other;
  other.seed = 2;
  EXPECT_NE(mesh_distance(s, t, other).rms, r1.rms);
}

TEST(mesh_distance, ProgressAndErrors) {
  const PolyData s = sphere(1, 8);
  MeshDistanceOptions options;
  double last = -1;
  options.progress = [&](double f) {
    last = f;
    return true;
  };
  (void)mesh_distance(s, s, options);
  EXPECT_EQ(last, 1.0);
  options.progress = [](double) { return false; };
  EXPECT_THROW((void)mesh_distance(s, s, options), Cancelled);

  PolyData lines;
  lines.points.push_back({0, 0, 0});
  lines.points.push_back({1, 0, 0});
  lines.lines.add({0, 1});
  EXPECT_THROW((void)mesh_distance(lines, s), Error);  // no triangles in a
  EXPECT_THROW((void)mesh_distance(s, PolyData{}), Error);
  PolyData bad = s;
  bad.polys.add({0, 1, 100000});
  EXPECT_THROW((void)mesh_distance(s, bad), Error);
}
