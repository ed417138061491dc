// The coherent paths of the prober: in a curvilinear grid, the walk whose Newton iterations
// start from the coordinates predicted by the previous point (and whose image rows restart from
// the previous row); in a tetra mesh, the walk through remembered face neighbours. Each must
// find exactly what the cold path (every point probed alone, from the exact locator) finds.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

#include "filters/probe_grid.hpp"
#include "filters/probe_tets.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/filters/probe.hpp"
#include "isoforge/spatial/cell_locator.hpp"

using namespace isoforge;

namespace {

double linear(const Vec3& p) {
  return 1.5 + 2 * p.x - 3 * p.y + 0.5 * p.z;
}

/// Strongly curved but valid hexahedra: each coordinate displaced by 0.3 sin of the others
/// (second derivatives up to 0.2 per cell, Jacobians diagonally dominant: 2 · 0.3 · 0.8 < 1).
Vec3 twist(const Vec3& p) {
  return {p.x + 0.3 * std::sin(0.8 * p.y + 0.6 * p.z), p.y + 0.3 * std::sin(0.8 * p.z + 0.6 * p.x),
          p.z + 0.3 * std::sin(0.8 * p.x + 0.6 * p.y)};
}

/// An n³-point twisted grid with the linear field, a cell-id array and, when `holes`, every
/// seventh cell blanked through "Valid".
StructuredGrid twisted_grid(Index n, bool holes) {
  StructuredGrid g;
  g.dims = {n, n, n};
  g.points = Points(std::size_t(n * n * n), ScalarType::Float64);
  DataArray f("f", ScalarType::Float64, 1, g.points.size());
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const auto id = std::size_t(g.point_id(i, j, k));
        g.points.set(id, twist({double(i), double(j), double(k)}));
        f.set(id, 0, linear(g.points[id]));
      }
  g.point_data.add(std::move(f), AttributeRole::Scalars);
  const std::size_t nc = g.num_cells();
  DataArray cell("cell", ScalarType::Int32, 1, nc);
  DataArray valid("Valid", ScalarType::UInt8, 1, nc);
  for (std::size_t c = 0; c < nc; ++c) {
    cell.set(c, 0, double(c));
    valid.set(c, 0, holes && c % 7 == 3 ? 0 : 1);
  }
  g.cell_data.add(std::move(cell));
  if (holes) g.cell_data.add(std::move(valid));
  return g;
}

/// The n³-point twisted grid's cubes split into six tetrahedra each (a conforming mesh), with
/// the linear field "f".
UnstructuredGrid twisted_tetrahedra(Index n) {
  const StructuredGrid g = twisted_grid(n, false);
  UnstructuredGrid ug;
  ug.points = g.points;
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (Index k = 0; k + 1 < n; ++k)
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i + 1 < n; ++i) {
        auto c = [&](int q) { return g.point_id(i + (q & 1), j + ((q >> 1) & 1), k + (q >> 2)); };
        for (const auto& p : paths) ug.add_cell(CellType::Tetra, {c(0), c(p[0]), c(p[1]), c(7)});
      }
  ug.point_data.add(DataArray(g.point_data.get("f")), AttributeRole::Scalars);
  return ug;
}
/// Whether cell `c` of the grid (a non-blanked hexahedron) contains p within the tolerance.
bool cell_contains(const StructuredGrid& g, Index c, const Vec3& p) {
  const Index cx = g.dims[0] - 1, cy = g.dims[1] - 1;
  const Index i = c % cx, j = (c / cx) % cy, k = c / (cx * cy);
  const int order[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                           {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};  // VTK's order
  std::vector<Vec3> pts;
  for (const auto& o : order)
    pts.push_back(g.points[std::size_t(g.point_id(i + o[0], j + o[1], k + o[2]))]);
  return locate_in_cell(CellType::Hexahedron, pts, p, kDefaultCellTolerance).inside;
}

/// Probes the image `vol` at once (an image of many points: cell by cell, the image scan; of
/// few: the coherent walk) and point by point (each point alone: the exact locator), and
/// compares: the same points found, in cells that contain them and are not blanked (with
/// `same_cell`, the very same cell: the smallest id containing the point), with the linear field
/// reproduced; NaN elsewhere. Returns the points found.
std::size_t expect_image_equals_cold(const StructuredGrid& g, const ImageData& vol,
                                     bool same_cell) {
  const Prober prober(g);
  const auto [out, stats] = prober.probe(vol);
  const auto& pd = std::get<ImageData>(out).point_data;
  const DataArray& f = pd.get("f");
  const DataArray& mask = pd.get("vtkValidPointMask");
  const DataArray& cell = pd.get("cell");
  const DataArray* valid = g.cell_data.find("Valid");
  std::size_t found = 0;
  for (Index id = 0; id < Index(vol.num_points()); ++id) {
    const Vec3 p = vol.point(id);
    PolyData one;
    one.points = Points(0, ScalarType::Float64);
    one.points.push_back(p);
    const auto [cold, cold_stats] = prober.probe(one);
    const bool cold_found = cold_stats.found == 1;
    const auto i = std::size_t(id);
    EXPECT_EQ(mask.get(i) != 0, cold_found)
        << "point " << id << " at " << p.x << " " << p.y << " " << p.z;
    if (!cold_found || mask.get(i) == 0) {
      EXPECT_TRUE(std::isnan(f.get(i)));
      continue;
    }
    ++found;
    const auto c = Index(cell.get(i));
    EXPECT_TRUE(cell_contains(g, c, p)) << "point " << id << " in cell " << c;
    if (same_cell) {
      EXPECT_EQ(c, Index(std::get<PolyData>(cold).point_data.get("cell").get(0))) << "point " << id;
    }
    if (valid) {
      EXPECT_EQ(valid->get(std::size_t(c)), 1) << "point " << id << " in blanked cell " << c;
    }
    EXPECT_NEAR(f.get(i), linear(p), 1e-9) << "point " << id;
    EXPECT_NEAR(f.get(i), std::get<PolyData>(cold).point_data.get("f").get(0), 1e-9);
  }
  EXPECT_EQ(stats.found, found);
  return found;
}

/// A volume over the grid's bounds grown by 0.4 on each side (rows start and end outside),
/// against the cold path; both kinds of point occur.
void expect_coherent_equals_cold(const StructuredGrid& g, const Dims& dims, bool same_cell) {
  Bounds box = g.bounds();
  box.min = box.min - Vec3{0.4, 0.4, 0.4};
  box.max = box.max + Vec3{0.4, 0.4, 0.4};
  const ImageData vol = probe_volume(box, dims);
  const std::size_t found = expect_image_equals_cold(g, vol, same_cell);
  EXPECT_GT(found, vol.num_points() / 4);
  EXPECT_LT(found, vol.num_points() - vol.num_points() / 10);
}

}  // namespace

TEST(ProbeWalk, ImageScanFindsTheExactLocatorsCellsOnTwistedGrid) {
  expect_coherent_equals_cold(twisted_grid(7, false), {37, 29, 23}, true);
}

TEST(ProbeWalk, ImageScanFindsTheExactLocatorsCellsAroundHoles) {
  expect_coherent_equals_cold(twisted_grid(7, true), {31, 27, 19}, true);
}

TEST(ProbeWalk, ImageScanWithThePortableKernel) {
  // The Newton kernel without AVX2 (what a processor without it runs), on the same cases.
  probe_detail::use_portable_kernel(true);
  expect_coherent_equals_cold(twisted_grid(7, true), {31, 27, 19}, true);
  expect_coherent_equals_cold(twisted_grid(6, false), {29, 31, 23}, true);
  probe_detail::use_portable_kernel(false);
}

TEST(ProbeWalk, CoherentRowsOfASmallImageAgreeWithColdPoints) {
  // 504 image points against 2744 cells: too few to plan a scan, so the rows are walked.
  expect_coherent_equals_cold(twisted_grid(15, true), {9, 8, 7}, false);
  expect_coherent_equals_cold(twisted_grid(15, false), {9, 8, 7}, false);
}

TEST(ProbeWalk, ImageScanOnGridPointsFacesAndEdges) {
  // Unit cubes probed at half spacing: every image point lies on a grid point, an edge, a face
  // or at a centre; all are found, each in the smallest-id cell holding it.
  StructuredGrid g = twisted_grid(4, false);
  for (std::size_t id = 0; id < g.points.size(); ++id) {
    const Index i = Index(id) % 4, j = (Index(id) / 4) % 4, k = Index(id) / 16;
    g.points.set(id, Vec3{double(i), double(j), double(k)});
    g.point_data.get("f").set(id, 0, linear(g.points[id]));
  }
  ImageData vol;
  vol.dims = {7, 7, 7};
  vol.spacing = {0.5, 0.5, 0.5};
  EXPECT_EQ(expect_image_equals_cold(g, vol, true), 343u);
  // The same points in reverse order along x and z (negative spacing).
  vol.origin = {3, 0, 3};
  vol.spacing = {-0.5, 0.5, -0.5};
  EXPECT_EQ(expect_image_equals_cold(g, vol, true), 343u);
}

TEST(ProbeWalk, ImageScanOfPlanesAndLines) {
  // Images of one layer (slabs along y) and of one row (slabs along x), slanted through the
  // twisted grid.
  const StructuredGrid g = twisted_grid(6, true);
  ImageData plane;
  plane.dims = {41, 37, 1};
  plane.origin = {-0.6, -0.5, 2.3};
  plane.spacing = {0.16, 0.17, 1};
  EXPECT_GT(expect_image_equals_cold(g, plane, true), 500u);
  ImageData line;
  line.dims = {301, 1, 1};
  line.origin = {-0.7, 2.6, 1.9};
  line.spacing = {0.021, 1, 1};
  EXPECT_GT(expect_image_equals_cold(g, line, true), 150u);
}

TEST(ProbeWalk, PredictedStartsFindWhatTheExactLocatorFinds) {
  // The locator itself: a walk along a line with its predictions, and the same points each
  // from a fresh cursor (the exact locator), in the same cells or in cells equally containing
  // them, at the same parametric coordinates up to the solver's accuracy.
  const StructuredGrid g = twisted_grid(6, false);
  const probe_detail::GridLocator loc(g, {}, kDefaultCellTolerance);
  probe_detail::GridCursor walk;
  std::size_t found = 0, predicted = 0;
  for (int q = 0; q <= 600; ++q) {
    const Vec3 p = Vec3{-0.5, 0.3, 0.2} + Vec3{6.0, 4.4, 4.1} * (q / 600.0);
    const bool was_predicting = walk.predict;
    probe_detail::GridHit a, b;
    const bool fa = loc.find(p, walk, a);
    probe_detail::GridCursor fresh;
    const bool fb = loc.find(p, fresh, b);
    ASSERT_EQ(fa, fb) << "point " << q;
    if (!fa) continue;
    ++found;
    predicted += was_predicting ? 1 : 0;
    EXPECT_TRUE(cell_contains(g, a.cell, p)) << "point " << q;
    if (a.cell == b.cell) {
      EXPECT_NEAR(a.r, b.r, 1e-10);
      EXPECT_NEAR(a.s, b.s, 1e-10);
      EXPECT_NEAR(a.t, b.t, 1e-10);
    }
  }
  EXPECT_GT(found, 400u);
  EXPECT_GT(predicted, found / 2);  // the walk mostly started from a prediction
}

TEST(ProbeWalk, OutputIdenticalForOneAndTwoThreadsWithHoles) {
  const StructuredGrid g = twisted_grid(9, true);
  Bounds box = g.bounds();
  const ImageData vol = probe_volume(box, {61, 47, 33});  // several blocks, rows across blocks
  ProbeOptions o;
  o.nil_value = -7;  // comparable (NaN != NaN)
  const Prober prober(g, o);
  Dataset one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = prober.probe(vol).output;
  }
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
  const auto [two, stats] = prober.probe(vol);
  EXPECT_TRUE(one == two);
  EXPECT_GT(stats.found, 0u);
  EXPECT_LT(stats.found, stats.points);
}

TEST(ProbeWalk, RememberedTetraNeighboursChangeNothing) {
  // A tetra mesh probed twice by one prober (the second time every face neighbour the walks
  // need is remembered) and by a fresh one: identical outputs, all points inside found.
  const UnstructuredGrid ug = twisted_tetrahedra(6);
  const ImageData vol = probe_volume(ug.bounds(), {41, 37, 29});
  ProbeOptions o;
  o.nil_value = -7;
  const Prober prober(ug, o);
  const auto first = prober.probe(vol);
  const auto second = prober.probe(vol);
  EXPECT_TRUE(first.output == second.output);
  EXPECT_TRUE(probe(ug, vol, o).output == first.output);
  const auto& pd = std::get<ImageData>(first.output).point_data;
  std::size_t checked = 0;
  for (std::size_t i = 0; i < vol.num_points(); ++i) {
    if (pd.get("vtkValidPointMask").get(i) == 0) continue;
    EXPECT_NEAR(pd.get("f").get(i), linear(vol.point(Index(i))), 1e-9);
    ++checked;
  }
  EXPECT_EQ(checked, first.stats.found);
  EXPECT_GT(checked, vol.num_points() / 4);
}

TEST(ProbeWalk, TetraWalksReachEveryInsidePointFromAnyStart) {
  // The face neighbours matched when the walker is built: a walk from any tetrahedron reaches
  // the one holding p (the twisted mesh is not convex, so a walk may also stop at the boundary:
  // then the exact locator must find p outside or the walk have met a concave part). With every
  // tetrahedron twice (each face then has two or four cells) walks still arrive, by scanning.
  const UnstructuredGrid ug = twisted_tetrahedra(6);
  const UnstructuredGrid doubled = [&] {
    UnstructuredGrid d = ug;
    for (std::size_t c = 0; c < ug.cells.size(); ++c) {
      const auto v = ug.cells.cell(c);
      d.add_cell(CellType::Tetra, std::vector<Index>(v.begin(), v.end()));
    }
    return d;
  }();
  const Index nc = Index(ug.cells.size());
  for (const UnstructuredGrid* mesh : {&ug, &doubled}) {
    const probe_detail::TetWalker walker(*mesh, {}, 1e-9);
    std::size_t arrived = 0, tried = 0;
    for (Index q = 0; q < 400; ++q) {
      // Points at cell centroids (certainly inside), walked to from far-away starts.
      const Index target = (q * 7919) % nc;
      const auto v = ug.cells.cell(std::size_t(target));
      Vec3 p{};
      for (const Index id : v) p += ug.points[std::size_t(id)] * 0.25;
      Index cell = (q * 104729 + 17) % Index(mesh->cells.size());
      std::array<double, 4> w{};
      ++tried;
      if (!walker.walk(p, cell, w)) continue;
      ++arrived;
      // The weights reproduce p from the reached cell's points.
      const auto u = mesh->cells.cell(std::size_t(cell));
      Vec3 back{};
      for (std::size_t k = 0; k < 4; ++k) back += mesh->points[std::size_t(u[k])] * w[k];
      EXPECT_LT(norm(back - p), 1e-9);
      for (const double x : w) EXPECT_GE(x, -1e-9);
      EXPECT_EQ(cell % nc, target);  // the centroid lies in its own tetrahedron only
      // A linear field's gradient, exact in any tetrahedron: (2, −3, 0.5) for every component.
      std::vector<double> f3;
      for (std::size_t i = 0; i < mesh->points.size(); ++i) {
        const double fi = mesh->point_data.get("f").get(i);
        f3.insert(f3.end(), {fi, fi, fi});
      }
      std::array<Vec3, 3> grad{};
      ASSERT_TRUE(walker.gradient(cell, f3.data(), grad));
      for (const Vec3& g : grad) EXPECT_LT(norm(g - Vec3{2, -3, 0.5}), 1e-9);
    }
    // The mildly twisted mesh is nearly convex: almost every walk arrives.
    EXPECT_GE(arrived, tried * 9 / 10);
    // Bounds: the mesh's own, grown by a tolerance far below a cell.
    const Bounds b = mesh->bounds();
    EXPECT_TRUE(walker.in_bounds(b.min));
    EXPECT_TRUE(walker.in_bounds(b.max));
    EXPECT_FALSE(walker.in_bounds(b.max + Vec3{1e-3, 0, 0}));
    EXPECT_FALSE(walker.in_bounds(b.min - Vec3{0, 0, 1e-3}));
  }
}

TEST(ProbeWalk, TetraPointsOutsideTheBoundsNeedNoLocatorAndMatchIt) {
  // A volume reaching 0.4 beyond the twisted (non-convex) tetra mesh on every side: points
  // outside the mesh's bounds are missed without the locator, points within them that a walk
  // cannot reach go to the locator. Every point is found exactly when the exact locator finds
  // it, with the linear field reproduced.
  const UnstructuredGrid ug = twisted_tetrahedra(6);
  Bounds box = ug.bounds();
  box.min = box.min - Vec3{0.4, 0.4, 0.4};
  box.max = box.max + Vec3{0.4, 0.4, 0.4};
  const ImageData vol = probe_volume(box, {23, 19, 21});
  const auto [out, stats] = probe(ug, vol);
  const auto& pd = std::get<ImageData>(out).point_data;
  const CellLocator exact(ug, {});
  std::size_t outside_bounds = 0, inside = 0;
  const Bounds b = ug.bounds();
  for (std::size_t i = 0; i < vol.num_points(); ++i) {
    const Vec3 p = vol.point(Index(i));
    const bool found = pd.get("vtkValidPointMask").get(i) != 0;
    EXPECT_EQ(found, exact.find_cell(p).found()) << i;
    if (found) {
      EXPECT_NEAR(pd.get("f").get(i), linear(p), 1e-9);
      ++inside;
    }
    if (p.x < b.min.x || p.x > b.max.x || p.y < b.min.y || p.y > b.max.y || p.z < b.min.z ||
        p.z > b.max.z) {
      ++outside_bounds;
    }
  }
  EXPECT_EQ(inside, stats.found);
  EXPECT_GT(outside_bounds, vol.num_points() / 4);
  EXPECT_GT(inside, vol.num_points() / 4);
}
