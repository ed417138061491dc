#include "isoforge/spatial/self_intersections.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "isoforge/core/error.hpp"
#include "isoforge/core/predicates.hpp"

using namespace isoforge;

namespace {

using Pairs = std::vector<std::pair<Index, Index>>;

PolyData make_mesh(const std::vector<Vec3>& pts, const std::vector<std::array<Index, 3>>& tris) {
  PolyData m;
  for (const Vec3& p : pts) m.points.push_back(p);
  for (const auto& t : tris) m.polys.add({t[0], t[1], t[2]});
  return m;
}

// The octahedron: equator e0..e3 = ids 0..3, top = 4, bottom = 5. Faces 0..3 are the top fan
// T_k = (top, e_k, e_k+1), faces 4..7 the bottom fan B_k = (bottom, e_k+1, e_k).
PolyData octahedron(const Vec3& top) {
  const std::vector<Vec3> pts{{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, top, {0, 0, -1}};
  std::vector<std::array<Index, 3>> tris;
  for (Index k = 0; k < 4; ++k) tris.push_back({4, k, (k + 1) % 4});
  for (Index k = 0; k < 4; ++k) tris.push_back({5, (k + 1) % 4, k});
  return make_mesh(pts, tris);
}

// Brute force: every pair of non-degenerate triangles through faces_intersect.
Pairs brute_force(const PolyData& m) {
  std::vector<std::array<Index, 3>> tris;
  for (std::size_t c = 0; c < m.polys.size(); ++c) {
    auto ids = m.polys.cell(c);
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) tris.push_back({ids[0], ids[k], ids[k + 1]});
  }
  const auto corners = [&](const std::array<Index, 3>& t) {
    return std::array<Vec3, 3>{m.points[std::size_t(t[0])], m.points[std::size_t(t[1])],
                               m.points[std::size_t(t[2])]};
  };
  const auto ok = [&](const std::array<Index, 3>& t) {
    const auto p = corners(t);
    return t[0] != t[1] && t[1] != t[2] && t[0] != t[2] && !triangle_degenerate(p[0], p[1], p[2]);
  };
  Pairs r;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    if (!ok(tris[i])) continue;
    for (std::size_t j = i + 1; j < tris.size(); ++j) {
      if (ok(tris[j]) && faces_intersect(corners(tris[i]), tris[i], corners(tris[j]), tris[j])) {
        r.emplace_back(Index(i), Index(j));
      }
    }
  }
  return r;
}

}  // namespace

TEST(self_intersections, TwoCrossingTriangles) {
  const PolyData m =
      make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0.5}},
                {{0, 1, 2}, {3, 4, 5}});
  EXPECT_EQ(self_intersections(m), (Pairs{{0, 1}}));
}

TEST(self_intersections, ClosedOctahedronHasNone) {
  EXPECT_TRUE(self_intersections(octahedron({0, 0, 1})).empty());
}

// The top vertex pushed through the bottom half to (0.75, 0, −0.5), outside the bottom pyramid
// |x| + |y| ≤ z + 1. In the plane y = 0 the top faces T_1 = (top, e1, e2) and T_2 = (top, e2, e3)
// reduce to the segment e2–top, which crosses the bottom pyramid's edge bottom–e0 (shared by
// B_0 and B_3) at a point off every shared vertex; T_1 and T_2 lie on either side of y = 0 and
// each meets both B_0 and B_3 there (B_0 shares e1 with T_1, B_3 shares e3 with T_2: the contact
// is off those vertices). T_0 and T_3 meet the bottom faces only at e0, e1, e3 or along shared
// non-coplanar edges, and the top fan stays a fan. So 4 pairs: (1,4), (1,7), (2,4), (2,7).
TEST(self_intersections, OctahedronWithVertexPushedThrough) {
  const PolyData m = octahedron({0.75, 0, -0.5});
  const Pairs expected{{1, 4}, {1, 7}, {2, 4}, {2, 7}};
  EXPECT_EQ(self_intersections(m), expected);
  EXPECT_EQ(brute_force(m), expected);
}

// The top vertex moved exactly onto the bottom vertex's position: T_k and B_k coincide
// (overlapping across their shared edge), T_k meets B_k±1 along the segment from their shared
// equator vertex to the common apex position, and T_k touches B_k+2 at that apex point. The
// apexes have different ids, so every such contact counts: 4 × 4 = 16 pairs; the fans
// themselves are fine.
TEST(self_intersections, OctahedronFoldedFlatOntoItself) {
  const Pairs r = self_intersections(octahedron({0, 0, -1}));
  EXPECT_EQ(r.size(), 16u);
  for (const auto& [i, j] : r) {
    EXPECT_LT(i, 4);
    EXPECT_GE(j, 4);
  }
}

TEST(self_intersections, FoldedEdge) {
  // Two faces sharing edge (1, 2), the second folded back onto the first (coplanar, third
  // corners on the same side of the edge): 1 pair. Unfolded (3 across the edge): none.
  EXPECT_EQ(self_intersections(make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 0}},
                                         {{0, 1, 2}, {1, 3, 2}})),
            (Pairs{{0, 1}}));
  EXPECT_TRUE(self_intersections(
                  make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}}, {{0, 1, 2}, {1, 3, 2}}))
                  .empty());
}

TEST(self_intersections, DegenerateFacesAreSkipped) {
  // Face 1 is collinear (on the line through 0 and 1), face 2 repeats an id; both cross face 0's
  // region, but neither has an interior to intersect with.
  const PolyData m =
      make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {0.5, 0.5, 0}},
                {{0, 1, 2}, {3, 4, 5}, {3, 4, 4}});
  EXPECT_TRUE(self_intersections(m).empty());
}

TEST(self_intersections, PolygonsAndStripsNumberedAsTriangulateFaces) {
  // A quad at z = 0 (triangles 0 = (0, 1, 2) below the diagonal y = x, 1 = (0, 2, 3) above) and
  // a strip 4 5 6 7 (triangles 2 = (4, 5, 6) and 3 = (6, 5, 7)). Triangle 2 stands across z = 0
  // along the segment (1.5, 0.2)–(1.6, 0.3), inside triangle 0; triangle 3 lies in z ≥ 0 and
  // touches z = 0 only at point 6 = (1.6, 0.3, 0), also inside triangle 0. The strip's two
  // triangles share the non-coplanar edge 5–6. So: (0, 2) and (0, 3).
  PolyData m;
  for (const Vec3& p : std::vector<Vec3>{{0, 0, 0},
                                         {2, 0, 0},
                                         {2, 2, 0},
                                         {0, 2, 0},
                                         {1.5, 0.2, -1},
                                         {1.5, 0.2, 1},
                                         {1.6, 0.3, 0},
                                         {0.2, 1.5, 0.5}}) {
    m.points.push_back(p);
  }
  m.polys.add({0, 1, 2, 3});
  m.strips.add({4, 5, 6, 7});
  EXPECT_EQ(self_intersections(m), (Pairs{{0, 2}, {0, 3}}));
}

// A random soup of small triangles sharing vertices (ids drawn from a small pool): the grid
// finds exactly the pairs of the quadratic search, and max_pairs keeps a prefix.
TEST(self_intersections, RandomSoupMatchesBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 4);
  std::uniform_real_distribution<double> d(-0.6, 0.6);
  std::vector<Vec3> pts;
  for (int i = 0; i < 300; ++i) pts.push_back({u(rng), u(rng), u(rng)});
  std::vector<std::array<Index, 3>> tris;
  std::uniform_int_distribution<Index> id(0, 299);
  for (int n = 0; n < 700; ++n) {
    // A corner from the pool (shared between triangles), two new points near it.
    const Index a = id(rng);
    const Vec3 p = pts[std::size_t(a)];
    pts.push_back(p + Vec3{d(rng), d(rng), d(rng)});
    pts.push_back(p + Vec3{d(rng), d(rng), d(rng)});
    const Index b = n % 3 == 0 ? id(rng) : Index(pts.size() - 2);
    tris.push_back({a, b, Index(pts.size() - 1)});
  }
  const PolyData m = make_mesh(pts, tris);
  const Pairs expected = brute_force(m);
  ASSERT_GT(expected.size(), 50u);
  EXPECT_EQ(self_intersections(m), expected);
  SelfIntersectionOptions options;
  options.max_pairs = 7;
  EXPECT_EQ(self_intersections(m, options), Pairs(expected.begin(), expected.begin() + 7));
}

TEST(self_intersections, ProgressAndCancel) {
  const PolyData m = octahedron({0.75, 0, -0.5});
  SelfIntersectionOptions options;
  double last = -1;
  options.progress = [&](double f) {
    last = f;
    return true;
  };
  EXPECT_EQ(self_intersections(m, options).size(), 4u);
  EXPECT_EQ(last, 1.0);
  options.progress = [](double) { return false; };
  EXPECT_THROW((void)self_intersections(m, options), Cancelled);
}

TEST(self_intersections, BadInput) {
  PolyData m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 1, 3}});
  EXPECT_THROW((void)self_intersections(m), Error);  // id 3 out of range
  PolyData n =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}, {{0, 1, 2}, {0, 1, 3}});
  EXPECT_THROW((void)self_intersections(n), Error);
  EXPECT_TRUE(self_intersections(PolyData{}).empty());
}

// ---------------------------------------------------------------------------------------------
// TriangleGrid

namespace {

struct Box {
  Vec3 lo, hi;
};

bool overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k) {
    if (a.lo[k] > b.hi[k] || a.hi[k] < b.lo[k]) return false;
  }
  return true;
}

// A random box with float coordinates (so the grid's float boxes are exact), partly outside
// the grid's bounds [0, 10]^3 sometimes.
Box random_box(std::mt19937& rng, double max_size) {
  std::uniform_real_distribution<float> c(-0.5f, 10.5f);
  std::uniform_real_distribution<float> s(0.0f, static_cast<float>(max_size));
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = c(rng);
    b.hi[k] = static_cast<float>(b.lo[k] + s(rng));
  }
  return b;
}

}  // namespace

TEST(self_intersections_grid, MatchesBruteForceUnderInsertAndRemove) {
  std::mt19937 rng(9);
  Bounds bounds;
  bounds.extend({0, 0, 0});
  bounds.extend({10, 10, 10});
  TriangleGrid grid(bounds, 0.7);
  std::vector<Box> boxes;
  std::vector<bool> present;
  for (std::uint32_t f = 0; f < 3000; ++f) {
    boxes.push_back(random_box(rng, f % 10 == 0 ? 4.0 : 0.8));  // some span many cells
    present.push_back(true);
    grid.insert(f, boxes[f].lo, boxes[f].hi);
  }
  // Remove a third, re-insert some of them with new boxes.
  std::uniform_int_distribution<std::uint32_t> any(0, 2999);
  for (int n = 0; n < 1000; ++n) {
    const std::uint32_t f = any(rng);
    if (!present[f]) continue;
    grid.remove(f, boxes[f].lo, boxes[f].hi);
    present[f] = false;
    if (n % 4 == 0) {
      boxes[f] = random_box(rng, 1.5);
      grid.insert(f, boxes[f].lo, boxes[f].hi);
      present[f] = true;
    }
  }
  EXPECT_EQ(grid.size(), std::size_t(std::count(present.begin(), present.end(), true)));
  std::size_t reported_total = 0;
  for (int n = 0; n < 500; ++n) {
    const Box q = random_box(rng, n % 5 == 0 ? 6.0 : 1.0);
    std::vector<std::uint32_t> got;
    grid.for_each_candidate(q.lo, q.hi, [&](std::uint32_t f) { got.push_back(f); });
    std::vector<std::uint32_t> expected;
    for (std::uint32_t f = 0; f < boxes.size(); ++f) {
      if (present[f] && overlap(boxes[f], q)) expected.push_back(f);
    }
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expected);  // each overlapping face exactly once, nothing else
    reported_total += got.size();
  }
  EXPECT_GT(reported_total, 5000u);
}

TEST(self_intersections_grid, RemoveChecksTheBox) {
  Bounds bounds;
  bounds.extend({0, 0, 0});
  bounds.extend({1, 1, 1});
  TriangleGrid grid(bounds, 0.1);
  grid.insert(3, {0.1, 0.1, 0.1}, {0.15, 0.15, 0.15});
  EXPECT_THROW(grid.remove(3, {0.8, 0.8, 0.8}, {0.9, 0.9, 0.9}), Error);
  EXPECT_THROW(grid.remove(4, {0.1, 0.1, 0.1}, {0.15, 0.15, 0.15}), Error);
  grid.remove(3, {0.1, 0.1, 0.1}, {0.15, 0.15, 0.15});
  EXPECT_EQ(grid.size(), 0u);
  int calls = 0;
  grid.for_each_candidate({0, 0, 0}, {1, 1, 1}, [&](std::uint32_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  EXPECT_THROW(TriangleGrid(bounds, 0), Error);
  EXPECT_THROW(TriangleGrid(Bounds{}, 1), Error);
  EXPECT_THROW(TriangleGrid(bounds, 1e-9), Error);  // 10^9 cells along an axis
}

TEST(self_intersections_grid, CellSizeBounds) {
  Bounds bounds;
  bounds.extend({0, 0, 0});
  bounds.extend({10, 10, 10});
  // Twice the mean edge when the grid stays small: 1000 faces allow 4000 cells; a cell of 2
  // gives 6^3 = 216.
  EXPECT_DOUBLE_EQ(triangle_grid_cell_size(bounds, 1000, 1.0), 2.0);
  // Tiny edges: enlarged until at most 4 cells per face.
  const double h = triangle_grid_cell_size(bounds, 1000, 1e-3);
  const double cells = std::pow(std::floor(10 / h) + 1, 3);
  EXPECT_LE(cells, 4000);
  EXPECT_GT(cells, 4000 / 1.25 / 1.25 / 1.25 / 2);  // not much larger than needed
  // No usable edge length: a fraction of the diagonal.
  EXPECT_GT(triangle_grid_cell_size(bounds, 10, 0.0), 0.0);
}
