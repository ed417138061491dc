#include "isoforge/contour/connectivity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <set>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/implicit/sample.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using F = ImplicitFunction;
using Mode = ConnectivityMode;

namespace {

std::vector<std::int32_t> ints(const DataArray& a) {
  const auto v = a.values<std::int32_t>();
  return {v.begin(), v.end()};
}

std::vector<std::int64_t> int64s(const DataArray& a) {
  const auto v = a.values<std::int64_t>();
  return {v.begin(), v.end()};
}

std::vector<Index> ids_of(const CellArray& a) {
  return {a.connectivity().begin(), a.connectivity().end()};
}

// Adds "pid" (Int64, the input point id) and "cid" (Int64, the input cell id).
void add_id_arrays(PolyData& pd) {
  std::vector<std::int64_t> pid(pd.num_points()), cid(pd.num_cells());
  std::iota(pid.begin(), pid.end(), 0);
  std::iota(cid.begin(), cid.end(), 0);
  pd.point_data.add(DataArray::from_vector<std::int64_t>("pid", 1, pid), AttributeRole::Scalars);
  pd.cell_data.add(DataArray::from_vector<std::int64_t>("cid", 1, cid));
}

// Two disjoint triangles, a line and a vertex: cells V=0 (vertex 8), L=1 (line 6-7),
// T0=2 (0,1,2), T1=3 (3,4,5); with `extra`, T2=4 (0,2,9) shares the edge 0-2 with T0. Point 10
// is used by no cell. Groups sit far apart along x.
PolyData sample_mesh(bool extra) {
  PolyData pd;
  const std::vector<Vec3> p{{0, 0, 0},  {1, 0, 0},  {0, 1, 0},  {10, 0, 0}, {11, 0, 0}, {10, 1, 0},
                            {20, 0, 0}, {21, 0, 0}, {30, 0, 0}, {-1, 0, 0}, {100, 0, 0}};
  for (const Vec3& q : p) pd.points.push_back(q);
  pd.verts.add({8});
  pd.lines.add({6, 7});
  pd.polys.add({0, 1, 2});
  pd.polys.add({3, 4, 5});
  if (extra) pd.polys.add({0, 2, 9});
  add_id_arrays(pd);
  return pd;
}

ConnectivityOptions mode(Mode m) {
  ConnectivityOptions o;
  o.mode = m;
  return o;
}

using isoforge::test::expect_error;

// Reference labeling: breadth-first search over cell adjacency (quadratic), components ordered
// by decreasing cell count, then smallest cell id.
std::vector<std::int32_t> reference_labels(const PolyData& pd, bool by_edge) {
  std::vector<std::vector<Index>> cells;
  std::vector<std::set<std::pair<Index, Index>>> edges;
  auto add = [&](const CellArray& a, int kind) {
    for (std::size_t c = 0; c < a.size(); ++c) {
      auto s = a.cell(c);
      cells.emplace_back(s.begin(), s.end());
      std::set<std::pair<Index, Index>> e;
      const std::size_t n = s.size();
      auto put = [&](Index x, Index y) {
        if (x != y) e.insert({std::min(x, y), std::max(x, y)});
      };
      if (kind == 1) {
        for (std::size_t i = 0; i + 1 < n; ++i) put(s[i], s[i + 1]);
      } else if (kind == 2) {
        for (std::size_t i = 0; i < n; ++i) put(s[i], s[(i + 1) % n]);
      } else if (kind == 3) {
        for (std::size_t i = 0; i + 2 < n; ++i) {
          put(s[i], s[i + 1]);
          put(s[i + 1], s[i + 2]);
          put(s[i], s[i + 2]);
        }
      }
      edges.push_back(e);
    }
  };
  add(pd.verts, 0);
  add(pd.lines, 1);
  add(pd.polys, 2);
  add(pd.strips, 3);
  const std::size_t nc = cells.size();
  auto adjacent = [&](std::size_t a, std::size_t b) {
    if (by_edge) {
      for (const auto& e : edges[a]) {
        if (edges[b].count(e)) return true;
      }
      return false;
    }
    for (Index x : cells[a]) {
      if (std::find(cells[b].begin(), cells[b].end(), x) != cells[b].end()) return true;
    }
    return false;
  };
  std::vector<int> group(nc, -1);
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t s = 0; s < nc; ++s) {
    if (group[s] >= 0) continue;
    groups.emplace_back();
    std::vector<std::size_t> stack{s};
    group[s] = static_cast<int>(groups.size() - 1);
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      groups.back().push_back(c);
      for (std::size_t d = 0; d < nc; ++d) {
        if (group[d] < 0 && adjacent(c, d)) {
          group[d] = group[s];
          stack.push_back(d);
        }
      }
    }
  }
  std::vector<std::size_t> order(groups.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return groups[a].size() > groups[b].size();  // groups are already by smallest cell
  });
  std::vector<std::int32_t> label(nc);
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (std::size_t c : groups[order[i]]) label[c] = static_cast<std::int32_t>(i);
  }
  return label;
}

PolyData two_spheres(Index n) {
  const F f = F::sphere({-0.9, 0, 0}, 0.7) | F::sphere({1.0, 0.1, 0}, 0.45);
  Bounds b;
  b.extend({-2, -1.5, -1.5});
  b.extend({2, 1.5, 1.5});
  return contour_image(sample_image(f, GridSpec::from_bounds(b, {n, n, n}))).output;
}

}  // namespace

TEST(Connectivity, TwoTrianglesALineAndAVertexAreFourComponents) {
  const PolyData pd = sample_mesh(false);
  const ConnectivityResult r = connectivity(pd);
  EXPECT_EQ(r.stats.components, 4u);
  // All of size 1: numbered by smallest cell id (vertex, line, T0, T1).
  EXPECT_EQ(r.stats.sizes, (std::vector<std::size_t>{1, 1, 1, 1}));
  EXPECT_EQ(r.stats.cell_component, (std::vector<std::int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_TRUE(r.stats.areas.empty());
  // Mode All: every cell; the unused points 9 and 10 are dropped.
  EXPECT_EQ(r.output.num_cells(), 4u);
  EXPECT_EQ(r.output.num_points(), 9u);
  EXPECT_EQ(ints(r.output.cell_data.get("ComponentId")), (std::vector<std::int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(ints(r.output.point_data.get("ComponentId")),
            (std::vector<std::int32_t>{2, 2, 2, 3, 3, 3, 1, 1, 0}));
  EXPECT_EQ(int64s(r.output.point_data.get("pid")),
            (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_NO_THROW(r.output.validate());
}

TEST(Connectivity, SizesOrderComponents) {
  const PolyData pd = sample_mesh(true);
  const ConnectivityResult r = connectivity(pd);
  ASSERT_EQ(r.stats.components, 4u);
  // {T0, T2} has 2 cells: component 0; then vertex, line, T1 by smallest cell id.
  EXPECT_EQ(r.stats.sizes, (std::vector<std::size_t>{2, 1, 1, 1}));
  EXPECT_EQ(r.stats.cell_component, (std::vector<std::int32_t>{1, 2, 0, 3, 0}));
  // All points but 10 are used, renumbered in increasing id (0..9 unchanged).
  EXPECT_EQ(r.output.num_points(), 10u);
  EXPECT_EQ(ints(r.output.point_data.get("ComponentId")),
            (std::vector<std::int32_t>{0, 0, 0, 3, 3, 3, 2, 2, 1, 0}));
  EXPECT_EQ(ids_of(r.output.polys), ids_of(pd.polys));
  EXPECT_EQ(int64s(r.output.cell_data.get("cid")), (std::vector<std::int64_t>{0, 1, 2, 3, 4}));
  // Attribute roles survive.
  EXPECT_EQ(r.output.point_data.active_name(AttributeRole::Scalars), "pid");
}

TEST(Connectivity, BowTieIsOneComponentByPointTwoByEdge) {
  PolyData pd;
  for (Vec3 p : {Vec3{-1, -1, 0}, Vec3{-1, 1, 0}, Vec3{0, 0, 0}, Vec3{1, 1, 0}, Vec3{1, -1, 0}}) {
    pd.points.push_back(p);
  }
  pd.polys.add({0, 1, 2});
  pd.polys.add({2, 3, 4});
  const ConnectivityResult by_point = connectivity(pd);
  EXPECT_EQ(by_point.stats.components, 1u);
  EXPECT_EQ(by_point.stats.sizes, (std::vector<std::size_t>{2}));

  ConnectivityOptions o;
  o.connected_by = ConnectedBy::Edge;
  const ConnectivityResult by_edge = connectivity(pd, o);
  EXPECT_EQ(by_edge.stats.components, 2u);
  EXPECT_EQ(by_edge.stats.cell_component, (std::vector<std::int32_t>{0, 1}));
  // The shared point takes the smallest component of the output cells using it.
  EXPECT_EQ(ints(by_edge.output.point_data.get("ComponentId")),
            (std::vector<std::int32_t>{0, 0, 0, 1, 1}));
  // Extracting component 1 alone labels the shared point 1.
  o.mode = Mode::Specified;
  o.components = {1};
  const ConnectivityResult second = connectivity(pd, o);
  EXPECT_EQ(second.output.num_points(), 3u);
  EXPECT_EQ(ids_of(second.output.polys), (std::vector<Index>{0, 1, 2}));
  EXPECT_EQ(ints(second.output.point_data.get("ComponentId")),
            (std::vector<std::int32_t>{1, 1, 1}));
}

TEST(Connectivity, EdgeCriterionCoversLinesStripsAndVerts) {
  PolyData pd;
  for (int i = 0; i < 9; ++i) pd.points.push_back({static_cast<double>(i), i % 2 ? 1.0 : 0.0, 0});
  // Cell ids run verts, lines, polys, strips:
  pd.verts.add({0});            // 0: shares point 0 with the strip, but no edge
  pd.lines.add({4, 5, 6});      // 1: its segment 4-5 ...
  pd.lines.add({3, 6});         // 2: shares only points (3 with the strip, 6 with cell 1)
  pd.polys.add({5, 4, 7});      // 3: ... is a side of this triangle
  pd.polys.add({2, 0, 8});      // 4: its side 0-2 is a side of the strip's first triangle
  pd.strips.add({0, 1, 2, 3});  // 5: triangles 012, 123
  ConnectivityOptions o;
  o.connected_by = ConnectedBy::Edge;
  const ConnectivityResult e = connectivity(pd, o);
  EXPECT_EQ(e.stats.cell_component, reference_labels(pd, true));
  // {1, 3} and {4, 5} (2 cells; by smallest cell), then {0} and {2}.
  EXPECT_EQ(e.stats.components, 4u);
  EXPECT_EQ(e.stats.cell_component, (std::vector<std::int32_t>{2, 0, 3, 0, 1, 1}));
  // By point they are all one: 0-strip-3-line36-6-line456-poly547, and poly208 through 0 and 2.
  const ConnectivityResult p = connectivity(pd);
  EXPECT_EQ(p.stats.components, 1u);
}

TEST(Connectivity, LargestKeepsOnlyTheUsedPointsAndCarriesAttributes) {
  const PolyData pd = sample_mesh(true);
  const ConnectivityResult r = connectivity(pd, mode(Mode::Largest));
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{0}));
  const PolyData& out = r.output;
  EXPECT_NO_THROW(out.validate());
  EXPECT_EQ(out.num_cells(), 2u);
  EXPECT_EQ(out.polys.size(), 2u);
  EXPECT_EQ(out.num_points(), 4u);
  EXPECT_EQ(ids_of(out.polys), (std::vector<Index>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(int64s(out.point_data.get("pid")), (std::vector<std::int64_t>{0, 1, 2, 9}));
  EXPECT_EQ(int64s(out.cell_data.get("cid")), (std::vector<std::int64_t>{2, 4}));
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    EXPECT_EQ(out.points[i], pd.points[static_cast<std::size_t>(out.point_data.get("pid").get(i))]);
  }
  EXPECT_EQ(ints(out.cell_data.get("ComponentId")), (std::vector<std::int32_t>{0, 0}));
  EXPECT_EQ(ints(out.point_data.get("ComponentId")), (std::vector<std::int32_t>{0, 0, 0, 0}));
  EXPECT_EQ(out.point_data.active_name(AttributeRole::Scalars), "pid");
}

TEST(Connectivity, LargestNTakesTheNLargest) {
  const PolyData pd = sample_mesh(true);
  ConnectivityOptions o = mode(Mode::LargestN);
  o.count = 2;
  const ConnectivityResult r = connectivity(pd, o);
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(r.output.num_cells(), 3u);  // vertex, T0, T2
  EXPECT_EQ(r.output.verts.size(), 1u);
  EXPECT_EQ(r.output.polys.size(), 2u);
  EXPECT_EQ(r.output.num_points(), 5u);
  EXPECT_EQ(int64s(r.output.point_data.get("pid")), (std::vector<std::int64_t>{0, 1, 2, 8, 9}));
  EXPECT_EQ(int64s(r.output.cell_data.get("cid")), (std::vector<std::int64_t>{0, 2, 4}));
  EXPECT_EQ(ids_of(r.output.verts), (std::vector<Index>{3}));
  EXPECT_EQ(ints(r.output.cell_data.get("ComponentId")), (std::vector<std::int32_t>{1, 0, 0}));

  o.count = 10;  // more than there are: all of them
  const ConnectivityResult all = connectivity(pd, o);
  EXPECT_EQ(all.stats.selected.size(), 4u);
  EXPECT_EQ(all.output.num_cells(), 5u);
}

TEST(Connectivity, ClosestToPointPicksTheComponentOfTheNearestUsedPoint) {
  const PolyData pd = sample_mesh(true);
  ConnectivityOptions o = mode(Mode::ClosestToPoint);
  o.point = {10.4, 0.3, 5};
  ConnectivityResult r = connectivity(pd, o);
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{3}));
  EXPECT_EQ(r.output.num_cells(), 1u);
  EXPECT_EQ(r.output.num_points(), 3u);
  EXPECT_EQ(int64s(r.output.point_data.get("pid")), (std::vector<std::int64_t>{3, 4, 5}));
  EXPECT_EQ(int64s(r.output.cell_data.get("cid")), (std::vector<std::int64_t>{3}));
  EXPECT_EQ(ids_of(r.output.polys), (std::vector<Index>{0, 1, 2}));
  // Point 10 (x = 100) is used by no cell: the vertex at x = 30 is the nearest used point.
  o.point = {99, 0, 0};
  r = connectivity(pd, o);
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{1}));
  EXPECT_EQ(r.output.verts.size(), 1u);
  EXPECT_EQ(r.output.num_points(), 1u);
  EXPECT_EQ(int64s(r.output.point_data.get("pid")), (std::vector<std::int64_t>{8}));
}

TEST(Connectivity, SpecifiedAndSeededSelections) {
  const PolyData pd = sample_mesh(true);
  ConnectivityOptions o = mode(Mode::Specified);
  o.components = {3, 2, 3};
  ConnectivityResult r = connectivity(pd, o);
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(r.output.num_cells(), 2u);  // line, T1
  EXPECT_EQ(r.output.num_points(), 5u);
  EXPECT_EQ(int64s(r.output.point_data.get("pid")), (std::vector<std::int64_t>{3, 4, 5, 6, 7}));
  EXPECT_EQ(int64s(r.output.cell_data.get("cid")), (std::vector<std::int64_t>{1, 3}));
  EXPECT_EQ(ids_of(r.output.lines), (std::vector<Index>{3, 4}));
  EXPECT_EQ(ids_of(r.output.polys), (std::vector<Index>{0, 1, 2}));

  o.components.clear();
  r = connectivity(pd, o);
  EXPECT_EQ(r.output.num_cells(), 0u);
  EXPECT_EQ(r.output.num_points(), 0u);
  EXPECT_TRUE(r.output.point_data.has("pid"));

  o = mode(Mode::PointSeeded);
  o.seeds = {7, 10};  // the line's end; an unused point selects nothing
  r = connectivity(pd, o);
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{2}));
  EXPECT_EQ(int64s(r.output.cell_data.get("cid")), (std::vector<std::int64_t>{1}));

  o = mode(Mode::CellSeeded);
  o.seeds = {4, 0};
  r = connectivity(pd, o);
  EXPECT_EQ(r.stats.selected, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(int64s(r.output.cell_data.get("cid")), (std::vector<std::int64_t>{0, 2, 4}));
}

TEST(Connectivity, KeepUnusedPointsKeepsInputIds) {
  const PolyData pd = sample_mesh(true);
  ConnectivityOptions o = mode(Mode::Largest);
  o.keep_unused_points = true;
  const ConnectivityResult r = connectivity(pd, o);
  EXPECT_NO_THROW(r.output.validate());
  EXPECT_EQ(r.output.points, pd.points);
  EXPECT_EQ(ids_of(r.output.polys), (std::vector<Index>{0, 1, 2, 0, 2, 9}));
  EXPECT_EQ(r.output.point_data.get("pid"), pd.point_data.get("pid"));
  // Points of other components keep their component; point 10 belongs to none.
  EXPECT_EQ(ints(r.output.point_data.get("ComponentId")),
            (std::vector<std::int32_t>{0, 0, 0, 3, 3, 3, 2, 2, 1, 0, -1}));
}

TEST(Connectivity, AreaOrdersByArea) {
  PolyData pd;
  // Three small triangles in a fan (3 cells, area 1.5), then one big triangle (area 50).
  for (Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}, Vec3{-1, 0, 0},
                 Vec3{5, 0, 0}, Vec3{15, 0, 0}, Vec3{5, 10, 0}}) {
    pd.points.push_back(p);
  }
  pd.polys.add({0, 1, 2});
  pd.polys.add({0, 2, 3});
  pd.polys.add({0, 3, 4});
  pd.polys.add({5, 6, 7});
  const ConnectivityResult by_cells = connectivity(pd, mode(Mode::Largest));
  EXPECT_EQ(by_cells.stats.sizes, (std::vector<std::size_t>{3, 1}));
  EXPECT_EQ(by_cells.output.num_cells(), 3u);

  ConnectivityOptions o = mode(Mode::Largest);
  o.size_by = ComponentSize::Area;
  const ConnectivityResult by_area = connectivity(pd, o);
  EXPECT_EQ(by_area.stats.sizes, (std::vector<std::size_t>{1, 3}));
  ASSERT_EQ(by_area.stats.areas.size(), 2u);
  EXPECT_DOUBLE_EQ(by_area.stats.areas[0], 50.0);
  EXPECT_DOUBLE_EQ(by_area.stats.areas[1], 1.5);
  EXPECT_EQ(by_area.output.num_cells(), 1u);
  EXPECT_EQ(by_area.stats.cell_component, (std::vector<std::int32_t>{1, 1, 1, 0}));
}

TEST(Connectivity, MatchesABreadthFirstReferenceOnRandomMeshes) {
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 200; ++trial) {
    const int np = 5 + static_cast<int>(rng() % 40);
    std::uniform_int_distribution<Index> pick(0, np - 1);
    PolyData pd;
    for (int i = 0; i < np; ++i) pd.points.push_back({static_cast<double>(i), 0, 0});
    auto cell = [&](std::size_t n) {
      std::vector<Index> ids(n);
      for (auto& id : ids) id = pick(rng);
      return ids;
    };
    const int nv = static_cast<int>(rng() % 4), nl = static_cast<int>(rng() % 6);
    const int nq = static_cast<int>(rng() % 12), ns = static_cast<int>(rng() % 3);
    for (int i = 0; i < nv; ++i) pd.verts.add(cell(1 + rng() % 2));
    for (int i = 0; i < nl; ++i) pd.lines.add(cell(2 + rng() % 3));
    for (int i = 0; i < nq; ++i) pd.polys.add(cell(3 + rng() % 2));
    for (int i = 0; i < ns; ++i) pd.strips.add(cell(3 + rng() % 3));
    for (bool by_edge : {false, true}) {
      ConnectivityOptions o;
      o.connected_by = by_edge ? ConnectedBy::Edge : ConnectedBy::Point;
      const ConnectivityResult r = connectivity(pd, o);
      const auto expected = reference_labels(pd, by_edge);
      ASSERT_EQ(r.stats.cell_component, expected) << "trial " << trial << " by_edge " << by_edge;
      std::size_t total = 0;
      for (std::size_t s : r.stats.sizes) total += s;
      EXPECT_EQ(total, pd.num_cells());
      EXPECT_TRUE(std::is_sorted(r.stats.sizes.rbegin(), r.stats.sizes.rend()));
      EXPECT_NO_THROW(r.output.validate());
    }
  }
}

TEST(Connectivity, TwoSeparateSpheresAreTwoClosedComponents) {
  // Fig. 1.29 in spirit: the union of two separated spheres contours to two surfaces.
  const PolyData pd = two_spheres(48);
  ASSERT_GT(pd.polys.size(), 0u);
  const ConnectivityResult r = connectivity(pd);
  ASSERT_EQ(r.stats.components, 2u);
  EXPECT_EQ(r.stats.sizes[0] + r.stats.sizes[1], pd.polys.size());
  EXPECT_GT(r.stats.sizes[0], r.stats.sizes[1]);
  EXPECT_EQ(r.output.num_points(), pd.num_points());
  EXPECT_TRUE(r.output.point_data.has("IsovalueIndex"));

  for (std::size_t c = 0; c < 2; ++c) {
    ConnectivityOptions o = mode(Mode::Specified);
    o.components = {c};
    const PolyData part = connectivity(pd, o).output;
    EXPECT_EQ(part.polys.size(), r.stats.sizes[c]);
    const SurfaceTopology t = analyze_topology(part);
    ASSERT_EQ(t.components.size(), 1u) << c;
    EXPECT_TRUE(t.closed()) << c;
    EXPECT_TRUE(t.manifold()) << c;
    EXPECT_EQ(t.components[0].genus, 0) << c;
    EXPECT_EQ(t.vertices, part.num_points()) << c;
  }

  const PolyData big = connectivity(pd, mode(Mode::Largest)).output;
  const Bounds b = big.bounds();
  const double h = 4.0 / 47;  // grid spacing along x
  EXPECT_NEAR(b.min.x, -1.6, h);
  EXPECT_NEAR(b.max.x, -0.2, h);
  EXPECT_NEAR(b.min.y, -0.7, h);
  EXPECT_NEAR(b.max.y, 0.7, h);

  ConnectivityOptions near_small = mode(Mode::ClosestToPoint);
  near_small.point = {1.0, 0.1, 0};
  const Bounds s = connectivity(pd, near_small).output.bounds();
  EXPECT_NEAR(s.min.x, 0.55, h);
  EXPECT_NEAR(s.max.x, 1.45, h);

  // Sharing an edge or a point gives the same components on a manifold surface; so does area.
  ConnectivityOptions by_edge;
  by_edge.connected_by = ConnectedBy::Edge;
  EXPECT_EQ(connectivity(pd, by_edge).stats.cell_component, r.stats.cell_component);
  ConnectivityOptions by_area;
  by_area.size_by = ComponentSize::Area;
  const ConnectivityResult a = connectivity(pd, by_area);
  EXPECT_EQ(a.stats.cell_component, r.stats.cell_component);
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(a.stats.areas[0], 4 * pi * 0.7 * 0.7, 0.05 * 4 * pi * 0.7 * 0.7);
  EXPECT_NEAR(a.stats.areas[1], 4 * pi * 0.45 * 0.45, 0.05 * 4 * pi * 0.45 * 0.45);
}

TEST(Connectivity, IsDeterministic) {
  const PolyData pd = two_spheres(40);
  for (Mode m : {Mode::All, Mode::Largest, Mode::ClosestToPoint}) {
    ConnectivityOptions o = mode(m);
    o.point = {0.9, 0, 0};
    const ConnectivityResult a = connectivity(pd, o), b = connectivity(pd, o);
    EXPECT_EQ(a.output, b.output);
    EXPECT_EQ(a.stats.cell_component, b.stats.cell_component);
    EXPECT_EQ(a.stats.sizes, b.stats.sizes);
  }
  const PolyData small = sample_mesh(true);
  EXPECT_EQ(connectivity(small).output, connectivity(small).output);
}

TEST(Connectivity, RvalueInputGivesTheSameResult) {
  for (const PolyData& pd : {sample_mesh(false), sample_mesh(true), two_spheres(32)}) {
    for (Mode m : {Mode::All, Mode::Largest, Mode::ClosestToPoint}) {
      for (bool keep : {false, true}) {
        ConnectivityOptions o = mode(m);
        o.keep_unused_points = keep;
        PolyData copy = pd;
        const ConnectivityResult a = connectivity(pd, o);
        const ConnectivityResult b = connectivity(std::move(copy), o);
        EXPECT_EQ(a.output, b.output);
        EXPECT_EQ(a.stats.cell_component, b.stats.cell_component);
        EXPECT_EQ(a.stats.selected, b.stats.selected);
        EXPECT_EQ(copy, PolyData{});  // NOLINT(bugprone-use-after-move): documented state
      }
    }
  }
  PolyData bad = sample_mesh(true);
  bad.polys.add({0, 1, 42});
  EXPECT_THROW((void)connectivity(std::move(bad)), Error);
  EXPECT_EQ(bad, PolyData{});  // NOLINT(bugprone-use-after-move)
}

TEST(Connectivity, DoublePrecisionPointsStayDoublePrecision) {
  PolyData pd = sample_mesh(true);
  Points p(pd.num_points(), ScalarType::Float64);
  for (std::size_t i = 0; i < p.size(); ++i) p.set(i, pd.points[i] + Vec3{1e-12, 0, 0});
  pd.points = p;
  const ConnectivityResult r = connectivity(pd, mode(Mode::Largest));
  ASSERT_EQ(r.output.points.type(), ScalarType::Float64);
  ASSERT_EQ(r.output.num_points(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(r.output.points[i], pd.points[static_cast<std::size_t>(std::array{0, 1, 2, 9}[i])]);
  }
}

TEST(Connectivity, EmptyInputHasNoComponents) {
  PolyData pd;
  pd.points.push_back({1, 2, 3});
  for (Mode m : {Mode::All, Mode::Largest, Mode::ClosestToPoint}) {
    const ConnectivityResult r = connectivity(pd, mode(m));
    EXPECT_EQ(r.stats.components, 0u);
    EXPECT_EQ(r.output.num_cells(), 0u);
    EXPECT_EQ(r.output.num_points(), 0u);
  }
}

TEST(Connectivity, ComponentIdsCanBeLeftOut) {
  ConnectivityOptions o;
  o.component_ids = false;
  const ConnectivityResult r = connectivity(sample_mesh(true), o);
  EXPECT_FALSE(r.output.point_data.has("ComponentId"));
  EXPECT_FALSE(r.output.cell_data.has("ComponentId"));
  EXPECT_EQ(r.stats.cell_component.size(), 5u);
}

TEST(Connectivity, BadInputThrowsNamingTheProblem) {
  const PolyData pd = sample_mesh(true);
  ConnectivityOptions o = mode(Mode::LargestN);
  o.count = 0;
  expect_error([&] { (void)connectivity(pd, o); }, "count must be at least 1");
  o = mode(Mode::ClosestToPoint);
  o.point = {0, std::numeric_limits<double>::quiet_NaN(), 0};
  expect_error([&] { (void)connectivity(pd, o); }, "not finite");
  o.point = {std::numeric_limits<double>::infinity(), 0, 0};
  expect_error([&] { (void)connectivity(pd, o); }, "not finite");
  o = mode(Mode::Specified);
  o.components = {1, 4};
  expect_error([&] { (void)connectivity(pd, o); }, "component 4 is out of range");
  o = mode(Mode::PointSeeded);
  o.seeds = {11};
  expect_error([&] { (void)connectivity(pd, o); }, "seed point 11 is out of range");
  o = mode(Mode::CellSeeded);
  o.seeds = {-1};
  expect_error([&] { (void)connectivity(pd, o); }, "seed cell -1 is out of range");

  PolyData bad = pd;
  bad.polys.add({0, 1, 42});
  expect_error([&] { (void)connectivity(bad); }, "polys");
  PolyData short_cell = pd;
  short_cell.cell_data.clear();
  short_cell.lines.add({3});
  expect_error([&] { (void)connectivity(short_cell); }, "fewer than 2 points");
  PolyData bad_attr = pd;
  bad_attr.cell_data.add(DataArray("wrong", ScalarType::Float32, 1, 2));
  expect_error([&] { (void)connectivity(bad_attr); }, "wrong");

  ConnectivityOptions cancel;
  cancel.progress = [](double f) { return f < 0.5; };
  EXPECT_THROW((void)connectivity(pd, cancel), Cancelled);
}

TEST(Connectivity, ProgressAdvancesWhileLabelling) {
  // 3 million triangles (a 1500 x 1000 grid of quads, two triangles each): labelling reports
  // every 2^20 cells (by point) or points (by edge), not only at its end.
  PolyData pd;
  const Index nx = 1501, ny = 1001;
  for (Index j = 0; j < ny; ++j)
    for (Index i = 0; i < nx; ++i) pd.points.push_back({double(i), double(j), 0});
  for (Index j = 0; j + 1 < ny; ++j)
    for (Index i = 0; i + 1 < nx; ++i) {
      const Index a = i + nx * j;
      pd.polys.add({a, a + 1, a + nx + 1});
      pd.polys.add({a, a + nx + 1, a + nx});
    }
  for (const ConnectedBy by : {ConnectedBy::Point, ConnectedBy::Edge}) {
    ConnectivityOptions o;
    o.connected_by = by;
    std::vector<double> seen;
    o.progress = [&](double f) {
      seen.push_back(f);
      return true;
    };
    EXPECT_EQ(connectivity(pd, o).stats.components, 1u);
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_GE(std::count_if(seen.begin(), seen.end(), [](double f) { return f > 0 && f < 0.5; }), 2);
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  }
}

// A timing run, not part of the suite: a 10M-triangle grid mesh (both triangles of every quad).
// Run with --gtest_also_run_disabled_tests --gtest_filter='*TenMillion*'.
TEST(Connectivity, DISABLED_TenMillionTriangles) {
  const Index n = 2237;  // (n - 1)^2 quads, 2 triangles each: 10.0M triangles
  PolyData pd;
  pd.points = Points(static_cast<std::size_t>(n * n));
  for (Index j = 0; j < n; ++j) {
    for (Index i = 0; i < n; ++i) {
      const Vec3 p{static_cast<double>(i), static_cast<double>(j), 0};
      pd.points.set(static_cast<std::size_t>(i + n * j), p);
    }
  }
  auto& conn = pd.polys.connectivity();
  auto& off = pd.polys.offsets();
  conn.reserve(static_cast<std::size_t>(6 * (n - 1) * (n - 1)));
  off.reserve(static_cast<std::size_t>(2 * (n - 1) * (n - 1) + 1));
  for (Index j = 0; j + 1 < n; ++j) {
    for (Index i = 0; i + 1 < n; ++i) {
      const Index a = i + n * j, b = a + 1, c = a + n, d = c + 1;
      // Leave a gap every 100 columns so there are several components.
      if (i % 100 == 99) continue;
      for (Index id : {a, b, d, a, d, c}) conn.push_back(id);
      off.push_back(static_cast<Index>(conn.size()) - 3);
      off.push_back(static_cast<Index>(conn.size()));
    }
  }
  for (bool by_edge : {false, true}) {
    for (Mode m : {Mode::All, Mode::Largest}) {
      ConnectivityOptions o = mode(m);
      o.connected_by = by_edge ? ConnectedBy::Edge : ConnectedBy::Point;
      const auto t0 = std::chrono::steady_clock::now();
      const ConnectivityResult r = connectivity(pd, o);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%zu triangles, by %s, mode %s: %zu components in %.3f s\n", pd.polys.size(),
                  by_edge ? "edge" : "point", m == Mode::All ? "All" : "Largest", r.stats.components, s);
      EXPECT_EQ(r.stats.components, static_cast<std::size_t>((n - 1 + 99) / 100));
    }
  }
  PolyData copy = pd;
  const auto t0 = std::chrono::steady_clock::now();
  const ConnectivityResult r = connectivity(std::move(copy));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%zu triangles, by point, mode All, rvalue input: %zu components in %.3f s\n",
              r.output.polys.size(), r.stats.components, s);
}
