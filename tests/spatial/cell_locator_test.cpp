#include "isoforge/spatial/cell_locator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

// A curved 6 x 5 x 4 structured grid of hexahedra: a box bent around the z axis and sheared, so
// that cells are not boxes (Newton iteration in locate_in_cell) and neighbours meet on curved
// faces.
StructuredGrid bent_grid() {
  StructuredGrid g;
  g.dims = {6, 5, 4};
  for (Index k = 0; k < 4; ++k)
    for (Index j = 0; j < 5; ++j)
      for (Index i = 0; i < 6; ++i) {
        const double r = 1 + 0.3 * static_cast<double>(i), a = 0.25 * static_cast<double>(j);
        g.points.push_back(
            {r * std::cos(a), r * std::sin(a), 0.4 * static_cast<double>(k) + 0.05 * j});
      }
  return g;
}

// Mixed 3D cells tiling [0, 2] x [0, 1] x [0, 1]: a hexahedron on [0, 1]^3, and [1, 2] x [0, 1]^2
// cut into two wedges (prisms along z over the triangles of the square), plus a pyramid on top
// of the hexahedron's top face and one tetra beside it.
UnstructuredGrid mixed_grid() {
  UnstructuredGrid u;
  const Vec3 pts[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},       {0, 1, 0}, {0, 0, 1},
                      {1, 0, 1}, {1, 1, 1}, {0, 1, 1},       {2, 0, 0}, {2, 1, 0},
                      {2, 0, 1}, {2, 1, 1}, {0.5, 0.5, 1.6}, {2, 0, 2}};
  for (const Vec3& p : pts) u.points.push_back(p);
  u.add_cell(CellType::Hexahedron, {0, 1, 2, 3, 4, 5, 6, 7});
  u.add_cell(CellType::Wedge, {1, 8, 9, 5, 10, 11});
  u.add_cell(CellType::Wedge, {1, 9, 2, 5, 11, 6});
  u.add_cell(CellType::Pyramid, {4, 5, 6, 7, 12});
  u.add_cell(CellType::Tetra, {5, 10, 11, 13});
  return u;
}

// The smallest cell id whose locate_in_cell says inside (3D cells), by trying every cell.
Index brute_find(DatasetRef ds, const Vec3& p) {
  std::vector<Index> ids;
  std::vector<Vec3> pts;
  for (std::size_t c = 0; c < num_cells(ds); ++c) {
    cell_point_ids(ds, Index(c), ids);
    pts.clear();
    for (Index id : ids) pts.push_back(point(ds, id));
    if (locate_in_cell(cell_type(ds, Index(c)), pts, p).inside) return Index(c);
  }
  return -1;
}

double brute_dist2(DatasetRef ds, const Vec3& p) {
  std::vector<Index> ids;
  std::vector<Vec3> pts;
  double best = INFINITY;
  for (std::size_t c = 0; c < num_cells(ds); ++c) {
    cell_point_ids(ds, Index(c), ids);
    pts.clear();
    for (Index id : ids) pts.push_back(point(ds, id));
    best = std::min(best, locate_in_cell(cell_type(ds, Index(c)), pts, p).dist2);
  }
  return best;
}

void expect_like_brute_force(DatasetRef ds, const Bounds& box, int queries, unsigned seed) {
  const CellLocator locator(ds);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 lo = box.min - box.size() * 0.1, size = box.size() * 1.2;
  int found = 0;
  for (int q = 0; q < queries; ++q) {
    const Vec3 p{lo.x + size.x * u(rng), lo.y + size.y * u(rng), lo.z + size.z * u(rng)};
    const CellHit hit = locator.find_cell(p);
    ASSERT_EQ(hit.cell, brute_find(ds, p)) << "query " << q;
    found += hit.found();
    if (hit.found()) {
      // The weights interpolate the query point.
      std::vector<Index> ids;
      cell_point_ids(ds, hit.cell, ids);
      Vec3 x{};
      for (std::size_t k = 0; k < ids.size(); ++k) x += point(ds, ids[k]) * hit.weights[k];
      EXPECT_LT(norm(x - p), 1e-9 * (1 + box.diagonal()));
    }
    const CellHit near = locator.closest_point(p);
    ASSERT_TRUE(near.found());
    EXPECT_NEAR(near.dist2, brute_dist2(ds, p), 1e-12 * box.diagonal() * box.diagonal());
    EXPECT_NEAR(norm2(near.closest_point - p), near.dist2, 1e-9);
  }
  EXPECT_GT(found, queries / 4);  // the queries exercise both outcomes
  EXPECT_LT(found, queries);
}

}  // namespace

TEST(CellLocator, CurvedStructuredGridMatchesBruteForce) {
  const StructuredGrid g = bent_grid();
  expect_like_brute_force(g, g.points.bounds(), 1500, 1);
}

TEST(CellLocator, MixedUnstructuredCellsMatchBruteForce) {
  const UnstructuredGrid u = mixed_grid();
  expect_like_brute_force(u, u.points.bounds(), 1500, 2);
}

TEST(CellLocator, ImageDataAndSharedFacesGiveTheSmallestId) {
  ImageData img;
  img.dims = {4, 3, 2};
  img.spacing = {0.5, 1, 2};
  expect_like_brute_force(img, img.bounds(), 500, 3);
  // A point on the face shared by voxels 0 and 1 belongs to the smaller id.
  const CellHit h = find_cell(img, {0.5, 0.5, 1});
  EXPECT_EQ(h.cell, 0);
  EXPECT_NEAR(h.pcoords.x, 1.0, 1e-12);
  // Outside: not found; the closest point is on the boundary.
  EXPECT_FALSE(find_cell(img, {-0.1, 0.5, 1}).found());
  const CellHit c = closest_cell_point(img, {-1, 0.5, 1});
  EXPECT_EQ(c.cell, 0);
  EXPECT_NEAR(c.dist2, 1.0, 1e-12);
  EXPECT_NEAR(c.closest_point.x, 0.0, 1e-12);
}

TEST(CellLocator, SurfacesNeedTheDistanceTolerance) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({1, 0, 0});
  pd.points.push_back({0, 1, 0});
  pd.points.push_back({1, 1, 0});
  pd.polys.add({0, 1, 2});
  pd.polys.add({1, 3, 2});
  pd.lines.add({0, 3});  // a diagonal line: cell 0 (lines come before polys)
  CellLocatorOptions o;
  o.distance_tolerance = 1e-6;
  const CellLocator locator(pd, o);
  EXPECT_EQ(locator.find_cell({0.7, 0.6, 0}).cell, 2);        // the second triangle
  EXPECT_EQ(locator.find_cell({0.2, 0.1, 5e-7}).cell, 1);     // within the tolerance above it
  EXPECT_FALSE(locator.find_cell({0.2, 0.1, 1e-3}).found());  // too far above the surface
  EXPECT_EQ(locator.find_cell({0.5, 0.5, 0}).cell, 0);        // on the line: the smallest id
  EXPECT_NEAR(locator.closest_point({0.2, 0.1, 2}).dist2, 4.0, 1e-12);
}

TEST(CellLocator, RejectsBadOptionsAndEmptyDatasetsFindNothing) {
  const ImageData img;  // one point: a vertex cell
  CellLocatorOptions o;
  o.tolerance = -1;
  expect_error([&] { (void)CellLocator(img, o); }, "tolerance");
  o.tolerance = 0;
  o.distance_tolerance = NAN;
  expect_error([&] { (void)CellLocator(img, o); }, "distance tolerance");
  UnstructuredGrid none;
  none.points.push_back({0, 0, 0});
  const CellLocator empty(none);
  EXPECT_FALSE(empty.find_cell({0, 0, 0}).found());
  EXPECT_FALSE(empty.closest_point({0, 0, 0}).found());
}
