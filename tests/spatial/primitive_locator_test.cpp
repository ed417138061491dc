#include "isoforge/spatial/primitive_locator.hpp"

#include <gtest/gtest.h>

#include <random>

#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

using Id = PrimitiveSet::Id;

// Random small points, segments and triangles in the unit cube (some degenerate).
PrimitiveSet random_set(std::mt19937& rng, Id n_points, Id n_segments, Id n_triangles) {
  std::uniform_real_distribution<double> u(0, 1), near(-0.05, 0.05);
  std::vector<Vec3> v;
  Vec3 base;
  // A new vertex: anywhere, or near the previous one (a primitive's later vertices).
  const auto vertex = [&](bool first = true) {
    base = first ? Vec3{u(rng), u(rng), u(rng)} : base;
    v.push_back(first ? base : base + Vec3{near(rng), near(rng), near(rng)});
    return static_cast<Id>(v.size() - 1);
  };
  std::vector<Id> points;
  std::vector<std::array<Id, 2>> segments;
  std::vector<std::array<Id, 3>> triangles;
  for (Id i = 0; i < n_points; ++i) points.push_back(vertex());
  for (Id i = 0; i < n_segments; ++i) {
    const Id a = vertex();
    segments.push_back({a, vertex(false)});
  }
  for (Id i = 0; i < n_triangles; ++i) {
    const Id a = vertex();
    // Every tenth triangle is degenerate (a repeated vertex).
    const Id b = vertex(false);
    triangles.push_back({a, b, i % 10 == 0 ? a : vertex(false)});
  }
  return PrimitiveSet(std::move(v), std::move(points), std::move(segments), std::move(triangles));
}

ClosestPrimitive brute_force(const PrimitiveSet& set, const Vec3& p) {
  ClosestPrimitive best;
  for (Id id = 0; id < set.size(); ++id) {
    const double d2 = set.dist2(id, p);
    if (d2 < best.dist2) best.dist2 = d2, best.id = id;  // ties: the first (smallest) id
  }
  return best;
}

}  // namespace

TEST(PrimitiveLocator, ClosestEqualsBruteForce) {
  std::mt19937 rng(7);
  const PrimitiveSet set = random_set(rng, 200, 300, 2000);
  const PrimitiveLocator locator(set);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int q = 0; q < 2000; ++q) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    const ClosestPrimitive got = locator.closest(p);
    const ClosestPrimitive want = brute_force(set, p);
    ASSERT_EQ(got.id, want.id) << "query " << q;
    ASSERT_EQ(got.dist2, want.dist2);
    EXPECT_LT(got.evaluations, set.size() / 4);  // the hierarchy prunes most primitives
  }
  EXPECT_EQ(closest_primitive(set, {0.5, 0.5, 0.5}).id, brute_force(set, {0.5, 0.5, 0.5}).id);
}

TEST(PrimitiveLocator, TiesGoToTheSmallestIdAndLimitsBound) {
  // Two copies of one triangle and one point: every query ties between ids 1 and 2.
  std::vector<Vec3> v = {{5, 5, 5}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const PrimitiveSet set(v, {0}, {}, {{1, 2, 3}, {1, 2, 3}});
  const PrimitiveLocator locator(set);
  const ClosestPrimitive c = locator.closest({0.2, 0.2, 1});
  EXPECT_EQ(c.id, 1u);
  EXPECT_DOUBLE_EQ(c.dist2, 1.0);
  // Nothing within the limit: the candidate is kept.
  ClosestPrimitive seeded;
  seeded.id = 0;
  seeded.dist2 = set.dist2(0, {0.2, 0.2, 1});
  locator.nearest({0.2, 0.2, 1}, 0.25, seeded);
  EXPECT_EQ(seeded.id, 0u);
  // Within it: improved.
  locator.nearest({0.2, 0.2, 1}, 4.0, seeded);
  EXPECT_EQ(seeded.id, 1u);
}

TEST(PrimitiveLocator, AnyWithinIsNeverWronglyFalse) {
  std::mt19937 rng(11);
  const PrimitiveSet set = random_set(rng, 20, 20, 50);
  const PrimitiveLocator locator(set);
  std::uniform_real_distribution<double> u(-1, 2), r(0, 0.3);
  for (int q = 0; q < 500; ++q) {
    Vec3 lo{u(rng), u(rng), u(rng)};
    const Vec3 hi = lo + Vec3{r(rng), r(rng), r(rng)};
    const double reach = r(rng);
    bool any = false;  // some primitive's box within reach of the query box
    for (Id id = 0; id < set.size(); ++id) {
      const Bounds b = set.bounds(id);
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double d = std::max({0.0, b.min[a] - hi[a], lo[a] - b.max[a]});
        d2 += d * d;
      }
      any = any || d2 <= reach * reach;
    }
    if (any) {
      ASSERT_TRUE(locator.any_within(lo, hi, reach * reach)) << q;
    }
  }
}

TEST(PrimitiveSet, CountsIdsAndRejectsBadInput) {
  const PrimitiveSet set({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 2}, {{0, 1}}, {{0, 1, 2}});
  EXPECT_EQ(set.size(), 4u);
  EXPECT_EQ(set.segment_begin(), 2u);
  EXPECT_EQ(set.triangle_begin(), 3u);
  EXPECT_DOUBLE_EQ(set.dist2(2, {0.5, 1, 0}), 1.0);  // the segment from (0,0,0) to (1,0,0)
  expect_error([] { (void)PrimitiveSet({{0, 0, 0}}, {1}, {}, {}); }, "vertex id 1 is out of range");
  expect_error([] { (void)PrimitiveSet({{NAN, 0, 0}}, {0}, {}, {}); }, "vertex 0 is not finite");
  PrimitiveSet balls({{0, 0, 0}}, {0}, {}, {});
  expect_error([&] { balls.set_radii({-1}); }, "radius of point 0");
  expect_error([&] { balls.set_radii({1, 2}); }, "2 radii for 1 points");
  balls.set_radii({0.5});
  EXPECT_EQ(balls.radius(0), 0.5);
}

TEST(PrimitiveSet, FromPolyData) {
  PolyData pd;
  for (int i = 0; i < 5; ++i) pd.points.push_back({double(i), 0, 0});
  pd.verts.add({0, 1});        // a poly-vertex: two points
  pd.lines.add({1, 2, 3});     // a polyline: two segments
  pd.polys.add({0, 1, 2, 3});  // a quad: two triangles
  const PrimitiveSet set = primitives_of(pd, "test");
  EXPECT_EQ(set.points().size(), 2u);
  EXPECT_EQ(set.segments().size(), 2u);
  EXPECT_EQ(set.triangles().size(), 2u);
  expect_error([] { (void)primitives_of(PolyData{}, "test"); }, "test: the input is empty");
}
