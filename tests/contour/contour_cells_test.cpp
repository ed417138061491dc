// Marching cells on structured grids and unstructured grids of every linear cell type.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "support/result.hpp"
#include "support/surface_checks.hpp"
#include "contour/tables.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/io/io.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::cube_grid;
using isoforge::test::expect_closed_manifold;
using isoforge::test::signed_volume;

namespace {

std::size_t sz(Index i) {
  return static_cast<std::size_t>(i);
}



double triple(const Vec3& a, const Vec3& b, const Vec3& c) {
  return dot(a, cross(b, c));
}

// A cube mesh builder: (n+1)^3 lattice points of the box [-1, 1]^3 (optionally warped), cube
// centres added on demand, cells of several decompositions. Every cell is made valid in VTK's
// sense (positive tetra/hexahedron/pyramid, wedge base facing away from its top).
class CubeMesh {
 public:
  enum Kind { Hex, Pyramids, Wedges, Tets6, Tets12 };

  explicit CubeMesh(Index n, std::function<Vec3(Vec3)> warp = {}) : n_(n) {
    for (Index k = 0; k <= n; ++k)
      for (Index j = 0; j <= n; ++j)
        for (Index i = 0; i <= n; ++i) {
          Vec3 p{-1 + 2.0 * static_cast<double>(i) / static_cast<double>(n),
                 -1 + 2.0 * static_cast<double>(j) / static_cast<double>(n),
                 -1 + 2.0 * static_cast<double>(k) / static_cast<double>(n)};
          if (warp) p = warp(p);
          grid_.points.push_back(p);
        }
  }
  Index id(Index i, Index j, Index k) const { return i + (n_ + 1) * (j + (n_ + 1) * k); }
  Vec3 pt(Index id) const { return grid_.points[sz(id)]; }

  // Adds cube (i, j, k) as `kind`; for Pyramids, faces whose bit is set in `split` (bits:
  // -x +x -y +y -z +z) become two tetrahedra split along the diagonal through the face's
  // lowest-numbered corner (the same rule everywhere, so split faces match).
  void add_cube(Index i, Index j, Index k, Kind kind, unsigned split = 0) {
    Index c[8];  // voxel order
    for (int q = 0; q < 8; ++q) c[q] = id(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
    switch (kind) {
      case Hex:
        add(CellType::Hexahedron, {c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]});
        break;
      case Tets6: {
        const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        for (const auto& a : axes) {
          const int b0 = 1 << a[0], b1 = b0 | 1 << a[1];
          add_tet(c[0], c[b0], c[b1], c[7]);
        }
        break;
      }
      case Wedges: {
        // Prisms along x over the triangles (j,k) (j+1,k) (j+1,k+1) and (j,k) (j+1,k+1) (j,k+1).
        add_wedge({c[0], c[2], c[6]}, {c[1], c[3], c[7]});
        add_wedge({c[0], c[6], c[4]}, {c[1], c[7], c[5]});
        break;
      }
      case Pyramids:
      case Tets12: {
        const Vec3 centre = (pt(c[0]) + pt(c[7])) / 2.0;
        const auto apex = static_cast<Index>(grid_.points.size());
        grid_.points.push_back(centre);
        // Faces as corner cycles (voxel corners).
        const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                 {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
        for (int f = 0; f < 6; ++f) {
          Index q[4];
          for (int m = 0; m < 4; ++m) q[m] = c[faces[f][m]];
          if (kind == Tets12 || ((split >> f) & 1u)) {
            // Rotate so q[0] is the lowest id; the diagonal q0-q2 splits the face.
            while (q[0] != *std::min_element(q, q + 4)) std::rotate(q, q + 1, q + 4);
            add_tet(q[0], q[1], q[2], apex);
            add_tet(q[0], q[2], q[3], apex);
          } else {
            add_pyramid(q, apex);
          }
        }
        break;
      }
    }
  }

  UnstructuredGrid& grid() { return grid_; }

  // Point scalars "d" = distance to `centre` minus r.
  void sphere_field(const Vec3& centre, double r) {
    DataArray d("d", ScalarType::Float64, 1, grid_.points.size());
    for (std::size_t p = 0; p < grid_.points.size(); ++p)
      d.set(p, 0, norm(grid_.points[p] - centre) - r);
    grid_.point_data.add(std::move(d), AttributeRole::Scalars);
  }

  void add(CellType t, std::initializer_list<Index> ids) { grid_.add_cell(t, ids); }
  void add_tet(Index a, Index b, Index c, Index d) {
    if (triple(pt(b) - pt(a), pt(c) - pt(a), pt(d) - pt(a)) < 0) std::swap(b, c);
    add(CellType::Tetra, {a, b, c, d});
  }
  void add_wedge(std::array<Index, 3> base, std::array<Index, 3> top) {
    // VTK: the base's right-hand normal points away from the top.
    if (dot(cross(pt(base[1]) - pt(base[0]), pt(base[2]) - pt(base[0])), pt(top[0]) - pt(base[0])) >
        0) {
      std::swap(base[1], base[2]);
      std::swap(top[1], top[2]);
    }
    add(CellType::Wedge, {base[0], base[1], base[2], top[0], top[1], top[2]});
  }
  void add_pyramid(Index q[4], Index apex) {
    const Vec3 nrm = cross(pt(q[1]) - pt(q[0]), pt(q[2]) - pt(q[0]));
    if (dot(nrm, pt(apex) - pt(q[0])) < 0) std::swap(q[1], q[3]);
    add(CellType::Pyramid, {q[0], q[1], q[2], q[3], apex});
  }

 private:
  Index n_;
  UnstructuredGrid grid_;
};

CubeMesh uniform_mesh(Index n, CubeMesh::Kind kind, unsigned split = 0) {
  CubeMesh m(n);
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) m.add_cube(i, j, k, kind, split);
  return m;
}

// Hexahedra, pyramids, pyramids with tetrahedra on some faces, wedges and tetrahedra in slabs
// along x; neighbouring slabs agree on their shared faces (quads, or triangles split by the
// lowest-corner rule).
CubeMesh mixed_mesh() {
  // Slabs of cubes along x (16 cubes): x faces split into triangles (S) or kept as quads (Q).
  struct Slab {
    CubeMesh::Kind kind;
    unsigned split;
  };
  const Slab slabs[16] = {
      {CubeMesh::Hex, 0},      {CubeMesh::Hex, 0},      {CubeMesh::Pyramids, 0},
      {CubeMesh::Pyramids, 2}, {CubeMesh::Wedges, 0},   {CubeMesh::Wedges, 0},
      {CubeMesh::Tets12, 0},   {CubeMesh::Tets12, 0},   {CubeMesh::Tets6, 0},
      {CubeMesh::Tets6, 0},    {CubeMesh::Tets12, 0},   {CubeMesh::Tets12, 0},
      {CubeMesh::Pyramids, 1}, {CubeMesh::Pyramids, 0}, {CubeMesh::Hex, 0},
      {CubeMesh::Hex, 0},
  };
  const Index n = 16;
  CubeMesh m(n);
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) m.add_cube(i, j, k, slabs[i].kind, slabs[i].split);
  return m;
}

StructuredGrid structured_box(Dims dims, const std::function<Vec3(Index, Index, Index)>& point) {
  StructuredGrid g;
  g.dims = dims;
  for (Index k = 0; k < dims[2]; ++k)
    for (Index j = 0; j < dims[1]; ++j)
      for (Index i = 0; i < dims[0]; ++i) g.points.push_back(point(i, j, k));
  return g;
}

void add_sphere_field(StructuredGrid& g, const Vec3& c, double r) {
  DataArray d("d", ScalarType::Float32, 1, g.points.size());
  for (std::size_t p = 0; p < g.points.size(); ++p) d.set(p, 0, norm(g.points[p] - c) - r);
  g.point_data.add(std::move(d), AttributeRole::Scalars);
}

const Vec3 kCentre{0.031, -0.047, 0.023};
const double kRadius = 0.62;
const double kSphereVolume = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;

void expect_sphere(const PolyData& pd, const std::string& what, double tolerance) {
  expect_closed_manifold(pd, what);
  const SurfaceTopology t = analyze_topology(pd);
  ASSERT_EQ(t.components.size(), 1u) << what;
  EXPECT_EQ(t.components[0].genus, 0) << what;
  // Distance fields increase outward: outward normals, positive volume.
  EXPECT_NEAR(signed_volume(pd) / kSphereVolume, 1.0, tolerance) << what;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Structured grids.

TEST(ContourStructured, WarpedGridGivesAClosedSphere) {
  const Index n = 26;
  auto warp = [n](Index i, Index j, Index k) {
    const double x = -1 + 2.0 * static_cast<double>(i) / (n - 1),
                 y = -1 + 2.0 * static_cast<double>(j) / (n - 1),
                 z = -1 + 2.0 * static_cast<double>(k) / (n - 1);
    return Vec3{x + 0.08 * std::sin(2 * y), y + 0.08 * std::sin(2 * z), z + 0.08 * std::sin(2 * x)};
  };
  StructuredGrid g = structured_box({n, n, n}, warp);
  add_sphere_field(g, kCentre, kRadius);
  ContourStats st;
  const PolyData pd = test::split_result(contour(g, {}), st);
  EXPECT_EQ(st.cells, pd.polys.size());
  EXPECT_EQ(st.points, pd.points.size());
  expect_sphere(pd, "warped", 0.02);
  // The same grid indexed left-handed (k reversed): the cells are mirrored, the surface is not.
  StructuredGrid mirrored =
      structured_box({n, n, n}, [&](Index i, Index j, Index k) { return warp(i, j, n - 1 - k); });
  add_sphere_field(mirrored, kCentre, kRadius);
  const PolyData pm = contour(mirrored, {}).output;
  expect_sphere(pm, "mirrored", 0.02);
  EXPECT_NEAR(signed_volume(pm), signed_volume(pd), 1e-3);
}

TEST(ContourStructured, AxisAlignedGridEqualsTheImage) {
  const Dims dims{19, 23, 17};
  ImageData img;
  img.dims = dims;
  img.origin = {-1, -1.2, -0.9};
  img.spacing = {0.11, 0.1, 0.12};
  StructuredGrid g =
      structured_box(dims, [&](Index i, Index j, Index k) { return img.point(i, j, k); });
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> noise(-0.02f, 0.02f);
  std::vector<float> v(img.num_points());
  for (std::size_t p = 0; p < v.size(); ++p) {
    const Vec3 x = img.point(static_cast<Index>(p));
    v[p] = static_cast<float>(std::sin(3 * x.x) * std::cos(2 * x.y) + x.z * x.z) + noise(rng);
  }
  img.point_data.add(DataArray::from_vector<float>("v", 1, v), AttributeRole::Scalars);
  g.point_data = img.point_data;
  DataArray cell("cell", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t c = 0; c < img.num_cells(); ++c) cell.set(c, 0, static_cast<double>(c));
  img.cell_data.add(cell);
  g.cell_data.add(std::move(cell));
  ContourOptions o;
  o.values = {-0.3, 0.2, 0.6};
  ContourStats si, sg;
  const PolyData a = test::split_result(contour(img, o), si), b = test::split_result(contour(g, o), sg);
  ASSERT_GT(a.polys.size(), 1000u);
  EXPECT_GT(si.ambiguous_faces, 0u);
  EXPECT_EQ(si.points, sg.points);
  EXPECT_EQ(si.cells, sg.cells);
  EXPECT_EQ(si.ambiguous_faces, sg.ambiguous_faces);
  // Same numbering and triangles; points equal up to rounding of the interpolation.
  EXPECT_TRUE(a.polys == b.polys);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t p = 0; p < a.points.size(); ++p)
    ASSERT_LT(norm(a.points[p] - b.points[p]), 1e-5) << p;
  EXPECT_TRUE(a.cell_data == b.cell_data);
  EXPECT_TRUE(a.point_data.get("IsovalueIndex") == b.point_data.get("IsovalueIndex"));
}

TEST(ContourStructured, GradientNormalsAndDeterminism) {
  const Index n = 33;
  StructuredGrid g = structured_box({n, n + 4, n - 3}, [&](Index i, Index j, Index k) {
    const double x = -1 + 2.0 * static_cast<double>(i) / (n - 1),
                 y = -1 + 2.0 * static_cast<double>(j) / (n + 3),
                 z = -1 + 2.0 * static_cast<double>(k) / (n - 4);
    return Vec3{x + 0.1 * y * y, y, z - 0.1 * x};
  });
  add_sphere_field(g, kCentre, kRadius);
  ContourOptions o;
  o.values = {-0.1, 0.0, 0.1};
  o.normals = ContourNormals::Gradient;
  for (const bool flip : {false, true}) {
    o.flip = flip;
    PolyData one;
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      one = contour(g, o).output;
    }
    const PolyData many = contour(g, o).output;
    EXPECT_TRUE(one == many);
    const DataArray* nrm = many.point_data.normals();
    ASSERT_NE(nrm, nullptr);
    for (std::size_t i = 0; i < many.points.size(); ++i) {
      const Vec3 nn{nrm->get(i, 0), nrm->get(i, 1), nrm->get(i, 2)};
      const double radial = dot(nn, (many.points[i] - kCentre) / norm(many.points[i] - kCentre));
      ASSERT_GT(flip ? -radial : radial, 0.97) << i;
    }
    EXPECT_GT(flip ? -signed_volume(many) : signed_volume(many), 0);
  }
}

TEST(ContourStructured, SurfaceGridsGiveIsolinesAndCurvesGiveVertices) {
  // A half cylinder (quads of the grid's own points): a closed loop around a maximum of the
  // parameter-space field, all its points on the cylinder.
  const Index nu = 41, nv = 31;
  StructuredGrid g = structured_box({nu, 1, nv}, [&](Index i, Index, Index k) {
    const double th = std::numbers::pi * static_cast<double>(i) / (nu - 1);
    return Vec3{std::cos(th), std::sin(th), -1 + 2.0 * static_cast<double>(k) / (nv - 1)};
  });
  DataArray f("f", ScalarType::Float64, 1, g.points.size());
  for (Index k = 0; k < nv; ++k)
    for (Index i = 0; i < nu; ++i) {
      const double u = static_cast<double>(i) / (nu - 1) - 0.5,
                   v = static_cast<double>(k) / (nv - 1) - 0.5;
      f.set(sz(i + nu * k), 0, 0.3 - std::hypot(u, v));
    }
  g.point_data.add(std::move(f), AttributeRole::Scalars);
  ContourStats st;
  const PolyData pd = test::split_result(contour(g, {}), st);
  ASSERT_EQ(pd.lines.size(), 1u);
  auto ids = pd.lines.cell(0);
  EXPECT_EQ(ids.front(), ids.back());
  EXPECT_EQ(ids.size(), pd.points.size() + 1);
  EXPECT_EQ(st.cells, pd.points.size());
  for (std::size_t p = 0; p < pd.points.size(); ++p) {
    EXPECT_NEAR(std::hypot(pd.points[p].x, pd.points[p].y), 1.0, 2e-3);  // chords of the circle
  }
  // Orientation: seen from the side of the quads' normal (first axis x second: θ x z, outward
  // from the cylinder's axis) the maximum is on the left, so the loop turns about the normal.
  double turning = 0;
  for (std::size_t k = 1; k + 1 < ids.size(); ++k) {
    const Vec3 a = pd.points[sz(ids[k - 1])], b = pd.points[sz(ids[k])],
               c = pd.points[sz(ids[k + 1])];
    turning += dot(cross(b - a, c - b), Vec3{b.x, b.y, 0});
  }
  EXPECT_GT(turning, 0);
  // Planar and axis-aligned: identical to the image.
  ImageData img;
  img.dims = {nu, nv, 1};
  img.spacing = {0.1, 0.2, 1};
  StructuredGrid flat =
      structured_box(img.dims, [&](Index i, Index j, Index k) { return img.point(i, j, k); });
  img.point_data = g.point_data;
  flat.point_data = g.point_data;
  const PolyData pi = contour(img, {}).output, pf = contour(flat, {}).output;
  EXPECT_TRUE(pi.lines == pf.lines);
  ASSERT_EQ(pi.points.size(), pf.points.size());
  for (std::size_t p = 0; p < pi.points.size(); ++p)
    EXPECT_LT(norm(pi.points[p] - pf.points[p]), 1e-6);
  // A curve: one vertex per crossed segment.
  StructuredGrid curve = structured_box({1, 1, 9}, [](Index, Index, Index k) {
    return Vec3{std::cos(0.3 * static_cast<double>(k)), std::sin(0.3 * static_cast<double>(k)), 0};
  });
  curve.point_data.add(DataArray::from_vector<double>("s", 1, {0, 1, 2, 3, 2, 1, 0, 1, 2}),
                       AttributeRole::Scalars);
  ContourOptions o;
  o.values = {1.5};
  const PolyData pc = contour(curve, o).output;
  EXPECT_EQ(pc.verts.size(), 3u);
  EXPECT_EQ(pc.points.size(), 3u);
  const Vec3 expected = (curve.points[1] + curve.points[2]) / 2.0;
  EXPECT_LT(norm(pc.points[0] - expected), 1e-6);
}

// ------------------------------------------------------------------------------------------------
// Unstructured grids.

TEST(ContourUnstructured, SphereInEveryDecompositionIsClosedAndGenusZero) {
  const Index n = 14;
  struct Case {
    const char* name;
    CubeMesh mesh;
  };
  Case cases[] = {
      {"hexahedra", uniform_mesh(n, CubeMesh::Hex)},
      {"6 tetrahedra per cube", uniform_mesh(n, CubeMesh::Tets6)},
      {"12 tetrahedra per cube", uniform_mesh(n, CubeMesh::Tets12)},
      {"wedges", uniform_mesh(n, CubeMesh::Wedges)},
      {"pyramids", uniform_mesh(n, CubeMesh::Pyramids)},
      {"pyramids and tetrahedra", uniform_mesh(n, CubeMesh::Pyramids, 0b110011)},
      {"mixed", mixed_mesh()},
  };
  for (Case& c : cases) {
    c.mesh.sphere_field(kCentre, kRadius);
    ContourStats st;
    const PolyData pd = test::split_result(contour(c.mesh.grid(), {}), st);
    EXPECT_EQ(st.cells, pd.polys.size()) << c.name;
    EXPECT_TRUE(pd.lines.empty() && pd.verts.empty()) << c.name;
    expect_sphere(pd, c.name, 0.05);  // chords of the sphere at about six cells per radius
  }
}

TEST(ContourUnstructured, EveryCaseOfEveryCellTypeClosesWhenEnclosed) {
  // One cell in the middle of a 3x3x3-cube mesh takes every above/below pattern of its corners
  // (random magnitudes, so both resolutions of its ambiguous faces occur); all other points are
  // below, so the surface must close around the above corners, oriented inward (toward the
  // increasing values), through the neighbouring cells of the same type.
  struct Case {
    const char* name;
    CubeMesh::Kind kind;
    unsigned split;
  };
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> mag(0.05, 1.0);
  for (const Case& c :
       {Case{"hexahedron", CubeMesh::Hex, 0}, Case{"tetra", CubeMesh::Tets6, 0},
        Case{"wedge", CubeMesh::Wedges, 0}, Case{"pyramid", CubeMesh::Pyramids, 0}}) {
    CubeMesh m = uniform_mesh(3, c.kind, c.split);
    UnstructuredGrid& g = m.grid();
    // The first cell of the middle cube.
    const std::size_t cell = 13 * (g.types.size() / 27);
    auto ids = g.cells.cell(cell);
    const std::size_t corners = ids.size();
    std::size_t ambiguous = 0;
    for (unsigned bits = 0; bits < (1u << corners); ++bits) {
      for (int trial = 0; trial < 8; ++trial) {
        std::vector<double> v(g.points.size(), -1.0);
        for (std::size_t k = 0; k < corners; ++k)
          v[sz(ids[k])] = ((bits >> k) & 1) ? mag(rng) : -mag(rng);
        g.point_data.add(DataArray::from_vector<double>("s", 1, v), AttributeRole::Scalars);
        ContourStats st;
        const PolyData pd = test::split_result(contour(g, {}), st);
        ambiguous += st.ambiguous_faces;
        const std::string what = std::string(c.name) + " case " + std::to_string(bits);
        if (bits == 0) {
          EXPECT_EQ(pd.polys.size(), 0u) << what;
          continue;
        }
        expect_closed_manifold(pd, what);
        EXPECT_LT(signed_volume(pd), 0) << what;
      }
    }
    if (c.kind != CubeMesh::Tets6) {
      EXPECT_GT(ambiguous, 0u) << c.name;
    }
  }
}

TEST(ContourUnstructured, MirroredCellsKeepTheOrientation) {
  // Hexahedra with top and bottom swapped (left-handed), wedges in the table's own handedness
  // (right-handed base, i.e. VTK-inverted): the surface is oriented the same.
  CubeMesh m = uniform_mesh(14, CubeMesh::Hex);
  m.sphere_field(kCentre, kRadius);
  UnstructuredGrid g = m.grid();
  const PolyData normal = contour(g, {}).output;
  for (std::size_t c = 0; c < g.types.size(); ++c) {
    auto ids = g.cells.cell(c);
    for (int q = 0; q < 4; ++q) std::swap(ids[sz(q)], ids[sz(q + 4)]);
  }
  const PolyData mirrored = contour(g, {}).output;
  expect_sphere(normal, "hex", 0.05);
  expect_sphere(mirrored, "mirrored hex", 0.05);
  // (the same loops, possibly triangulated differently)
  EXPECT_NEAR(signed_volume(mirrored), signed_volume(normal), 2e-3 * kSphereVolume);
  CubeMesh w = uniform_mesh(14, CubeMesh::Wedges);
  w.sphere_field(kCentre, kRadius);
  UnstructuredGrid gw = w.grid();
  for (std::size_t c = 0; c < gw.types.size(); ++c) {
    auto ids = gw.cells.cell(c);
    std::swap(ids[1], ids[2]);
    std::swap(ids[4], ids[5]);
  }
  expect_sphere(contour(gw, {}).output, "right-handed wedges", 0.05);
}

TEST(ContourUnstructured, PostPressureIsManifoldWithBordersOnTheBoundary) {
  Dataset ds = read(std::string(ISOFORGE_DATA_DIR) + "/post.vtk");
  ASSERT_TRUE(std::holds_alternative<UnstructuredGrid>(ds));
  UnstructuredGrid& g = std::get<UnstructuredGrid>(ds);
  ASSERT_EQ(g.types.size(), 8750u);
  DataArray cell("cell", ScalarType::Int32, 1, g.types.size());
  for (std::size_t c = 0; c < g.types.size(); ++c) cell.set(c, 0, static_cast<double>(c));
  g.cell_data.add(std::move(cell));
  const DataArray& pressure = g.point_data.get("Pressure");
  // Boundary faces of the tetrahedral mesh, and the largest pressure jump along an edge.
  std::map<std::array<Index, 3>, int> faces;
  double max_jump = 0;
  for (std::size_t c = 0; c < g.types.size(); ++c) {
    ASSERT_EQ(g.types[c], CellType::Tetra);
    auto ids = g.cells.cell(c);
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Index, 3> f;
      int m = 0;
      for (int q = 0; q < 4; ++q)
        if (q != skip) f[sz(m++)] = ids[sz(q)];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        max_jump = std::max(max_jump,
                            std::abs(pressure.get(sz(ids[sz(a)])) - pressure.get(sz(ids[sz(b)]))));
  }
  ContourOptions o;
  o.array = "Pressure";
  o.values = {0.5, 0.8, 1.1, 1.4};
  ContourStats st;
  const PolyData pd = test::split_result(contour(g, o), st);
  ASSERT_GT(pd.polys.size(), 500u);
  const SurfaceTopology t = analyze_topology(pd);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.non_manifold_vertices, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_EQ(t.repeated_vertex_faces, 0u);
  EXPECT_EQ(t.vertices, pd.points.size());
  EXPECT_GT(t.border_edges, 0u);
  // Each output point is the crossing of one mesh edge: find it by its exact position (post.vtk
  // has 88 pairs of coincident points along a seam, so a position may belong to two edges).
  const DataArray& idx = pd.point_data.get("IsovalueIndex");
  std::map<std::pair<int, std::array<float, 3>>, std::set<std::pair<Index, Index>>> edge_of;
  for (std::size_t c = 0; c < g.types.size(); ++c) {
    auto ids = g.cells.cell(c);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const Index lo = std::min(ids[sz(a)], ids[sz(b)]), hi = std::max(ids[sz(a)], ids[sz(b)]);
        for (std::size_t v = 0; v < o.values.size(); ++v) {
          const double pa = pressure.get(sz(lo)), pb = pressure.get(sz(hi));
          if ((pa >= o.values[v]) == (pb >= o.values[v])) continue;
          const double tt = contour_detail::crossing(pa, pb, o.values[v]);
          const Vec3 x = g.points[sz(lo)] + (g.points[sz(hi)] - g.points[sz(lo)]) * tt;
          edge_of[{static_cast<int>(v),
                   {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)}}]
              .insert({lo, hi});
        }
      }
  }
  std::size_t crossed_edges = 0;
  for (const auto& [key, edges] : edge_of) crossed_edges += edges.size();
  EXPECT_EQ(crossed_edges, pd.points.size());  // one point per crossed edge, none missing
  std::map<std::pair<int, std::array<float, 3>>, std::size_t> points_at;
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    const Vec3 x = pd.points[i];
    ++points_at[{static_cast<int>(idx.get(i)),
                 {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)}}];
  }
  ASSERT_EQ(points_at.size(), edge_of.size());
  for (const auto& [key, n] : points_at) {
    ASSERT_TRUE(edge_of.count(key));
    EXPECT_EQ(edge_of[key].size(), n);
  }
  auto mesh_edges = [&](Index p) {
    const Vec3 x = pd.points[sz(p)];
    return edge_of[{static_cast<int>(idx.get(sz(p))),
                    {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)}}];
  };
  // Border edges of the contour lie in boundary faces of the mesh.
  std::map<std::pair<Index, Index>, int> uses;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    auto ids = pd.polys.cell(c);
    for (int k = 0; k < 3; ++k)
      ++uses[{std::min(ids[sz(k)], ids[sz((k + 1) % 3)]),
              std::max(ids[sz(k)], ids[sz((k + 1) % 3)])}];
  }
  std::size_t border = 0;
  for (const auto& [e, n] : uses) {
    if (n != 1) continue;
    ++border;
    bool on_boundary = false;
    for (const auto& a : mesh_edges(e.first))
      for (const auto& b : mesh_edges(e.second)) {
        std::set<Index> corners{a.first, a.second, b.first, b.second};
        if (corners.size() != 3) continue;
        const std::array<Index, 3> f{*corners.begin(), *std::next(corners.begin()),
                                     *corners.rbegin()};
        on_boundary = on_boundary || (faces.count(f) && faces[f] == 1);
      }
    EXPECT_TRUE(on_boundary) << "border edge inside the mesh";
  }
  EXPECT_EQ(border, t.border_edges);
  // Pressure interpolated (to the isovalue, within the 1/1024 clamp); triangles inside their tet.
  const DataArray& p = pd.point_data.get("Pressure");
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    EXPECT_NEAR(p.get(i), o.values[sz(static_cast<Index>(idx.get(i)))], max_jump / 1024 + 1e-6);
  }
  const DataArray& cells = pd.cell_data.get("cell");
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    auto ids = pd.polys.cell(c);
    const Vec3 x = (pd.points[sz(ids[0])] + pd.points[sz(ids[1])] + pd.points[sz(ids[2])]) / 3.0;
    auto tet = g.cells.cell(sz(static_cast<Index>(cells.get(c))));
    const Vec3 a = g.points[sz(tet[0])], b = g.points[sz(tet[1])], cc = g.points[sz(tet[2])],
               d = g.points[sz(tet[3])];
    const double vol = triple(b - a, cc - a, d - a);
    const double w[4] = {triple(b - x, cc - x, d - x) / vol, triple(x - a, cc - a, d - a) / vol,
                         triple(b - a, x - a, d - a) / vol, triple(b - a, cc - a, x - a) / vol};
    for (double wi : w) ASSERT_GT(wi, -1e-4) << "triangle " << c;
  }
}

// Adds the boundary faces of a mesh of 3D cells as 2D cells (triangles, quads), outward.
std::size_t add_boundary_faces(UnstructuredGrid& g) {
  std::map<std::vector<Index>, std::pair<std::vector<Index>, int>> faces;
  const std::size_t cells = g.types.size();
  for (std::size_t c = 0; c < cells; ++c) {
    auto ids = g.cells.cell(c);
    std::vector<std::vector<int>> local;
    switch (g.types[c]) {
      case CellType::Tetra:
        local = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 2, 1}};
        break;
      case CellType::Hexahedron:
        local = {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4},
                 {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};
        break;
      case CellType::Wedge:
        local = {{0, 1, 2}, {3, 5, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}};
        break;
      case CellType::Pyramid:
        local = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
        break;
      default:
        ADD_FAILURE();
    }
    Vec3 centre{0, 0, 0};
    for (Index id : ids) centre += g.points[sz(id)] / static_cast<double>(ids.size());
    for (const auto& f : local) {
      std::vector<Index> face;
      Vec3 fc{0, 0, 0}, nrm{0, 0, 0};
      for (int q : f) face.push_back(ids[sz(q)]);
      for (std::size_t q = 0; q < face.size(); ++q) {
        fc += g.points[sz(face[q])] / static_cast<double>(face.size());
        nrm += cross(g.points[sz(face[q])], g.points[sz(face[(q + 1) % face.size()])]);
      }
      if (dot(nrm, fc - centre) < 0) std::reverse(face.begin(), face.end());
      std::vector<Index> key = face;
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      e.first = face;
      ++e.second;
    }
  }
  std::size_t added = 0;
  for (const auto& [key, e] : faces) {
    if (e.second != 1) continue;
    g.add_cell(e.first.size() == 3 ? CellType::Triangle : CellType::Quad, e.first);
    ++added;
  }
  return added;
}

TEST(ContourUnstructured, BoundaryPolygonsGiveTheSurfaceBorderAsPolylines) {
  // 3D cells plus their boundary faces (outward) as 2D cells, cut by a noisy sphere that leaves
  // the box: the isolines on the boundary faces are exactly the border of the surface, with the
  // same points and the same direction (quads decide their saddles like the 3D cells' faces).
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> noise(-0.4, 0.4);
  for (const auto kind : {CubeMesh::Tets6, CubeMesh::Hex, CubeMesh::Wedges, CubeMesh::Pyramids}) {
    const std::string what = "kind " + std::to_string(static_cast<int>(kind));
    CubeMesh m = uniform_mesh(8, kind);
    UnstructuredGrid& g = m.grid();
    const std::size_t solids = g.types.size();
    const std::size_t boundary = add_boundary_faces(g);
    // 6 x 64 squares; split in two on all faces (tetrahedra) or on the x faces (wedges).
    const std::size_t expected = kind == CubeMesh::Tets6    ? 768u
                                 : kind == CubeMesh::Wedges ? 512u
                                                            : 384u;
    ASSERT_EQ(boundary, expected) << what;
    DataArray d("d", ScalarType::Float64, 1, g.points.size());
    for (std::size_t p = 0; p < g.points.size(); ++p)
      d.set(p, 0, norm(g.points[p] - Vec3{0.7, 0.1, -0.2}) - 0.6 + noise(rng));
    g.point_data.add(std::move(d), AttributeRole::Scalars);
    ContourOptions o;
    o.values = {0.0, 0.15};
    ContourStats st;
    const PolyData pd = test::split_result(contour(g, o), st);
    ASSERT_GT(pd.polys.size(), 0u) << what;
    ASSERT_GT(pd.lines.size(), 0u) << what;
    const SurfaceTopology t = analyze_topology(pd);
    EXPECT_EQ(t.non_manifold_edges, 0u) << what;
    EXPECT_EQ(t.inconsistent_edges, 0u) << what;
    std::set<std::pair<Index, Index>> border, segs;
    std::map<std::pair<Index, Index>, int> uses;
    for (std::size_t c = 0; c < pd.polys.size(); ++c) {
      auto ids = pd.polys.cell(c);
      for (int k = 0; k < 3; ++k)
        ++uses[{std::min(ids[sz(k)], ids[sz((k + 1) % 3)]),
                std::max(ids[sz(k)], ids[sz((k + 1) % 3)])}];
    }
    for (std::size_t c = 0; c < pd.polys.size(); ++c) {
      auto ids = pd.polys.cell(c);
      for (int k = 0; k < 3; ++k) {
        const Index a = ids[sz(k)], b = ids[sz((k + 1) % 3)];
        if (uses[{std::min(a, b), std::max(a, b)}] == 1) border.insert({a, b});
      }
    }
    for (std::size_t l = 0; l < pd.lines.size(); ++l) {
      auto ids = pd.lines.cell(l);
      EXPECT_EQ(ids.front(), ids.back()) << what;  // isolines on the closed box surface close
      for (std::size_t k = 0; k + 1 < ids.size(); ++k) segs.insert({ids[k], ids[k + 1]});
    }
    EXPECT_EQ(border, segs) << what;
    EXPECT_EQ(st.cells, pd.polys.size() + segs.size()) << what;
    if (kind == CubeMesh::Hex) {
      EXPECT_GT(st.ambiguous_faces, 0u);
    }
    // Cell data: triangles carry their 3D cell, polylines their boundary face (so each segment
    // is its own polyline when every cell differs).
    DataArray cell("cell", ScalarType::Int64, 1, g.types.size());
    for (std::size_t c = 0; c < g.types.size(); ++c) cell.set(c, 0, static_cast<double>(c));
    g.cell_data.add(std::move(cell));
    const PolyData withcd = contour(g, o).output;
    EXPECT_EQ(withcd.lines.size(), segs.size()) << what;
    const DataArray& cd = withcd.cell_data.get("cell");
    for (std::size_t c = 0; c < withcd.lines.size(); ++c)
      EXPECT_GE(cd.get(c), static_cast<double>(solids));
    for (std::size_t c = 0; c < withcd.polys.size(); ++c)
      EXPECT_LT(cd.get(withcd.lines.size() + c), static_cast<double>(solids));
  }
}

TEST(ContourUnstructured, NormalsAndFlip) {
  CubeMesh m = mixed_mesh();
  m.sphere_field(kCentre, kRadius);
  for (const auto mode : {ContourNormals::Gradient, ContourNormals::Triangles}) {
    for (const bool flip : {false, true}) {
      ContourOptions o;
      o.normals = mode;
      o.flip = flip;
      const PolyData pd = contour(m.grid(), o).output;
      const DataArray* nrm = pd.point_data.normals();
      ASSERT_NE(nrm, nullptr);
      for (std::size_t i = 0; i < pd.points.size(); ++i) {
        const Vec3 nn{nrm->get(i, 0), nrm->get(i, 1), nrm->get(i, 2)};
        EXPECT_NEAR(norm(nn), 1.0, 1e-5);
        const double radial = dot(nn, (pd.points[i] - kCentre) / norm(pd.points[i] - kCentre));
        EXPECT_GT(flip ? -radial : radial, 0.9);
      }
      EXPECT_GT(flip ? -signed_volume(pd) : signed_volume(pd), 0);
    }
  }
}

TEST(ContourUnstructured, LinesAndVerticesOfAGrid) {
  // 1D cells give one vertex per crossed segment (shared points for shared segments); vertex
  // cells give nothing.
  UnstructuredGrid g;
  for (int i = 0; i < 6; ++i) g.points.push_back({static_cast<double>(i), 0, 0});
  g.add_cell(CellType::PolyLine, {0, 1, 2, 3, 4, 5});
  g.add_cell(CellType::Line, {2, 3});
  g.add_cell(CellType::Vertex, {3});
  g.add_cell(CellType::PolyVertex, {0, 3, 5});
  g.point_data.add(DataArray::from_vector<float>("s", 1, {0, 1, 2, 3, 2, 1}),
                   AttributeRole::Scalars);
  g.cell_data.add(DataArray::from_vector<std::int32_t>("c", 1, {10, 11, 12, 13}));
  ContourOptions o;
  o.values = {2.5};
  ContourStats st;
  const PolyData pd = test::split_result(contour(g, o), st);
  ASSERT_EQ(pd.verts.size(), 3u);  // segments 2-3 and 3-4 of the polyline, 2-3 of the line
  ASSERT_EQ(pd.points.size(), 2u);
  EXPECT_EQ(st.cells, 3u);
  EXPECT_EQ(pd.verts.cell(0)[0], 0);
  EXPECT_EQ(pd.verts.cell(1)[0], 1);
  EXPECT_EQ(pd.verts.cell(2)[0], 0);
  EXPECT_DOUBLE_EQ(pd.points[0].x, 2.5);
  EXPECT_DOUBLE_EQ(pd.points[1].x, 3.5);
  const DataArray& c = pd.cell_data.get("c");
  EXPECT_EQ(c.get(0), 10);
  EXPECT_EQ(c.get(1), 10);
  EXPECT_EQ(c.get(2), 11);
}

TEST(ContourUnstructured, BadInputIsAClearError) {
  CubeMesh m = uniform_mesh(2, CubeMesh::Tets6);
  UnstructuredGrid g = m.grid();
  auto expect_error = [](const Dataset& ds, const ContourOptions& o, const std::string& text) {
    test::expect_error([&] { (void)contour(ds, o); }, text);
  };
  ContourOptions o;
  expect_error(g, o, "no active point scalars");
  m.sphere_field(kCentre, 0.5);
  g = m.grid();
  o.values = {};
  expect_error(g, o, "no isovalues");
  o.values = {std::numeric_limits<double>::infinity()};
  expect_error(g, o, "not finite");
  o.values = {0};
  o.array = "Pressure";
  expect_error(g, o, "'Pressure'");
  g.point_data.add(DataArray("vec", ScalarType::Float64, 3, g.points.size()));
  o.array = "vec";
  expect_error(g, o, "3 components");
  o.array = "";
  g.cells.connectivity()[5] = 1000;  // out of range
  EXPECT_THROW((void)contour(g, o), Error);
  StructuredGrid s;
  s.dims = {3, 3, 3};
  s.points = Points(26);
  s.point_data.add(DataArray("d", ScalarType::Float32, 1, 26), AttributeRole::Scalars);
  EXPECT_THROW((void)contour(s, o), Error);
  s.points = Points(27);
  s.point_data.add(DataArray("d", ScalarType::Float32, 1, 27), AttributeRole::Scalars);
  o.array = "nothing";
  expect_error(s, o, "'nothing'");
}

TEST(ContourUnstructured, DeterministicForAnyThreadCount) {
  CubeMesh m = mixed_mesh();
  UnstructuredGrid& g = m.grid();
  add_boundary_faces(g);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  DataArray d("d", ScalarType::Float64, 1, g.points.size());
  for (std::size_t p = 0; p < g.points.size(); ++p)
    d.set(p, 0, norm(g.points[p] - Vec3{0.5, 0.1, 0}) - 0.7 + noise(rng));
  g.point_data.add(std::move(d), AttributeRole::Scalars);
  DataArray cell("cell", ScalarType::Int32, 1, g.types.size());
  for (std::size_t c = 0; c < g.types.size(); ++c) cell.set(c, 0, static_cast<double>(c % 7));
  g.cell_data.add(std::move(cell));
  ContourOptions o;
  o.values = {-0.1, 0.0, 0.1};
  o.normals = ContourNormals::Gradient;
  PolyData one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = contour(g, o).output;
  }
  const PolyData many = contour(g, o).output;
  EXPECT_GT(many.lines.size(), 0u);
  EXPECT_GT(many.polys.size(), 0u);
  EXPECT_TRUE(one == many);
}
