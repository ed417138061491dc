// Tests of filters/cut.hpp: exact counts on tiny inputs, invariants on larger ones.

#include "isoforge/filters/cut.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "isoforge/core/cell.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/io/io.hpp"
#include "support/sample_datasets.hpp"

using namespace isoforge;
using isoforge::test::single_cell;

namespace {

CutOptions values_opt(std::vector<double> values) {
  CutOptions o;
  o.values = std::move(values);
  return o;
}
CutOptions linear_opt() {
  CutOptions o;
  o.refine = false;
  return o;
}
CutOptions triangles_opt() {
  CutOptions o;
  o.triangulate = true;
  return o;
}

Vec3 polygon_area_vector(const PolyData& pd, std::size_t c) {
  const auto ids = pd.polys.cell(c);
  Vec3 n{};
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Vec3 a = pd.points[static_cast<std::size_t>(ids[i])];
    const Vec3 b = pd.points[static_cast<std::size_t>(ids[(i + 1) % ids.size()])];
    n += cross(a, b);
  }
  return n * 0.5;
}

/// Edges of the polygons: how many polygons use each (unordered) edge.
std::map<std::pair<Index, Index>, int> edge_uses(const PolyData& pd) {
  std::map<std::pair<Index, Index>, int> uses;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      Index a = ids[i], b = ids[(i + 1) % ids.size()];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  return uses;
}

/// Number of distinct edges of the dataset's cells whose ends are on both sides of c (F >= c
/// above), counted from the cells' edge tables: the cut has one point per such edge.
std::size_t crossed_edges(DatasetRef ds, const std::vector<double>& F, double c) {
  std::set<std::pair<Index, Index>> edges;
  std::vector<Index> ids;
  for (std::size_t cell = 0; cell < num_cells(ds); ++cell) {
    cell_point_ids(ds, static_cast<Index>(cell), ids);
    const CellType t = cell_type(ds, static_cast<Index>(cell));
    std::vector<CellEdge> list;
    if (cell_fixed_size(t) > 0 && cell_dimension(t) >= 2) {
      auto e = cell_edges(t);
      list.assign(e.begin(), e.end());
    } else if (t == CellType::Polygon) {
      for (int i = 0; i < static_cast<int>(ids.size()); ++i) list.push_back(polygon_edge(ids.size(), i));
    } else if (t == CellType::Line) {
      list.push_back({0, 1});
    }
    for (const CellEdge& e : list) {
      const Index a = ids[static_cast<std::size_t>(e[0])], b = ids[static_cast<std::size_t>(e[1])];
      if ((F[static_cast<std::size_t>(a)] >= c) != (F[static_cast<std::size_t>(b)] >= c)) {
        edges.insert({std::min(a, b), std::max(a, b)});
      }
    }
  }
  return edges.size();
}

std::vector<double> values_at_points(const ImplicitFunction& f, DatasetRef ds) {
  std::vector<double> F(num_points(ds));
  for (std::size_t i = 0; i < F.size(); ++i) F[i] = f.value(point(ds, static_cast<Index>(i)));
  return F;
}

/// A curvilinear grid: the box [-1.2, 1.2]^3 sampled n^3 with a smooth bend (non-planar cells).
StructuredGrid bent_grid(Index n) {
  StructuredGrid sg;
  sg.dims = {n, n, n};
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const double x = -1.2 + 2.4 * i / (n - 1), y = -1.2 + 2.4 * j / (n - 1),
                     z = -1.2 + 2.4 * k / (n - 1);
        sg.points.push_back({x + 0.05 * std::sin(3 * y), y + 0.05 * std::sin(2 * z), z});
      }
  DataArray d("density", ScalarType::Float32, 1, sg.num_points());
  for (std::size_t i = 0; i < sg.num_points(); ++i) {
    const Vec3 p = sg.points[i];
    d.set(i, 0, 2 * p.x - p.y + 0.5 * p.z);  // linear: interpolation along an edge is exact
  }
  sg.point_data.add(std::move(d), AttributeRole::Scalars);
  return sg;
}

}  // namespace

// The polygon of a single cell cut by a plane is its exact cross-section (planar faces), one
// polygon with one point per crossed edge, oriented toward increasing F.
TEST(Cut, SingleCellsGiveTheirCrossSections) {
  struct Case {
    CellType type;
    std::vector<Vec3> pts;
    ImplicitFunction f;
    double area;
    std::size_t points;
  };
  const double s3 = std::sqrt(3.0);
  std::vector<Case> cases = {
      // Tet cut by x + y + z = 0.5: the equilateral triangle (0.5,0,0),(0,0.5,0),(0,0,0.5).
      {CellType::Tetra, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
       ImplicitFunction::plane({0.5, 0, 0}, {1, 1, 1}), s3 / 2 * 0.25, 3},
      // Unit cube at z = 0.3: a unit square.
      {CellType::Hexahedron,
       {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
       ImplicitFunction::plane({0, 0, 0.3}, {0, 0, 1}), 1.0, 4},
      {CellType::Voxel,
       {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}},
       ImplicitFunction::plane({0, 0, 0.3}, {0, 0, -1}), 1.0, 4},
      // Unit cube by the plane x + y + z = 1.5 through its centre: the regular hexagon of side
      // sqrt(2)/2, area 3 sqrt(3)/2 * (1/2) = 3 sqrt(3)/4.
      {CellType::Hexahedron,
       {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
       ImplicitFunction::plane({0.5, 0.5, 0.5}, {1, 1, 1}), 3 * s3 / 4, 6},
      // Wedge over the right triangle (area 1/2), cut at half height (VTK's valid wedge: the
      // base's right-hand normal points away from the top).
      {CellType::Wedge, {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}},
       ImplicitFunction::plane({0, 0, 0.5}, {0, 0, 1}), 0.5, 3},
      // Pyramid with a unit base and apex height 1, cut at half height: a square of side 1/2.
      {CellType::Pyramid, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}},
       ImplicitFunction::plane({0, 0, 0.5}, {0, 0, 1}), 0.25, 4},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(cell_type_name(c.type));
    const UnstructuredGrid g = single_cell(c.type, c.pts);
    const auto [pd, stats] = cut(g, c.f);
    ASSERT_EQ(pd.polys.size(), 1u);
    EXPECT_EQ(pd.points.size(), c.points);
    EXPECT_EQ(pd.polys.cell_size(0), c.points);
    const Vec3 n = polygon_area_vector(pd, 0);
    EXPECT_NEAR(norm(n), c.area, 1e-6);
    EXPECT_GT(dot(n, c.f.gradient({0, 0, 0})), 0) << "normal toward increasing F";
    for (std::size_t i = 0; i < pd.points.size(); ++i) {
      EXPECT_NEAR(c.f.value(pd.points[i]), 0, 1e-7);
    }
  }
}

TEST(Cut, ValuesAreChecked) {
  UnstructuredGrid g = single_cell(CellType::Tetra, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0}, {0, 0, 1});
  EXPECT_THROW((void)cut(g, f, values_opt({})), Error);
  EXPECT_THROW((void)cut(g, f, values_opt({NAN})), Error);
  EXPECT_THROW((void)cut(g, f, values_opt({0.5, INFINITY})), Error);
  EXPECT_THROW((void)generate_values(0, 0, 1), Error);
  EXPECT_THROW((void)generate_values(2, 1, 0), Error);
  EXPECT_THROW((void)generate_values(1, 0, 1), Error);
  EXPECT_THROW((void)generate_values(3, 0, NAN), Error);
  EXPECT_EQ(generate_values(1, 2, 2), std::vector<double>{2});
  const auto v = generate_values(46, 1.5, 136.5);  // Fig. 1.33's family
  ASSERT_EQ(v.size(), 46u);
  EXPECT_EQ(v.front(), 1.5);
  EXPECT_EQ(v.back(), 136.5);
  EXPECT_DOUBLE_EQ(v[1] - v[0], 3.0);
}

// The plane fast path on image data and the general path on the same cells as an unstructured
// grid give the same cut: one point per crossed edge (counted independently), every point on
// the plane, the same polygons, interpolated point data and copied cell data.
TEST(Cut, ImagePlaneFastPathMatchesTheGeneralPath) {
  ImageData img;
  img.dims = {13, 11, 9};
  img.origin = {-1, -0.5, 0.25};
  img.spacing = {0.2, 0.15, 0.3};
  DataArray d("density", ScalarType::Float64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    const Vec3 p = img.point(static_cast<Index>(i));
    d.set(i, 0, 3 * p.x - 2 * p.y + p.z);
  }
  img.point_data.add(std::move(d));
  DataArray cid("cell", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t i = 0; i < img.num_cells(); ++i) cid.set(i, 0, static_cast<double>(i));
  img.cell_data.add(std::move(cid));
  const UnstructuredGrid ug = to_unstructured(img);
  const std::vector<double> values{-0.3, 0.05, 0.4};
  // Every sign of the normal's components (the fast path treats rows rising and falling along x
  // differently), normals along the axes, and triangulated output.
  const Vec3 normals[] = {{-0.287, 0.3, 0.9579},
                          {0.287, -0.3, 0.9579},
                          {0.6, 0.5, -0.4},
                          {-0.6, -0.5, -0.4},
                          {0, 0, 1},
                          {1, 0, 0},
                          {0, -1, 0},
                          {0.7, 0, -0.7}};
  for (const Vec3& normal : normals) {
    for (const bool triangulate : {false, true}) {
      SCOPED_TRACE("normal " + std::to_string(normal.x) + " " + std::to_string(normal.y) + " " +
                   std::to_string(normal.z) + (triangulate ? " triangulated" : ""));
      const ImplicitFunction f = ImplicitFunction::plane({0.13, 0.21, 1.3}, normal);
      CutOptions opt = values_opt(values);
      opt.triangulate = triangulate;
      const auto [fast, fs] = cut(img, f, opt);
      const auto [slow, ss] = cut(ug, f, opt);
      EXPECT_TRUE(fs.fast_path);
      EXPECT_FALSE(ss.fast_path);
      const std::vector<double> F = values_at_points(f, img);
      std::size_t expected_points = 0;
      for (double c : values) expected_points += crossed_edges(img, F, c);
      EXPECT_GT(expected_points, 100u);
      EXPECT_EQ(fast.points.size(), expected_points);
      EXPECT_EQ(slow.points.size(), expected_points);
      EXPECT_EQ(fast.polys.size(), slow.polys.size());
      EXPECT_EQ(fast.polys.connectivity().size(), slow.polys.connectivity().size());
      for (const PolyData* pd : {&fast, &slow}) {
        const auto vi = pd->point_data.get("CutValueIndex").values<std::int32_t>();
        const DataArray& dens = pd->point_data.get("density");
        for (std::size_t i = 0; i < pd->points.size(); ++i) {
          const Vec3 p = pd->points[i];
          const double c = values[static_cast<std::size_t>(vi[i])];
          // Float storage: within a few ulps of the coordinates (|grad F| = 1).
          EXPECT_NEAR(f.value(p), c, 4e-7);
          EXPECT_NEAR(dens.get(i), 3 * p.x - 2 * p.y + p.z, 2e-6);
        }
        // The cell array says which voxel each polygon came from: its centroid lies in that voxel.
        const DataArray& cells = pd->cell_data.get("cell");
        for (std::size_t c = 0; c < pd->polys.size(); ++c) {
          const auto ids = pd->polys.cell(c);
          Vec3 m{};
          for (Index id : ids) m += pd->points[static_cast<std::size_t>(id)];
          m = m / static_cast<double>(ids.size());
          const auto v = static_cast<Index>(cells.get(c));
          const Index i = v % 12, j = (v / 12) % 10, k = v / 120;
          EXPECT_GE(m.x, img.point(i, j, k).x - 1e-6);
          EXPECT_LE(m.x, img.point(i + 1, j, k).x + 1e-6);
          EXPECT_GE(m.z, img.point(i, j, k).z - 1e-6);
          EXPECT_LE(m.z, img.point(i, j, k + 1).z + 1e-6);
          EXPECT_GT(dot(polygon_area_vector(*pd, c), f.gradient({})), 0);
        }
        // Each plane's cut of the box is one closed disc: interior edges are shared by two
        // polygons, the boundary edges form closed loops (every boundary point has two boundary
        // edges).
        std::map<Index, int> boundary_degree;
        for (const auto& [e, uses] : edge_uses(*pd)) {
          ASSERT_LE(uses, 2);
          if (uses == 1) ++boundary_degree[e.first], ++boundary_degree[e.second];
        }
        for (const auto& [p, deg] : boundary_degree) EXPECT_EQ(deg, 2);
      }
    }
  }
}

// A grid point exactly on the plane is one output point, shared by all its edges: a plane
// through a layer of points gives that layer as quads.
TEST(Cut, PlaneThroughGridPointsMergesThem) {
  ImageData img;
  img.dims = {5, 4, 6};
  const auto [pd, stats] = cut(img, ImplicitFunction::plane({0, 0, 2}, {0, 0, 1}));
  EXPECT_FALSE(stats.fast_path);     // exact hits take the general path
  EXPECT_EQ(pd.points.size(), 20u);  // the 5 x 4 points of layer k = 2
  EXPECT_EQ(pd.polys.size(), 12u);   // from the voxels below the layer only
  for (std::size_t i = 0; i < pd.points.size(); ++i) EXPECT_EQ(pd.points[i].z, 2.0);
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    EXPECT_EQ(pd.polys.cell_size(c), 4u);
    EXPECT_NEAR(polygon_area_vector(pd, c).z, 1.0, 1e-12);
  }
}

// A sphere through a curvilinear grid: a closed surface (every edge used by two polygons),
// outward oriented (positive enclosed volume close to the ball's), every point on the sphere
// to float precision (refined), one point per crossed edge, exact linear density.
TEST(Cut, SphereThroughACurvilinearGridIsClosed) {
  const StructuredGrid sg = bent_grid(24);
  const ImplicitFunction f = ImplicitFunction::sphere({0.05, -0.1, 0.02}, 0.8);
  const auto [pd, stats] = cut(sg, f);
  const std::vector<double> F = values_at_points(f, sg);
  EXPECT_EQ(pd.points.size(), crossed_edges(sg, F, 0.0));
  for (const auto& [e, uses] : edge_uses(pd)) EXPECT_EQ(uses, 2);
  double volume = 0;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    const Vec3 a = pd.points[static_cast<std::size_t>(ids[0])];
    for (std::size_t t = 1; t + 1 < ids.size(); ++t) {
      volume += dot(a, cross(pd.points[static_cast<std::size_t>(ids[t])],
                             pd.points[static_cast<std::size_t>(ids[t + 1])])) / 6;
    }
  }
  const double ball = 4.0 / 3.0 * M_PI * 0.8 * 0.8 * 0.8;
  EXPECT_NEAR(volume, ball, 0.03 * ball);
  const DataArray& dens = pd.point_data.get("density");
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    const Vec3 p = pd.points[i];
    EXPECT_LE(std::abs(f.value(p)), 3e-7);
    EXPECT_NEAR(dens.get(i), 2 * p.x - p.y + 0.5 * p.z, 1e-5);
  }
  // Without refinement the points are the linear estimates: off the sphere by O(h^2).
  const auto [rough, rs] = cut(sg, f, linear_opt());
  double worst = 0;
  for (std::size_t i = 0; i < rough.points.size(); ++i) {
    worst = std::max(worst, std::abs(f.value(rough.points[i])));
  }
  EXPECT_GT(worst, 1e-4);
  // Triangulated: the same points, every polygon of k points becomes k - 2 triangles.
  const auto [tri, ts] = cut(sg, f, triangles_opt());
  EXPECT_EQ(tri.points.size(), pd.points.size());
  EXPECT_EQ(tri.polys.connectivity().size(), 3 * (pd.polys.connectivity().size() - 2 * pd.polys.size()));
}

// 2D cells give closed polylines around a closed surface; 1D cells give points.
TEST(Cut, SurfacesGiveClosedLinesAndLinesGivePoints) {
  // A closed surface: the cut of a sampled sphere's volume (from this filter), 3 planes z = c.
  const ImplicitFunction ball = ImplicitFunction::sphere({0, 0, 0}, 1);
  const auto [surface, s0] = cut(bent_grid(20), ball, triangles_opt());
  const std::vector<double> values{-0.5, 0.0, 0.5};
  const ImplicitFunction zf = ImplicitFunction::plane({0, 0, 0}, {0, 0, 1});
  const auto [lines, s1] = cut(surface, zf, values_opt(values));
  EXPECT_EQ(lines.polys.size(), 0u);
  ASSERT_EQ(lines.lines.size(), 3u);  // one closed loop per plane
  std::vector<double> F = values_at_points(zf, surface);
  std::size_t expected = 0;
  for (double c : values) expected += crossed_edges(surface, F, c);
  EXPECT_EQ(lines.points.size(), expected);
  std::size_t visited = 0;  // each loop visits its points once
  for (std::size_t l = 0; l < 3; ++l) {
    const auto ids = lines.lines.cell(l);
    EXPECT_EQ(ids.front(), ids.back()) << "closed";
    visited += ids.size() - 1;
  }
  EXPECT_EQ(visited, lines.points.size());
  const auto vi = lines.point_data.get("CutValueIndex").values<std::int32_t>();
  for (std::size_t i = 0; i < lines.points.size(); ++i) {
    EXPECT_NEAR(lines.points[i].z, values[static_cast<std::size_t>(vi[i])], 1e-7);
  }
  // The loops cut by z = c again give points (1D cells): two per loop crossing x = 0.
  PolyData loops = lines;
  const auto [pts, s2] = cut(loops, ImplicitFunction::plane({0, 0, 0}, {1, 0, 0}));
  EXPECT_EQ(pts.verts.size(), 6u);
  EXPECT_EQ(pts.points.size(), 6u);
  for (std::size_t i = 0; i < pts.points.size(); ++i) EXPECT_NEAR(pts.points[i].x, 0, 1e-7);
}

// The output does not depend on the number of threads.
TEST(Cut, DeterministicForAnyThreadCount) {
  const StructuredGrid sg = bent_grid(30);
  const ImplicitFunction f = ImplicitFunction::sphere({0, 0, 0}, 0.9);
  PolyData one, two;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    one = cut(sg, f, values_opt({-0.2, 0.0})).output;
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    two = cut(sg, f, values_opt({-0.2, 0.0})).output;
  }
  EXPECT_TRUE(one == two);
}

// ---- The chapter's figures, on the real data ----

namespace {

StructuredGrid combustor() {
  ReadOptions ro;
  ro.plot3d_q = ISOFORGE_DATA_DIR "/combq.bin";
  return std::get<StructuredGrid>(read(ISOFORGE_DATA_DIR "/combxyz.bin", ro));
}

/// Independent expectation: every crossed edge of the grid's hexahedra with its linearly
/// interpolated point and density.
struct Expected {
  Vec3 p;
  double density;
};
std::vector<Expected> expected_points(const StructuredGrid& sg, const std::vector<double>& F,
                                      double c) {
  std::set<std::pair<Index, Index>> edges;
  std::vector<Index> ids;
  for (std::size_t cell = 0; cell < sg.num_cells(); ++cell) {
    cell_point_ids(sg, static_cast<Index>(cell), ids);
    for (const CellEdge& e : cell_edges(CellType::Hexahedron)) {
      const Index a = ids[static_cast<std::size_t>(e[0])], b = ids[static_cast<std::size_t>(e[1])];
      if ((F[static_cast<std::size_t>(a)] >= c) != (F[static_cast<std::size_t>(b)] >= c)) {
        edges.insert({std::min(a, b), std::max(a, b)});
      }
    }
  }
  const DataArray& d = sg.point_data.get("Density");
  std::vector<Expected> out;
  for (const auto& [a, b] : edges) {
    const double fa = F[static_cast<std::size_t>(a)], fb = F[static_cast<std::size_t>(b)];
    const double t = (c - fa) / (fb - fa);
    const Vec3 pa = sg.points[static_cast<std::size_t>(a)], pb = sg.points[static_cast<std::size_t>(b)];
    out.push_back({pa + (pb - pa) * t, (1 - t) * d.get(static_cast<std::size_t>(a)) +
                                           t * d.get(static_cast<std::size_t>(b))});
  }
  return out;
}

}  // namespace

// Fig. 1.31: the combustor cut by the plane through its centre with normal (-0.287, 0, 0.9579),
// coloured by density. One point per crossed edge, each the linear interpolation along its edge
// (position and density), on the plane to float precision; polygons toward the normal.
TEST(CutFigures, Fig131CombustorPlane) {
  const StructuredGrid sg = combustor();
  const Vec3 centre = sg.bounds().center();
  const ImplicitFunction f = ImplicitFunction::plane(centre, {-0.287, 0, 0.9579});
  const auto [pd, stats] = cut(sg, f);
  EXPECT_TRUE(stats.fast_path);
  const std::vector<double> F = values_at_points(f, sg);
  std::vector<Expected> expected = expected_points(sg, F, 0.0);
  ASSERT_EQ(pd.points.size(), expected.size());
  std::sort(expected.begin(), expected.end(), [](const Expected& a, const Expected& b) { return a.p.x < b.p.x; });
  const DataArray& density = pd.point_data.get("Density");
  const double scale = norm(sg.bounds().max) + 1;
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    const Vec3 p = pd.points[i];
    EXPECT_LE(std::abs(f.value(p)), 4 * std::ldexp(scale, -24));
    // The expected point at the same place (within float rounding).
    auto it = std::lower_bound(expected.begin(), expected.end(), p.x - 1e-4,
                               [](const Expected& e, double x) { return e.p.x < x; });
    bool found = false;
    for (; it != expected.end() && it->p.x <= p.x + 1e-4 && !found; ++it) {
      if (norm(it->p - p) < 1e-4) {
        found = true;
        EXPECT_NEAR(density.get(i), it->density, 1e-6);
      }
    }
    EXPECT_TRUE(found) << "point " << i;
  }
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    EXPECT_GT(dot(polygon_area_vector(pd, c), Vec3{-0.287, 0, 0.9579}), 0);
  }
  // The cut of the grid is one sheet: no edge used by more than two polygons, and its border
  // (edges used once) is made of closed loops.
  std::map<Index, int> border;
  for (const auto& [e, uses] : edge_uses(pd)) {
    ASSERT_LE(uses, 2);
    if (uses == 1) ++border[e.first], ++border[e.second];
  }
  for (const auto& [p, deg] : border) EXPECT_EQ(deg % 2, 0);
}

// Fig. 1.32: 100 planes perpendicular to a view direction, through the whole combustor.
TEST(CutFigures, Fig132HundredPlanes) {
  const StructuredGrid sg = combustor();
  const Vec3 view = Vec3{1, 0.4, 0.6} / norm(Vec3{1, 0.4, 0.6});
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0}, view);
  const std::vector<double> F = values_at_points(f, sg);
  const auto [lo, hi] = std::minmax_element(F.begin(), F.end());
  const double step = (*hi - *lo) / 101;
  const std::vector<double> values = generate_values(100, *lo + step, *hi - step);
  const auto [pd, stats] = cut(sg, f, values_opt(values));
  std::size_t expected = 0;
  for (double c : values) expected += crossed_edges(sg, F, c);
  EXPECT_EQ(pd.points.size(), expected);
  const auto vi = pd.point_data.get("CutValueIndex").values<std::int32_t>();
  std::set<std::int32_t> seen(vi.begin(), vi.end());
  EXPECT_EQ(seen.size(), 100u);  // every plane crosses the grid
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    EXPECT_NEAR(f.value(pd.points[i]), values[static_cast<std::size_t>(vi[i])], 4e-6);
  }
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    EXPECT_GT(dot(polygon_area_vector(pd, c), view), 0);
  }
}

// Fig. 1.33: the skin (Torso.vtp) cut by the plane family y = c, 46 values 1.5 ... 136.5:
// contour lines, one point per crossed edge, each line closed or ending on the border of the
// skin (an edge used by one polygon).
TEST(CutFigures, Fig133TorsoContourLines) {
  const PolyData torso = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/Torso.vtp"));
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0}, {0, 1, 0});
  const std::vector<double> values = generate_values(46, 1.5, 136.5);
  const auto [pd, stats] = cut(torso, f, values_opt(values));
  EXPECT_EQ(pd.polys.size(), 0u);
  const std::vector<double> F = values_at_points(f, torso);
  std::size_t expected = 0;
  for (double c : values) expected += crossed_edges(torso, F, c);
  EXPECT_EQ(pd.points.size(), expected);
  const auto vi = pd.point_data.get("CutValueIndex").values<std::int32_t>();
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    EXPECT_NEAR(pd.points[i].y, values[static_cast<std::size_t>(vi[i])], 1e-5);
  }
  // Border edges of the skin.
  const auto uses = edge_uses(torso);
  std::vector<std::pair<Vec3, Vec3>> border;
  for (const auto& [e, n] : uses) {
    if (n == 1) border.push_back({torso.points[static_cast<std::size_t>(e.first)], torso.points[static_cast<std::size_t>(e.second)]});
  }
  auto on_border = [&](const Vec3& p) {
    for (const auto& [a, b] : border) {
      const Vec3 d = b - a;
      const double t = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
      if (norm(a + d * t - p) < 1e-3) return true;
    }
    return false;
  };
  std::size_t closed = 0;
  for (std::size_t l = 0; l < pd.lines.size(); ++l) {
    const auto ids = pd.lines.cell(l);
    if (ids.front() == ids.back()) {
      ++closed;
      continue;
    }
    EXPECT_TRUE(on_border(pd.points[static_cast<std::size_t>(ids.front())]));
    EXPECT_TRUE(on_border(pd.points[static_cast<std::size_t>(ids.back())]));
  }
  EXPECT_GT(closed, 0u);
}

// ---- The plane fast path of structured grids ----

namespace {

/// bent_grid with a cell array (the cell index), so that copied cell data is compared too.
StructuredGrid bent_grid_with_cells(Index n) {
  StructuredGrid sg = bent_grid(n);
  DataArray cell("cell", ScalarType::Int32, 1, sg.num_cells());
  for (std::size_t c = 0; c < sg.num_cells(); ++c) cell.set(c, 0, static_cast<double>(c));
  sg.cell_data.add(std::move(cell));
  return sg;
}

}  // namespace

// The fast path (one pass over the points, only the rows of cells the plane crosses) gives
// exactly the general path's output: the same grid as an unstructured grid of hexahedra takes
// the general path. Planes in several directions, polygons and triangles, a value off 0.
TEST(Cut, StructuredPlaneFastPathMatchesTheGeneralPath) {
  const StructuredGrid sg = bent_grid_with_cells(17);
  const UnstructuredGrid ug = to_unstructured(sg);
  const std::vector<std::pair<Vec3, Vec3>> planes = {
      {{0.01, 0.02, 0.03}, {-0.287, 0, 0.9579}},
      {{0.1, -0.2, 0.05}, {1, 0, 0}},     // across the lines along i
      {{0, 0.3, -0.1}, {0, 1, 0.001}},    // nearly parallel to the lines along i
      {{0.2, 0.1, 0}, {0.5, -0.6, 0.62}}};
  for (std::size_t pi = 0; pi < planes.size(); ++pi) {
    const ImplicitFunction f = ImplicitFunction::plane(planes[pi].first, planes[pi].second);
    for (const bool tri : {false, true}) {
      CutOptions o = values_opt({pi == 3 ? 0.13 : 0.0});
      o.triangulate = tri;
      const auto [fast, fs] = cut(sg, f, o);
      const auto [slow, ss] = cut(ug, f, o);
      EXPECT_TRUE(fs.fast_path);
      EXPECT_GT(fast.polys.size(), 10u);
      EXPECT_TRUE(fast == slow) << "plane " << pi << (tri ? ", triangles" : "");
      EXPECT_EQ(fs.points, ss.points);
      EXPECT_EQ(fs.polygons, ss.polygons);
      EXPECT_EQ(fs.cells_cut, ss.cells_cut);
    }
  }
}

// A plane through grid points (F = c exactly there) is left to the general path, which merges
// the cut points at those grid points; the output still equals the unstructured grid's.
TEST(Cut, StructuredPlaneThroughGridPointsTakesTheGeneralPath) {
  StructuredGrid sg;
  sg.dims = {5, 4, 3};
  for (Index k = 0; k < 3; ++k)
    for (Index j = 0; j < 4; ++j)
      for (Index i = 0; i < 5; ++i) {
        sg.points.push_back({0.5 * static_cast<double>(i) + 0.125 * static_cast<double>(j),
                             0.5 * static_cast<double>(j), 0.5 * static_cast<double>(k)});
      }
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0.5}, {0, 0, 1});  // the layer k = 1
  const auto [a, as] = cut(sg, f);
  const auto [b, bs] = cut(to_unstructured(sg), f);
  EXPECT_TRUE(a == b);
  EXPECT_EQ(a.points.size(), 20u);  // the layer's 5 × 4 points, one each
  EXPECT_EQ(a.polys.size(), 12u);   // its 4 × 3 quads, once each
}

TEST(Cut, StructuredPlaneFastPathIsDeterministicForAnyThreadCount) {
  const StructuredGrid sg = bent_grid_with_cells(60);
  const ImplicitFunction f = ImplicitFunction::plane({0.01, 0.02, 0.03}, {-0.287, 0.1, 0.9579});
  PolyData one, two;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    one = cut(sg, f).output;
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    two = cut(sg, f).output;
  }
  EXPECT_GT(one.polys.size(), 1000u);
  EXPECT_TRUE(one == two);
}
