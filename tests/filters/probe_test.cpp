#include "isoforge/filters/probe.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>
#include <vector>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

/// The linear field every test reproduces: probing interpolates it exactly in any cell.
double linear(const Vec3& p) { return 1.5 + 2 * p.x - 3 * p.y + 0.5 * p.z; }

void add_linear(Attributes& pd, DatasetRef ds) {
  DataArray f("f", ScalarType::Float64, 1, num_points(ds));
  for (std::size_t i = 0; i < num_points(ds); ++i) f.set(i, 0, linear(point(ds, Index(i))));
  pd.add(std::move(f), AttributeRole::Scalars);
}

void add_cell_ids(Attributes& cd, std::size_t cells) {
  DataArray c("cell", ScalarType::Int32, 1, cells);
  for (std::size_t i = 0; i < cells; ++i) c.set(i, 0, double(i));
  cd.add(std::move(c));
}

/// A smooth warp that keeps every hexahedron of a unit-spaced grid valid.
Vec3 warp(const Vec3& p) {
  return {p.x + 0.15 * std::sin(p.y * 1.3) + 0.05 * p.z, p.y + 0.1 * std::cos(p.x * 0.9),
          p.z + 0.12 * std::sin(p.x + p.y)};
}

StructuredGrid warped_grid(Index nx, Index ny, Index nz) {
  StructuredGrid g;
  g.dims = {nx, ny, nz};
  g.points = Points(std::size_t(nx * ny * nz), ScalarType::Float64);
  for (Index k = 0; k < nz; ++k)
    for (Index j = 0; j < ny; ++j)
      for (Index i = 0; i < nx; ++i)
        g.points.set(std::size_t(g.point_id(i, j, k)), warp({double(i), double(j), double(k)}));
  add_linear(g.point_data, g);
  add_cell_ids(g.cell_data, g.num_cells());
  return g;
}

/// Every 3D cell type: a hexahedron, a voxel, five tetrahedra, two wedges and six pyramids
/// (around a centre point), each filling a unit cube of a row of cubes along x.
UnstructuredGrid mixed_cells() {
  UnstructuredGrid ug;
  ug.points = Points(0, ScalarType::Float64);
  auto cube = [&](double x0) {  // the 8 corners, voxel order, and returns the first id
    const Index base = Index(ug.points.size());
    for (int c = 0; c < 8; ++c)
      ug.points.push_back(warp({x0 + (c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}));
    return base;
  };
  Index b = cube(0);  // hexahedron: voxel order 0 1 3 2 / 4 5 7 6
  ug.add_cell(CellType::Hexahedron, {b, b + 1, b + 3, b + 2, b + 4, b + 5, b + 7, b + 6});
  ug.points.push_back({1, 0, 0});  // a true box for the voxel (axis-aligned)
  const Index v = Index(ug.points.size()) - 1;
  for (int c = 1; c < 8; ++c) ug.points.push_back({1.0 + (c & 1), double((c >> 1) & 1), double((c >> 2) & 1)});
  ug.add_cell(CellType::Voxel, {v, v + 1, v + 2, v + 3, v + 4, v + 5, v + 6, v + 7});
  b = cube(2);  // five tetrahedra
  ug.add_cell(CellType::Tetra, {b + 0, b + 1, b + 2, b + 4});
  ug.add_cell(CellType::Tetra, {b + 1, b + 3, b + 2, b + 7});
  ug.add_cell(CellType::Tetra, {b + 1, b + 4, b + 7, b + 5});
  ug.add_cell(CellType::Tetra, {b + 2, b + 7, b + 4, b + 6});
  ug.add_cell(CellType::Tetra, {b + 1, b + 2, b + 4, b + 7});
  b = cube(3);  // two wedges: triangles (0,1,2)/(1,3,2) extruded along z
  ug.add_cell(CellType::Wedge, {b + 0, b + 2, b + 1, b + 4, b + 6, b + 5});
  ug.add_cell(CellType::Wedge, {b + 1, b + 2, b + 3, b + 5, b + 6, b + 7});
  b = cube(4);  // six pyramids to the centre
  ug.points.push_back(warp({4.5, 0.5, 0.5}));
  const Index c = Index(ug.points.size()) - 1;
  const Index faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) ug.add_cell(CellType::Pyramid, {b + f[0], b + f[1], b + f[2], b + f[3], c});
  add_linear(ug.point_data, ug);
  add_cell_ids(ug.cell_data, ug.num_cells());
  ug.validate();
  return ug;
}

/// Triangles, quads, a polygon, pixels are not polydata; lines and a polyline.
PolyData surface_cells() {
  PolyData pd;
  pd.points = Points(0, ScalarType::Float64);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) pd.points.push_back({double(i), double(j), 0.2 * i});
  pd.polys.add({0, 1, 5});
  pd.polys.add({0, 5, 4});
  pd.polys.add({1, 2, 6, 5});
  pd.polys.add({2, 3, 7, 11, 10, 6});  // a planar hexagon
  pd.polys.add({4, 5, 9, 8});
  pd.points.push_back({0, 0, 2});
  pd.points.push_back({3, 2, 3});
  pd.lines.add({12, 13});
  pd.lines.add({13, 7, 0});
  add_linear(pd.point_data, pd);
  add_cell_ids(pd.cell_data, pd.num_cells());
  pd.validate();
  return pd;
}

struct Brute {
  bool found = false;
  double value = 0;
};

/// Every cell tried: the definition the prober must meet.
Brute brute_force(DatasetRef ds, const Vec3& p, double tol, double dtol) {
  std::vector<Index> ids;
  std::vector<Vec3> pts;
  const DataArray& f = point_data(ds).get("f");
  for (std::size_t c = 0; c < num_cells(ds); ++c) {
    const CellType type = cell_type(ds, Index(c));
    cell_point_ids(ds, Index(c), ids);
    pts.clear();
    for (Index id : ids) pts.push_back(point(ds, id));
    const CellPosition pos = locate_in_cell(type, pts, p, tol);
    const int dim = cell_dimension(type);
    const bool hit = dim == 3 ? pos.inside : (dim == 0 || pos.inside) && pos.dist2 <= dtol * dtol;
    if (!hit) continue;
    double v = 0;
    for (std::size_t k = 0; k < ids.size(); ++k) v += pos.weights[k] * f.get(std::size_t(ids[k]));
    return {true, v};
  }
  return {};
}

PolyData cloud(const std::vector<Vec3>& pts) {
  PolyData pd;
  pd.points = Points(0, ScalarType::Float64);
  for (const Vec3& p : pts) pd.points.push_back(p);
  return pd;
}

std::vector<Vec3> random_points(const Bounds& b, std::size_t n, unsigned seed, double grow) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> pts;
  const Vec3 lo = b.min - Vec3{grow, grow, grow}, sz = b.size() + Vec3{2 * grow, 2 * grow, 2 * grow};
  for (std::size_t i = 0; i < n; ++i) pts.push_back(lo + Vec3{u(rng) * sz.x, u(rng) * sz.y, u(rng) * sz.z});
  return pts;
}

/// Probes `pts`, compares each with brute force: same found/not found, the linear field (to
/// float precision), the brute-force value, NaN outside. Returns the number found.
std::size_t expect_matches_brute_force(DatasetRef ds, const std::vector<Vec3>& pts) {
  const PolyData probe_pts = cloud(pts);
  const auto [out, stats] = probe(ds, probe_pts);
  const auto& pd = std::get<PolyData>(out).point_data;
  const DataArray& f = pd.get("f");
  const DataArray& mask = pd.get("vtkValidPointMask");
  const double dtol = 1e-6 * bounds(ds).diagonal();
  std::size_t found = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Brute b = brute_force(ds, pts[i], kDefaultCellTolerance, dtol);
    EXPECT_EQ(mask.get(i) != 0, b.found) << "point " << i << " at " << pts[i].x << " "
                                         << pts[i].y << " " << pts[i].z;
    if (b.found) {
      ++found;
      EXPECT_NEAR(f.get(i), linear(pts[i]), 1e-9) << "point " << i;
      EXPECT_NEAR(f.get(i), b.value, 1e-9) << "point " << i;
    } else {
      EXPECT_TRUE(std::isnan(f.get(i))) << "point " << i;
    }
  }
  EXPECT_EQ(stats.found, found);
  EXPECT_EQ(stats.points, pts.size());
  return found;
}

}  // namespace

TEST(Probe, ImageDataByArithmeticMatchesBruteForce) {
  ImageData img;
  img.dims = {5, 4, 3};
  img.origin = {-1, 0.5, 2};
  img.spacing = {0.5, 0.25, 1};
  add_linear(img.point_data, img);
  add_cell_ids(img.cell_data, img.num_cells());
  const std::size_t found = expect_matches_brute_force(img, random_points(img.bounds(), 400, 1, 0.3));
  // The image fills 2 x 0.75 x 2 of the 2.6 x 1.35 x 2.6 box sampled: about 33 % (131 points).
  EXPECT_GT(found, 90u);
  EXPECT_LT(found, 175u);
}

TEST(Probe, TwoDimensionalImageFindsPointsOnItsPlaneOnly) {
  ImageData img;
  img.dims = {4, 1, 3};  // an x-z plane at y = 0
  add_linear(img.point_data, img);
  const std::vector<Vec3> pts = {{0.5, 0, 0.5}, {3, 0, 2}, {1.2, 0.1, 1}, {3.5, 0, 1}};
  const auto [out, stats] = probe(img, cloud(pts));
  const auto& pd = std::get<PolyData>(out).point_data;
  EXPECT_EQ(pd.get("vtkValidPointMask").get(0), 1);
  EXPECT_EQ(pd.get("vtkValidPointMask").get(1), 1);  // the far corner point itself
  EXPECT_EQ(pd.get("vtkValidPointMask").get(2), 0);  // off the plane
  EXPECT_EQ(pd.get("vtkValidPointMask").get(3), 0);  // beyond x = 3
  EXPECT_DOUBLE_EQ(pd.get("f").get(1), linear({3, 0, 2}));
  EXPECT_EQ(stats.found, 2u);
}

TEST(Probe, CurvilinearGridWalkMatchesBruteForce) {
  const StructuredGrid g = warped_grid(6, 5, 4);
  expect_matches_brute_force(g, random_points(g.bounds(), 700, 2, 0.5));
  // Coherent points (a line through the grid) exercise the walk between neighbours.
  std::vector<Vec3> line;
  for (int i = 0; i <= 400; ++i) line.push_back(Vec3{-0.3, 0.2, 0.1} + Vec3{5.6, 4.3, 3.2} * (i / 400.0));
  expect_matches_brute_force(g, line);
}

TEST(Probe, GridPointsAndFacesAreNeverMissed) {
  // Every grid point and face centre lies on the boundary of up to eight cells: all are found
  // and reproduce the point data exactly (no false misses on shared faces).
  const StructuredGrid g = warped_grid(5, 4, 4);
  std::vector<Vec3> pts;
  for (std::size_t i = 0; i < g.num_points(); ++i) pts.push_back(g.points[i]);
  const auto [out, stats] = probe(g, cloud(pts));
  EXPECT_EQ(stats.found, pts.size());
  const DataArray& f = std::get<PolyData>(out).point_data.get("f");
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_NEAR(f.get(i), g.point_data.get("f").get(i), 1e-12);
}

TEST(Probe, EveryUnstructuredCellTypeMatchesBruteForce) {
  const UnstructuredGrid ug = mixed_cells();
  const std::size_t found = expect_matches_brute_force(ug, random_points(ug.bounds(), 3000, 3, 0.2));
  EXPECT_GT(found, 1000u);
}

/// A warped grid's cubes split into 6 tetrahedra each (the tetra walk's path).
UnstructuredGrid tet_mesh(Index n) {
  const StructuredGrid g = warped_grid(n + 1, n + 1, n + 1);
  UnstructuredGrid ug;
  ug.points = g.points;
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        auto c = [&](int q) { return g.point_id(i + (q & 1), j + ((q >> 1) & 1), k + (q >> 2)); };
        for (const auto& p : paths) ug.add_cell(CellType::Tetra, {c(0), c(p[0]), c(p[1]), c(7)});
      }
  add_linear(ug.point_data, ug);
  add_cell_ids(ug.cell_data, ug.num_cells());
  return ug;
}

TEST(Probe, TetraWalkMatchesBruteForce) {
  // Random points (about half outside: the walk fails and the locator decides), a coherent line
  // (walks between neighbours) and the mesh's own points (on shared faces and edges).
  const UnstructuredGrid ug = tet_mesh(5);
  const std::size_t found = expect_matches_brute_force(ug, random_points(ug.bounds(), 1500, 8, 0.4));
  EXPECT_GT(found, 300u);
  std::vector<Vec3> line;
  for (int i = 0; i <= 300; ++i) line.push_back(Vec3{-0.3, 0.2, 0.1} + Vec3{5.6, 4.3, 3.2} * (i / 300.0));
  expect_matches_brute_force(ug, line);
  std::vector<Vec3> own;
  for (std::size_t i = 0; i < ug.num_points(); ++i) own.push_back(ug.points[i]);
  EXPECT_EQ(expect_matches_brute_force(ug, own), ug.num_points());
  // Blanked tetrahedra are never found, through the walk or the locator.
  UnstructuredGrid blanked = ug;
  std::vector<std::uint8_t> valid(ug.num_cells(), 1);
  for (std::size_t c = 0; c < valid.size(); c += 3) valid[c] = 0;
  blanked.cell_data.add(DataArray::from_vector("Valid", 1, valid));
  const std::vector<Vec3> pts = random_points(ug.bounds(), 800, 9, 0.2);
  const auto r = probe(blanked, cloud(pts));
  const DataArray& mask = std::get<PolyData>(r.output).point_data.get("vtkValidPointMask");
  const DataArray& cell = std::get<PolyData>(r.output).point_data.get("cell");
  std::vector<Index> ids;
  std::vector<Vec3> corners;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    // Brute force over the valid cells only.
    bool expected = false;
    for (std::size_t c = 0; c < ug.num_cells() && !expected; ++c) {
      if (!valid[c]) continue;
      cell_point_ids(ug, Index(c), ids);
      corners.clear();
      for (Index id : ids) corners.push_back(ug.points[std::size_t(id)]);
      expected = locate_in_cell(CellType::Tetra, corners, pts[i]).inside;
    }
    EXPECT_EQ(mask.get(i) != 0, expected) << "point " << i;
    if (mask.get(i) != 0) {
      EXPECT_NE(valid[std::size_t(cell.get(i))], 0) << "point " << i;
    }
  }
  EXPECT_EQ(r.stats.blanked, (ug.num_cells() + 2) / 3);
}

TEST(Probe, SurfaceAndLineCellsFindPointsOnThem) {
  const PolyData pd = surface_cells();
  // Points on the cells (random parametric points) and random points off them.
  std::vector<Vec3> pts = random_points(pd.bounds(), 300, 4, 0.1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Index> ids;
  for (std::size_t c = 0; c < pd.num_cells(); ++c) {
    cell_point_ids(pd, Index(c), ids);
    for (int s = 0; s < 20; ++s) {
      // A convex combination of the cell's points lies on it (all cells here are planar/convex).
      std::vector<double> w(ids.size());
      double sum = 0;
      for (double& x : w) sum += (x = u(rng) + 1e-3);
      Vec3 p{};
      if (cell_type(pd, Index(c)) == CellType::PolyLine) {  // on one segment
        const double t = u(rng);
        p = point(pd, ids[0]) * (1 - t) + point(pd, ids[1]) * t;
      } else {
        for (std::size_t k = 0; k < ids.size(); ++k) p = p + point(pd, ids[k]) * (w[k] / sum);
      }
      pts.push_back(p);
    }
  }
  const std::size_t found = expect_matches_brute_force(pd, pts);
  EXPECT_GE(found, pd.num_cells() * 20);  // every point on a cell
}

TEST(Probe, CellDataIsCopiedAndNamesDoNotCollide) {
  ImageData img;
  img.dims = {3, 2, 2};  // two voxels along x
  add_linear(img.point_data, img);
  add_cell_ids(img.cell_data, 2);
  img.cell_data.add(DataArray::from_vector<double>("f", 1, {10, 20}));
  const auto [out, stats] = probe(img, cloud({{0.5, 0.5, 0.5}, {1.75, 0.2, 0.9}, {5, 0, 0}}));
  const auto& pd = std::get<PolyData>(out).point_data;
  EXPECT_EQ(pd.get("cell").get(0), 0);
  EXPECT_EQ(pd.get("cell").get(1), 1);
  EXPECT_EQ(pd.get("cell").get(2), 0);  // an integer array's nil is 0
  EXPECT_EQ(pd.get("f (cell)").get(1), 20);
  EXPECT_EQ(pd.get("cell").type(), ScalarType::Int32);
  EXPECT_EQ(pd.active_name(AttributeRole::Scalars), "f");
  EXPECT_EQ(stats.found, 2u);
}

TEST(Probe, NilValueAndMaskNameAreOptions) {
  const StructuredGrid g = warped_grid(3, 3, 3);
  ProbeOptions o;
  o.nil_value = -7.6;
  o.mask_name = "inside";
  const auto [out, stats] = probe(g, cloud({{1, 1, 1}, {100, 0, 0}}), o);
  const auto& pd = std::get<PolyData>(out).point_data;
  EXPECT_EQ(pd.get("inside").get(1), 0);
  EXPECT_DOUBLE_EQ(pd.get("f").get(1), -7.6);
  EXPECT_EQ(pd.get("cell").get(1), -8);  // rounded for the integer array
  EXPECT_FALSE(pd.has("vtkValidPointMask"));
  o.mask_name = "";
  EXPECT_THROW((void)probe(g, cloud({}), o), Error);
  o.mask_name = "m";
  o.tolerance = -1;
  EXPECT_THROW((void)probe(g, cloud({}), o), Error);
  o.tolerance = std::nan("");
  EXPECT_THROW((void)probe(g, cloud({}), o), Error);
}

TEST(Probe, BlankedCellsAreNeverFound) {
  // IBlank = 0 at point (1, 1, 1) of a 3x3x3 grid blanks all eight cells around it; the cell
  // array "Valid" blanks nothing more here. Every probe point is then outside.
  StructuredGrid g = warped_grid(3, 3, 3);
  std::vector<std::int32_t> ib(27, 1);
  ib[std::size_t(g.point_id(1, 1, 1))] = 0;
  g.point_data.add(DataArray::from_vector("IBlank", 1, ib));
  const std::vector<Vec3> pts = random_points(g.bounds(), 200, 6, 0);
  auto r = probe(g, cloud(pts));
  EXPECT_EQ(r.stats.found, 0u);
  EXPECT_EQ(r.stats.blanked, 8u);
  // Blank only one cell through "Valid": points on its shared faces are still found in the
  // neighbours; points strictly inside it are not.
  StructuredGrid h = warped_grid(3, 3, 3);
  std::vector<std::uint8_t> valid(8, 1);
  valid[0] = 0;
  h.cell_data.add(DataArray::from_vector("Valid", 1, valid));
  std::vector<Vec3> q = {warp({0.5, 0.5, 0.5}), warp({1, 0.5, 0.5}), warp({1.5, 0.5, 0.5}),
                         h.points[std::size_t(h.point_id(1, 1, 1))]};
  r = probe(h, cloud(q));
  const auto& pd = std::get<PolyData>(r.output).point_data;
  EXPECT_EQ(pd.get("vtkValidPointMask").get(0), 0);
  EXPECT_EQ(pd.get("vtkValidPointMask").get(1), 1);
  EXPECT_EQ(pd.get("vtkValidPointMask").get(2), 1);
  EXPECT_EQ(pd.get("vtkValidPointMask").get(3), 1);
  EXPECT_NE(pd.get("cell").get(1), 0);  // the face point went to a valid neighbour
  // The same through the locator: the grid as unstructured cells, and as image data.
  const UnstructuredGrid u = to_unstructured(h);
  const auto ru = probe(u, cloud(q));
  EXPECT_EQ(ru.stats.found, 3u);
  EXPECT_EQ(std::get<PolyData>(ru.output).point_data.get("vtkValidPointMask").get(0), 0);
  ImageData img;
  img.dims = {3, 3, 3};
  add_linear(img.point_data, img);
  img.cell_data.add(DataArray::from_vector("Valid", 1, valid));
  const auto ri = probe(img, cloud({{0.5, 0.5, 0.5}, {1, 0.5, 0.5}, {1, 1, 1}}));
  EXPECT_EQ(ri.stats.found, 2u);
  // The blanking arrays are options: without them nothing is blanked.
  ProbeOptions o;
  o.cell_validity = "";
  EXPECT_EQ(probe(img, cloud({{0.5, 0.5, 0.5}}), o).stats.found, 1u);
}

TEST(Probe, OutputKeepsTheProbeTypeAndIsIndependentOfThreads) {
  const StructuredGrid g = warped_grid(9, 8, 7);
  const ImageData vol = probe_volume(g.bounds(), {23, 19, 17});
  ProbeOptions o;
  o.nil_value = -1;  // comparable (NaN != NaN)
  const Prober prober(g, o);
  Dataset one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = prober.probe(vol).output;
  }
  const auto [many, stats] = prober.probe(vol);
  ASSERT_TRUE(std::holds_alternative<ImageData>(many));
  EXPECT_EQ(std::get<ImageData>(many).dims, vol.dims);
  EXPECT_TRUE(one == many);
  EXPECT_GT(stats.found, 0u);
  EXPECT_LT(stats.found, stats.points);
  // The reusable prober gives what the one-shot function gives.
  EXPECT_TRUE(probe(g, vol, o).output == many);
}

TEST(Probe, Generators) {
  const PolyData line = probe_line({0, 0, 0}, {1, 2, 3}, 5);
  EXPECT_EQ(line.num_points(), 5u);
  EXPECT_EQ(line.lines.size(), 1u);
  EXPECT_EQ(line.points[4], (Vec3{1, 2, 3}));
  EXPECT_EQ(line.points[2], (Vec3{0.5, 1, 1.5}));
  EXPECT_EQ(probe_line({0, 0, 0}, {1, 2, 3}, 1).verts.size(), 1u);
  EXPECT_THROW((void)probe_line({0, 0, 0}, {1, 1, 1}, 0), Error);
  EXPECT_THROW((void)probe_line({0, std::nan(""), 0}, {1, 1, 1}, 3), Error);
  const PolyData plane = probe_plane({0, 0, 0}, {2, 0, 0}, {0, 0, 1}, 3, 4);
  EXPECT_EQ(plane.num_points(), 12u);
  EXPECT_EQ(plane.polys.size(), 6u);  // (3 - 1) x (4 - 1) quads
  EXPECT_EQ(plane.points[2 + 3 * 3], (Vec3{2, 0, 1}));
  EXPECT_THROW((void)probe_plane({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, 3, 3), Error);  // parallel
  EXPECT_THROW((void)probe_plane({0, 0, 0}, {0, 0, 0}, {2, 0, 0}, 3, 3), Error);  // zero axis
  EXPECT_THROW((void)probe_plane({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 3), Error);
  Bounds b;
  b.extend({0, 0, 0});
  b.extend({1, 2, 0});
  const ImageData v = probe_volume(b, {3, 5, 1});
  EXPECT_EQ(v.spacing, (Vec3{0.5, 0.5, 1}));
  EXPECT_THROW((void)probe_volume(b, {3, 5, 2}), Error);  // zero z extent, 2 points
  EXPECT_THROW((void)probe_volume(b, {0, 5, 1}), Error);
}

TEST(Probe, Figure135CombustorPlanesContouredIntoLines) {
  // Three 50 x 50 planes across the combustor (VTK's probeComb example places them at
  // x = 3.7, 9.2 and 13.27, 5 units wide in y and z), probed and contoured into density lines.
  ReadOptions ro;
  ro.plot3d_q = ISOFORGE_DATA_DIR "/combq.bin";
  const auto grid = std::get<StructuredGrid>(read(ISOFORGE_DATA_DIR "/combxyz.bin", ro));
  const Prober prober(grid);
  const double xs[3] = {3.7, 9.2, 13.27}, zs[3] = {28.37, 31.2, 33.3};
  const auto [lo, hi] = grid.point_data.get("Density").range();
  for (int k = 0; k < 3; ++k) {
    const Vec3 o{xs[k], -2.5, zs[k] - 2.5};
    const PolyData plane = probe_plane(o, o + Vec3{0, 5, 0}, o + Vec3{0, 0, 5}, 50, 50);
    const auto [probed, stats] = prober.probe(plane);
    EXPECT_EQ(stats.points, 2500u);
    // The first two planes lie inside the duct; the third reaches out of it at one corner.
    if (k < 2) {
      EXPECT_EQ(stats.found, 2500u) << "plane " << k;
    } else {
      EXPECT_GT(stats.found, 2000u);
      EXPECT_LT(stats.found, 2500u);
    }
    const auto& pd = std::get<PolyData>(probed);
    const DataArray& rho = pd.point_data.get("Density");
    // Probed values lie in the input's range (interpolation is a convex combination).
    for (std::size_t i = 0; i < 2500; ++i) {
      if (pd.point_data.get("vtkValidPointMask").get(i) == 0) continue;
      EXPECT_GE(rho.get(i), lo - 1e-6);
      EXPECT_LE(rho.get(i), hi + 1e-6);
    }
    const double mid = 0.5 * (rho.range().first + rho.range().second);
    // Contour the quads whose four points were found (the others hold NaN).
    PolyData inside = pd;
    inside.polys = {};
    std::size_t kept = 0;
    for (std::size_t c = 0; c < pd.polys.size(); ++c) {
      const auto ids = pd.polys.cell(c);
      bool all = true;
      for (Index id : ids) all = all && pd.point_data.get("vtkValidPointMask").get(std::size_t(id)) != 0;
      if (all) {
        inside.polys.add(ids);
        ++kept;
      }
    }
    EXPECT_EQ(kept == 49u * 49u, stats.found == 2500u);
    ContourOptions co;
    co.values = {mid};
    co.array = "Density";
    const auto [lines, cs] = contour(inside, co);
    EXPECT_GT(lines.lines.size(), 0u) << "plane " << k;
    // Contour points lie on the plane and carry the isovalue.
    const DataArray& d = lines.point_data.get("Density");
    for (std::size_t i = 0; i < lines.num_points(); ++i) {
      EXPECT_NEAR(lines.points[i].x, xs[k], 1e-4);
      EXPECT_NEAR(d.get(i), mid, 1e-4 * (hi - lo));
    }
  }
}

TEST(Probe, DegenerateInputsAndProbesNeitherCrashNorHang) {
  // A grid whose top layer is collapsed onto the middle one (zero-volume hexahedra), and one
  // whose points all coincide: points in the valid cells are found, the rest are not, and
  // non-finite probe points are never found.
  StructuredGrid g = warped_grid(4, 4, 3);
  for (Index j = 0; j < 4; ++j)
    for (Index i = 0; i < 4; ++i)
      g.points.set(std::size_t(g.point_id(i, j, 2)), g.points[std::size_t(g.point_id(i, j, 1))]);
  g.point_data.clear();
  g.cell_data.clear();
  add_linear(g.point_data, g);
  add_cell_ids(g.cell_data, g.num_cells());
  const double nan = std::nan("");
  const std::vector<Vec3> pts = {warp({1.5, 1.5, 0.5}), {nan, 0, 0}, {1, 1, 1.5}, {1e300, 0, 0}};
  const auto r = probe(g, cloud(pts));
  const DataArray& mask = std::get<PolyData>(r.output).point_data.get("vtkValidPointMask");
  EXPECT_EQ(mask.get(0), 1);
  EXPECT_EQ(mask.get(1), 0);
  EXPECT_EQ(mask.get(3), 0);
  StructuredGrid same;
  same.dims = {3, 3, 3};
  same.points = Points(27, ScalarType::Float64);
  for (std::size_t i = 0; i < 27; ++i) same.points.set(i, {1, 2, 3});
  EXPECT_EQ(probe(same, cloud({{1, 2, 3}, {0, 0, 0}, {nan, nan, nan}})).stats.points, 3u);
  // The same for tetrahedra: a flat tetra among valid ones.
  UnstructuredGrid ug = tet_mesh(2);
  ug.add_cell(CellType::Tetra, {0, 1, 2, 2});
  ug.cell_data.clear();
  add_cell_ids(ug.cell_data, ug.num_cells());
  const auto rt = probe(ug, cloud({{0.5, 0.5, 0.5}, {nan, 0, 0}, {50, 50, 50}}));
  EXPECT_EQ(rt.stats.found, 1u);
}
