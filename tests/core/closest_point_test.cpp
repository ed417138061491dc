#include "isoforge/core/closest_point.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "isoforge/core/cell.hpp"

using namespace isoforge;

namespace {

Vec3 random_point(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

// Independent reference: the closest point of core/cell.hpp (Ericson's method).
double reference_triangle_d2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const std::array<Vec3, 3> pts{a, b, c};
  return locate_in_cell(CellType::Triangle, pts, p).dist2;
}

// Dense sampling of the triangle: an upper bound that converges to the distance.
double sampled_triangle_d2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  double best = 1e300;
  const int n = 200;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double s = double(i) / n, t = double(j) / n;
      best = std::min(best, norm2(p - (a + (b - a) * s + (c - a) * t)));
    }
  return best;
}

}  // namespace

TEST(ClosestPoint, TriangleMatchesEricsonOnRandomInput) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 a = random_point(rng, -1, 1), b = random_point(rng, -1, 1),
               c = random_point(rng, -1, 1), p = random_point(rng, -3, 3);
    const TriangleClosest r = closest_on_triangle(p, a, b, c);
    const double ref = reference_triangle_d2(p, a, b, c);
    ASSERT_NEAR(r.dist2, ref, 1e-12 * (1 + ref)) << trial;
    // The closest point is on the triangle and its (s, t) reproduce it.
    ASSERT_GE(r.s, 0);
    ASSERT_GE(r.t, 0);
    ASSERT_LE(r.s + r.t, 1 + 1e-12);
    ASSERT_LT(norm(r.point - (a + (b - a) * r.s + (c - a) * r.t)), 1e-12);
    ASSERT_DOUBLE_EQ(r.dist2, norm2(p - r.point));
  }
}

TEST(ClosestPoint, TriangleUpperBoundedBySampling) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = random_point(rng, -1, 1), b = random_point(rng, -1, 1),
               c = random_point(rng, -1, 1), p = random_point(rng, -2, 2);
    const double d = std::sqrt(triangle_distance2(p, a, b, c));
    const double sampled = std::sqrt(sampled_triangle_d2(p, a, b, c));
    ASSERT_LE(d, sampled + 1e-12);
    ASSERT_GT(d, sampled - 0.02);  // the sampling step is 1/200 of the edges
  }
}

TEST(ClosestPoint, FeaturesNameWhereTheClosestPointIs) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  using F = TriangleFeature;
  EXPECT_EQ(closest_on_triangle({0.2, 0.2, 1}, a, b, c).feature, F::Face);
  EXPECT_EQ(closest_on_triangle({-1, -1, 0}, a, b, c).feature, F::Vertex0);
  EXPECT_EQ(closest_on_triangle({2, -0.5, 0.3}, a, b, c).feature, F::Vertex1);
  EXPECT_EQ(closest_on_triangle({-0.1, 3, 0}, a, b, c).feature, F::Vertex2);
  EXPECT_EQ(closest_on_triangle({0.5, -1, 0}, a, b, c).feature, F::Edge01);
  EXPECT_EQ(closest_on_triangle({1, 1, 0}, a, b, c).feature, F::Edge12);
  EXPECT_EQ(closest_on_triangle({-1, 0.5, 2}, a, b, c).feature, F::Edge20);
  const TriangleClosest e = closest_on_triangle({1, 1, 0}, a, b, c);
  EXPECT_NEAR(e.point.x, 0.5, 1e-15);
  EXPECT_NEAR(e.point.y, 0.5, 1e-15);
  EXPECT_NEAR(e.dist2, 0.5, 1e-15);
}

TEST(ClosestPoint, DegenerateTrianglesAreTheirEdges) {
  // Collinear and repeated points: the distance to the union of the edges.
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{3, 0, 0};
  EXPECT_DOUBLE_EQ(triangle_distance2({2, 1, 0}, a, b, c), 1.0);
  EXPECT_DOUBLE_EQ(triangle_distance2({4, 0, 0}, a, b, c), 1.0);
  EXPECT_DOUBLE_EQ(triangle_distance2({1, 1, 1}, a, a, a), 3.0);
  EXPECT_DOUBLE_EQ(triangle_distance2({0.5, 2, 0}, a, b, b), 4.0);
}

TEST(ClosestPoint, Segment) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0};
  EXPECT_DOUBLE_EQ(segment_distance2({1, 1, 0}, a, b), 1.0);
  EXPECT_DOUBLE_EQ(segment_distance2({-1, 0, 0}, a, b), 1.0);
  EXPECT_DOUBLE_EQ(segment_distance2({3, 0, 1}, a, b), 2.0);
  EXPECT_DOUBLE_EQ(closest_on_segment({1.5, 5, 0}, a, b).t, 0.75);
  // A zero-length segment is its point.
  EXPECT_DOUBLE_EQ(segment_distance2({1, 1, 1}, a, a), 3.0);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 5000; ++trial) {
    const Vec3 p = random_point(rng, -2, 2), s0 = random_point(rng, -1, 1),
               s1 = random_point(rng, -1, 1);
    const std::array<Vec3, 2> pts{s0, s1};
    const double ref = locate_in_cell(CellType::Line, pts, p).dist2;
    ASSERT_NEAR(segment_distance2(p, s0, s1), ref, 1e-12 * (1 + ref));
  }
}
