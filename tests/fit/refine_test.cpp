// refine_mesh: a coarse mesh moves onto the fine surface it approximates (RMS and Hausdorff
// fall), faces neither flip nor intersect, connectivity and arrays are carried, a plane stays a
// plane, locked and border vertices stay, the result does not depend on the thread count, bad
// input is refused.

#include "isoforge/fit/refine.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/reduce/mesh_distance.hpp"
#include "isoforge/spatial/self_intersections.hpp"
#include "support/expect_error.hpp"
#include "support/meshes.hpp"

namespace isoforge {
namespace {

using test::expect_error;

// A sphere-like surface r(θ, φ) = 1 + bump · sin(5θ) cos(4φ) as a polar mesh.
PolyData bumpy_sphere(int rings, int segments, double bump, double scale = 1) {
  const auto r = [bump](double th, double ph) {
    return 1 + bump * std::sin(5 * th) * std::cos(4 * ph);
  };
  const double pi = std::numbers::pi;
  return test::polar_surface({0, 0, -scale * r(pi, 0)}, {0, 0, scale * r(0, 0)}, rings, segments,
                             [&](int i, int j) {
                               const double th = pi - pi * i / rings, ph = 2 * pi * j / segments;
                               const double rr = scale * r(th, ph);
                               return Vec3{rr * std::sin(th) * std::cos(ph),
                                           rr * std::sin(th) * std::sin(ph), rr * std::cos(th)};
                             });
}

// An icosphere: the icosahedron subdivided `levels` times, points on the sphere of `radius`.
PolyData icosphere(int levels, double radius) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<Index, 3>> f = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& p : v) p = p / norm(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<Index, Index>, Index> mid;
    const auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const Vec3 m = v[a] + v[b];
      v.push_back(m / norm(m));
      return mid[key] = Index(v.size() - 1);
    };
    std::vector<std::array<Index, 3>> g;
    for (const auto& tr : f) {
      const Index a = midpoint(tr[0], tr[1]), b = midpoint(tr[1], tr[2]),
                  c = midpoint(tr[2], tr[0]);
      g.push_back({tr[0], a, c});
      g.push_back({tr[1], b, a});
      g.push_back({tr[2], c, b});
      g.push_back({a, b, c});
    }
    f = std::move(g);
  }
  PolyData pd;
  for (const Vec3& p : v) pd.points.push_back(radius * p);
  for (const auto& tr : f) pd.polys.add({tr[0], tr[1], tr[2]});
  return pd;
}

// A grid of n × n quads split into triangles over [0, 1]² at z = 0; interior points moved by
// `jitter` (in-plane, a fixed pattern).
PolyData plane_grid(int n, double jitter) {
  return test::grid_surface(
      n,
      [&](int i, int j) {
        const bool inside = i > 0 && j > 0 && i < n && j < n;
        const double dx = inside ? jitter * std::sin(3.1 * i + 1.7 * j) : 0;
        const double dy = inside ? jitter * std::cos(2.3 * i - 0.9 * j) : 0;
        return Vec3{(i + dx) / n, (j + dy) / n, 0};
      },
      [](int, int) { return true; });
}

Vec3 face_normal(const PolyData& pd, std::size_t c) {
  const auto ids = pd.polys.cell(c);
  const Vec3 a = pd.points[ids[0]], b = pd.points[ids[1]], d = pd.points[ids[2]];
  return cross(b - a, d - a);
}

// Largest | |p| − 1 | over the points: the distance of the vertices to the unit sphere.
double sphere_error(const PolyData& pd) {
  double e = 0;
  for (std::size_t i = 0; i < pd.points.size(); ++i)
    e = std::max(e, std::abs(norm(pd.points[i]) - 1));
  return e;
}

TEST(RefineMesh, IcosphereMovesOntoTheSphere) {
  const PolyData fine = bumpy_sphere(64, 128, 0);
  PolyData coarse = icosphere(2, 0.95);  // 320 triangles, 5% inside
  std::vector<float> ids(coarse.points.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = float(i);
  coarse.point_data.add(DataArray::from_vector("Id", 1, ids));
  coarse.cell_data.add(DataArray::from_vector("Face", 1, std::vector<int>(320, 7)));

  const auto [out, st] = refine_mesh(fine, coarse);
  // Before: every vertex 0.05 inside. After: on the fine sphere up to its chord error (the
  // fine mesh's sagitta is 1 − cos(π/128) ≈ 3e-4) and the coarse faces' own sagitta.
  EXPECT_NEAR(st.hausdorff_before, 0.05 + 0.95 * (1 - std::cos(0.3)), 0.03);
  EXPECT_LT(st.rms_after, 0.3 * st.rms_before);
  EXPECT_LT(st.hausdorff_after, st.hausdorff_before);
  EXPECT_LT(sphere_error(out), 0.02);
  EXPECT_GT(st.moved_vertices, 150u);
  EXPECT_GE(st.solves, 1);
  EXPECT_GT(st.seconds, 0);
  // Connectivity identical, arrays carried unchanged.
  EXPECT_EQ(out.polys, coarse.polys);
  EXPECT_EQ(out.point_data, coarse.point_data);
  EXPECT_EQ(out.cell_data, coarse.cell_data);
  EXPECT_EQ(out.points.type(), coarse.points.type());
  // No face turned by 90° or more, no self-intersection.
  for (std::size_t c = 0; c < out.polys.size(); ++c)
    EXPECT_GT(dot(face_normal(out, c), face_normal(coarse, c)), 0) << "face " << c;
  EXPECT_TRUE(self_intersections(out).empty());
  // An independent measure (other samples, mesh_distance) agrees that both errors fell.
  const MeshDistance before = mesh_distance(fine, coarse), after = mesh_distance(fine, out);
  EXPECT_LT(after.rms, 0.3 * before.rms);
  EXPECT_LT(after.hausdorff, before.hausdorff);
}

TEST(RefineMesh, BumpySurfaceFitsBetter) {
  // The coarse mesh has its vertices on the bumpy surface; its faces cut the bumps. Refinement
  // trades vertex exactness for a smaller error over the whole surface.
  const PolyData fine = bumpy_sphere(96, 192, 0.1);
  const PolyData coarse = bumpy_sphere(16, 32, 0.1);
  RefineOptions fixed;
  fixed.flip_edges = false;
  for (const bool flips : {true, false}) {
    const auto [out, st] = refine_mesh(fine, coarse, flips ? RefineOptions{} : fixed);
    EXPECT_LT(st.rms_after, 0.7 * st.rms_before);
    EXPECT_LE(st.hausdorff_after, st.hausdorff_before);
    EXPECT_TRUE(self_intersections(out).empty());
    EXPECT_EQ(out.polys.size(), coarse.polys.size());
    const SurfaceTopology topo = analyze_topology(out);
    EXPECT_TRUE(topo.manifold() && topo.oriented());
    EXPECT_EQ(topo.edges, analyze_topology(coarse).edges);
    if (!flips) {
      EXPECT_EQ(out.polys, coarse.polys);
      EXPECT_EQ(st.flips, 0u);
    }
    const MeshDistance before = mesh_distance(fine, coarse), after = mesh_distance(fine, out);
    EXPECT_LT(after.rms, 0.7 * before.rms);
  }
}

TEST(RefineMesh, EdgeFlipsAlignEdgesWithTheRulings) {
  // The ruled surface z = 0.6 (x − y)² is straight along (1, 1). A coarse grid of its points
  // whose squares are split along (1, −1) cuts across the rulings; split along (1, 1) it holds
  // the surface exactly up to the fine mesh's own error. The flips find the second split.
  const auto f = [](double x, double y) { return 0.6 * (x - y) * (x - y); };
  const auto grid = [&](int n, bool along) {
    return test::grid_surface(
        n,
        [&](int i, int j) {
          const double x = double(i) / n, y = double(j) / n;
          return Vec3{x, y, f(x, y)};
        },
        [along](int, int) { return along; });
  };
  const PolyData fine = grid(64, true), coarse = grid(4, false);
  RefineOptions fixed;
  fixed.flip_edges = false;
  const auto [kept, ks] = refine_mesh(fine, coarse, fixed);
  const auto [out, st] = refine_mesh(fine, coarse);
  EXPECT_EQ(ks.flips, 0u);
  EXPECT_GE(st.flip_passes, 1);
  EXPECT_GE(st.flips, 16u);  // at least half of the 16 squares turned their diagonal
  EXPECT_LT(st.rms_after, 0.6 * ks.rms_after);  // measured: 0.52
  EXPECT_LE(st.hausdorff_after, ks.hausdorff_after);
  // Still a valid surface: as many triangles, manifold, oriented, the same edges count and
  // border, no self-intersection.
  EXPECT_EQ(out.polys.size(), coarse.polys.size());
  const SurfaceTopology topo = analyze_topology(out), before = analyze_topology(coarse);
  EXPECT_TRUE(topo.manifold() && topo.oriented());
  EXPECT_EQ(topo.edges, before.edges);
  EXPECT_EQ(topo.border_edges, before.border_edges);
  EXPECT_TRUE(self_intersections(out).empty());
  const MeshDistance d_kept = mesh_distance(fine, kept), d_out = mesh_distance(fine, out);
  EXPECT_LT(d_out.rms, 0.6 * d_kept.rms);
  // With a cell array, the cells must stay: no flips.
  PolyData with_cells = coarse;
  with_cells.cell_data.add(DataArray::from_vector("Face", 1, std::vector<int>(32, 3)));
  const auto [same, ss] = refine_mesh(fine, with_cells);
  EXPECT_EQ(ss.flips, 0u);
  EXPECT_EQ(same.polys, coarse.polys);
}

// A coarse, shrunken, nearly round mesh inside a strongly bumped sphere, without springs: the
// solves want large moves, and some would turn a face over or through another (found by
// trying: 192 moves are undone here).
struct BigMoves {
  PolyData fine = bumpy_sphere(96, 192, 0.3);
  PolyData coarse = bumpy_sphere(8, 16, 0.06, 0.8);
  RefineOptions options = [] {
    RefineOptions o;
    o.spring = 0;
    o.outer_iterations = 6;
    return o;
  }();
};

TEST(RefineMesh, BigMovesAreCheckedAndSomeUndone) {
  // What remains has no self-intersection and no face that collapsed, and both errors fell.
  const BigMoves bm;
  const auto [out, st] = refine_mesh(bm.fine, bm.coarse, bm.options);
  EXPECT_GT(st.rejected_moves, 0u);
  EXPECT_TRUE(self_intersections(out).empty());
  for (std::size_t c = 0; c < out.polys.size(); ++c) EXPECT_GT(norm2(face_normal(out, c)), 0) << c;
  EXPECT_LT(st.rms_after, 0.3 * st.rms_before);
  EXPECT_LT(st.hausdorff_after, st.hausdorff_before);
}

TEST(RefineMesh, ResultDoesNotDependOnTheThreads) {
  // The case above (moves refused, measures after undoing that take over what stayed, flips)
  // on one thread and on all: the same points and triangles, bit for bit.
  const BigMoves bm;
  const auto all = refine_mesh(bm.fine, bm.coarse, bm.options);
  const auto one = [&] {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    return refine_mesh(bm.fine, bm.coarse, bm.options);
  }();
  EXPECT_GT(all.stats.rejected_moves, 0u);
  EXPECT_EQ(all.stats.rejected_moves, one.stats.rejected_moves);
  EXPECT_EQ(all.stats.flips, one.stats.flips);
  ASSERT_EQ(all.output.points.size(), one.output.points.size());
  for (std::size_t i = 0; i < all.output.points.size(); ++i) {
    EXPECT_EQ(all.output.points[i], one.output.points[i]) << i;
  }
  ASSERT_EQ(all.output.polys.size(), one.output.polys.size());
  for (std::size_t c = 0; c < all.output.polys.size(); ++c) {
    const auto a = all.output.polys.cell(c), b = one.output.polys.cell(c);
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << c;
  }
}

TEST(RefineMesh, PlaneStaysPlanarAndBorderStays) {
  const PolyData fine = plane_grid(60, 0);
  const PolyData coarse = plane_grid(8, 0.3);
  const auto [out, st] = refine_mesh(fine, coarse);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    EXPECT_EQ(out.points[i].z, 0) << i;  // nothing pulls out of the plane
    const Vec3 p = coarse.points[i];
    const bool border = p.x == 0 || p.y == 0 || p.x == 1 || p.y == 1;
    if (border) {
      EXPECT_EQ(out.points[i], p) << i;
    }
  }
  EXPECT_LE(st.rms_after, st.rms_before);
  EXPECT_LE(st.hausdorff_after, st.hausdorff_before);
  EXPECT_TRUE(self_intersections(out).empty());
}

TEST(RefineMesh, FreeBorderStaysPlanar) {
  // keep_boundary = false: the border may move too, still within the plane, never worse.
  const PolyData fine = plane_grid(60, 0);
  const PolyData coarse = plane_grid(8, 0.3);
  RefineOptions o;
  o.keep_boundary = false;
  const auto [out, st] = refine_mesh(fine, coarse, o);
  for (std::size_t i = 0; i < out.points.size(); ++i) EXPECT_EQ(out.points[i].z, 0) << i;
  EXPECT_LE(st.rms_after, st.rms_before);
  EXPECT_LE(st.hausdorff_after, st.hausdorff_before);
  EXPECT_TRUE(self_intersections(out).empty());
}

TEST(RefineMesh, LockedVerticesStay) {
  const PolyData fine = bumpy_sphere(32, 64, 0);
  PolyData coarse = icosphere(1, 0.9);
  std::vector<std::uint8_t> lock(coarse.points.size(), 0);
  for (std::size_t i = 0; i < lock.size(); i += 2) lock[i] = 1;
  coarse.point_data.add(DataArray::from_vector("Lock", 1, lock));
  RefineOptions o;
  o.lock_array = "Lock";
  const auto [out, st] = refine_mesh(fine, coarse, o);
  for (std::size_t i = 0; i < lock.size(); ++i)
    if (lock[i]) {
      EXPECT_EQ(out.points[i], coarse.points[i]) << i;
    }
  EXPECT_GT(st.moved_vertices, 0u);
  EXPECT_LE(st.rms_after, st.rms_before);
}

TEST(RefineMesh, RobustLossAndExplicitSamples) {
  const PolyData fine = bumpy_sphere(48, 96, 0);
  const PolyData coarse = icosphere(2, 1.04);
  RefineOptions o;
  o.loss = RobustLoss::Huber;
  o.samples = 20000;
  o.outer_iterations = 2;
  const auto [out, st] = refine_mesh(fine, coarse, o);
  EXPECT_LT(st.rms_after, 0.5 * st.rms_before);
  EXPECT_LE(st.solves, 2);
  EXPECT_TRUE(self_intersections(out).empty());
}

TEST(RefineMesh, ProgressAndCancel) {
  const PolyData fine = bumpy_sphere(16, 32, 0);
  const PolyData coarse = icosphere(1, 0.9);
  RefineOptions o;
  double last = -1;
  o.progress = [&](double f) {
    EXPECT_GE(f, last);
    last = f;
    return true;
  };
  (void)refine_mesh(fine, coarse, o);
  EXPECT_EQ(last, 1);
  o.progress = [](double) { return false; };
  EXPECT_THROW((void)refine_mesh(fine, coarse, o), Cancelled);
}

TEST(RefineMesh, Errors) {
  const PolyData fine = bumpy_sphere(8, 16, 0);
  const PolyData coarse = icosphere(0, 1);
  PolyData quad;
  for (int i = 0; i < 4; ++i) quad.points.push_back({double(i & 1), double(i >> 1), 0});
  quad.polys.add({0, 1, 3, 2});
  expect_error([&] { (void)refine_mesh(fine, quad); },
               "simplified: cell 0 has 4 points; only triangles are refined");
  PolyData empty;
  expect_error([&] { (void)refine_mesh(empty, coarse); }, "original: has no triangles");
  expect_error([&] { (void)refine_mesh(fine, empty); }, "simplified: has no triangles");
  PolyData repeated = coarse;
  repeated.polys.add({0, 0, 1});
  expect_error([&] { (void)refine_mesh(fine, repeated); }, "triangle 20 repeats a point");
  PolyData nan = coarse;
  nan.points.set(3, {std::nan(""), 0, 0});
  expect_error([&] { (void)refine_mesh(fine, nan); }, "simplified: point 3 is not finite");
  PolyData strips = coarse;
  strips.strips.add({0, 1, 2, 3});
  expect_error([&] { (void)refine_mesh(fine, strips); }, "simplified: has triangle strips");
  RefineOptions o;
  o.outer_iterations = 0;
  expect_error([&] { (void)refine_mesh(fine, coarse, o); }, "outer_iterations must be >= 1");
  o = {};
  o.spring = -1;
  expect_error([&] { (void)refine_mesh(fine, coarse, o); }, "spring must be a finite number");
  o = {};
  o.lock_array = "Nope";
  expect_error([&] { (void)refine_mesh(fine, coarse, o); },
               "lock_array 'Nope' is not a point array");
  PolyData vec = coarse;
  vec.point_data.add(DataArray::from_vector("V", 3, std::vector<float>(3 * 12, 0)));
  o.lock_array = "V";
  expect_error([&] { (void)refine_mesh(fine, vec, o); }, "lock_array 'V' has 3 components");
}

// The measured case of docs/algorithms/fitting.md (not run by default: a timing, not a test):
// a 100k-triangle bumpy sphere and a 10k-triangle version of it.
TEST(RefineMesh, DISABLED_Measure100kTo10k) {
  const PolyData fine = bumpy_sphere(224, 224, 0.1);     // 100 128 triangles
  const PolyData coarse = bumpy_sphere(71, 71, 0.1, 1);  // 9 940 triangles
  const auto t0 = std::chrono::steady_clock::now();
  const auto [out, st] = refine_mesh(fine, coarse);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("original %zu triangles, simplified %zu triangles\n", fine.polys.size(),
              coarse.polys.size());
  std::printf("rms %.3e -> %.3e, hausdorff %.3e -> %.3e\n", st.rms_before, st.rms_after,
              st.hausdorff_before, st.hausdorff_after);
  std::printf("moved %zu, rejected %zu, solves %d, solve %.3f s, total %.3f s (wall %.3f s)\n",
              st.moved_vertices, st.rejected_moves, st.solves, st.seconds, st.total_seconds, wall);
  const MeshDistance before = mesh_distance(fine, coarse), after = mesh_distance(fine, out);
  std::printf("mesh_distance: rms %.3e -> %.3e, hausdorff %.3e -> %.3e\n", before.rms, after.rms,
              before.hausdorff, after.hausdorff);
  EXPECT_LT(st.rms_after, st.rms_before);
  EXPECT_TRUE(self_intersections(out).empty());
}

}  // namespace
}  // namespace isoforge
