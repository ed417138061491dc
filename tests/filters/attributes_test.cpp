// Attribute transformations: elevation, warping, the displacement plot's scalar and gradients.

#include <gtest/gtest.h>

#include <cmath>

#include "isoforge/filters/elevation.hpp"
#include "isoforge/filters/gradient.hpp"
#include "isoforge/filters/warp.hpp"
#include "support/expect_error.hpp"
#include "support/sample_datasets.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

// A point field f(p) evaluated at every point of `ds`, added as Float64 array `name`.
template <class F>
void add_field(Dataset& ds, const std::string& name, int components, F f,
               AttributeRole role = AttributeRole::Scalars) {
  const std::size_t n = num_points(ds);
  DataArray a(name, ScalarType::Float64, components, n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = f(point(ds, Index(i)));
    for (int c = 0; c < components; ++c) a.set(i, c, v[std::size_t(c)]);
  }
  point_data(ds).add(std::move(a), role);
}

ImageData image(Dims dims, Vec3 origin, Vec3 spacing) {
  ImageData img;
  img.dims = dims;
  img.origin = origin;
  img.spacing = spacing;
  return img;
}

// A curved 6 x 5 x 4 structured grid (no two cells alike).
StructuredGrid curved_grid() {
  StructuredGrid g;
  g.dims = {6, 5, 4};
  for (Index k = 0; k < 4; ++k)
    for (Index j = 0; j < 5; ++j)
      for (Index i = 0; i < 6; ++i) {
        const double x = i, y = j, z = k;
        g.points.push_back({x + 0.2 * std::sin(y + z), y + 0.15 * x * x / 6 + 0.1 * z,
                            z * (1 + 0.05 * x) + 0.1 * std::cos(x * y)});
      }
  return g;
}

// The 3D cells of sample_unstructured (hexahedron, pyramid, tetrahedron, wedge).
UnstructuredGrid solid_cells() {
  const UnstructuredGrid all = test::sample_unstructured();
  UnstructuredGrid ug;
  ug.points = all.points;
  for (std::size_t c = 0; c < 4; ++c) ug.add_cell(all.types[c], all.cells.cell(c));
  return ug;
}

constexpr std::array<double, 3> kSlope = {2, -3, 0.5};
std::array<double, 1> linear(const Vec3& p) {
  return {kSlope[0] * p.x + kSlope[1] * p.y + kSlope[2] * p.z + 1};
}

void expect_gradient(const DataArray& g, std::size_t i, std::array<double, 3> want, double tol) {
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(g.get(i, a), want[std::size_t(a)], tol) << "point " << i;
}

}  // namespace

TEST(Elevation, ProjectsOntoTheSegmentAndClamps) {
  Dataset img = image({2, 2, 5}, {0, 0, -1}, {1, 1, 1});  // z = -1 .. 3
  ElevationOptions o;
  o.low_point = {0, 0, 0};
  o.high_point = {0, 0, 2};
  o.range = {10, 20};
  const DataArray e = elevation(img, o);
  ASSERT_EQ(e.tuples(), 20u);
  EXPECT_EQ(e.name(), "Elevation");
  const double want[5] = {10, 10, 15, 20, 20};  // z = -1, 0, 1, 2, 3, clamped
  for (std::size_t i = 0; i < 20; ++i) EXPECT_FLOAT_EQ(e.get(i), want[i / 4]) << i;
  o.clamp = false;
  o.name = "h";
  const DataArray u = elevation(img, o);
  EXPECT_FLOAT_EQ(u.get(0), 5);    // z = -1
  EXPECT_FLOAT_EQ(u.get(19), 25);  // z = 3
  // Any direction: the projection of the sample polydata on (1, 1, 0) from the origin.
  const PolyData pd = test::sample_poly();
  ElevationOptions d;
  d.high_point = {1, 1, 0};
  const DataArray pe = elevation(pd, d);
  for (std::size_t i = 0; i < pd.num_points(); ++i) {
    const Vec3 p = pd.points[i];
    EXPECT_FLOAT_EQ(pe.get(i), std::clamp((p.x + p.y) / 2, 0.0, 1.0));
  }
}

TEST(Elevation, BadOptionsAreErrors) {
  const ImageData img = image({2, 2, 2}, {0, 0, 0}, {1, 1, 1});
  ElevationOptions o;
  o.high_point = o.low_point;
  expect_error([&] { (void)elevation(img, o); }, "must differ");
  o = {};
  o.range = {0, NAN};
  expect_error([&] { (void)elevation(img, o); }, "range must be finite");
  o = {};
  o.low_point = {INFINITY, 0, 0};
  expect_error([&] { (void)elevation(img, o); }, "must be finite");
  o = {};
  o.name.clear();
  expect_error([&] { (void)elevation(img, o); }, "needs a name");
}

TEST(WarpVector, ImageBecomesAStructuredGridWithItsDataCarried) {
  Dataset img = image({3, 2, 2}, {1, 0, 0}, {0.5, 1, 2});
  add_field(img, "v", 3, [](const Vec3& p) { return std::array<double, 3>{p.y, -p.x, 1}; },
            AttributeRole::Vectors);
  add_field(img, "s", 1, [](const Vec3& p) { return std::array<double, 1>{p.z}; });
  cell_data(img).add(DataArray::from_vector<std::int32_t>("c", 1, {4, 5}));
  WarpVectorOptions o;
  o.scale = 2;
  const Dataset out = warp_by_vector(img, o);
  const auto* g = std::get_if<StructuredGrid>(&out);
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->dims, (Dims{3, 2, 2}));
  ASSERT_EQ(g->num_points(), 12u);
  for (std::size_t i = 0; i < 12; ++i) {
    const Vec3 p = point(img, Index(i));
    const Vec3 want = p + Vec3{p.y, -p.x, 1} * 2;
    EXPECT_NEAR(norm(g->points[i] - want), 0, 1e-6) << i;
  }
  EXPECT_EQ(g->point_data, point_data(img));
  EXPECT_EQ(g->cell_data.get("c").get(1), 5);
  EXPECT_EQ(g->point_data.vectors()->name(), "v");
}

TEST(WarpVector, PolyDataKeepsItsCellsAndFloat64Points) {
  UnstructuredGrid ug = test::sample_unstructured();  // Float64 points
  Dataset ds = ug;
  add_field(ds, "d", 3, [](const Vec3& p) { return std::array<double, 3>{0, 0, p.x / 3}; });
  WarpVectorOptions o;
  o.vectors = "d";
  o.scale = -1;
  const Dataset out = warp_by_vector(ds, o);
  const auto& w = std::get<UnstructuredGrid>(out);
  EXPECT_EQ(w.points.type(), ScalarType::Float64);
  EXPECT_EQ(w.types, ug.types);
  EXPECT_EQ(w.cells, ug.cells);
  for (std::size_t i = 0; i < w.num_points(); ++i) {
    EXPECT_EQ(w.points[i], (ug.points[i] - Vec3{0, 0, ug.points[i].x / 3}));
  }
  const PolyData pd = test::sample_poly();
  Dataset pds = pd;
  add_field(pds, "v", 3, [](const Vec3&) { return std::array<double, 3>{1, 2, 3}; });
  o.vectors = "v";
  o.scale = 0.5;
  const PolyData wp = std::get<PolyData>(warp_by_vector(pds, o));
  EXPECT_EQ(wp.polys, pd.polys);
  EXPECT_EQ(wp.lines, pd.lines);
  EXPECT_EQ(wp.verts, pd.verts);
  EXPECT_EQ(wp.field_data, pd.field_data);
  EXPECT_EQ(wp.points[4], (Vec3{1, 1.5, 2.5}));
}

TEST(WarpVector, MissingOrWrongArraysAreErrorsNamingThem) {
  const PolyData pd = test::sample_poly();
  expect_error([&] { (void)warp_by_vector(pd); }, "no active point vectors; name one (point arrays: 'Normals', 'point_ids')");
  WarpVectorOptions o;
  o.vectors = "nope";
  expect_error([&] { (void)warp_by_vector(pd, o); }, "no point array 'nope'");
  o.vectors = "point_ids";
  expect_error([&] { (void)warp_by_vector(pd, o); }, "'point_ids' has 1 component, 3 needed");
  o.vectors = "Normals";
  o.scale = NAN;
  expect_error([&] { (void)warp_by_vector(pd, o); }, "scale factor must be finite");
}

TEST(WarpScalar, AlongADirectionOrTheNormals) {
  Dataset img = image({4, 3, 1}, {0, 0, 0}, {1, 1, 1});  // a flat 2D image
  add_field(img, "h", 1, [](const Vec3& p) { return std::array<double, 1>{p.x * p.y}; });
  WarpScalarOptions o;
  o.direction = Vec3{0, 0, 4};  // normalised to (0, 0, 1)
  o.scale = 0.5;
  const StructuredGrid g = std::get<StructuredGrid>(warp_by_scalar(img, o));
  for (std::size_t i = 0; i < 12; ++i) {
    const Vec3 p = point(img, Index(i));
    EXPECT_EQ(g.points[i], (Vec3{p.x, p.y, 0.5 * p.x * p.y}));
  }
  // Along the point normals of the pyramid: every point moves by s along its unit normal.
  PolyData pd = test::sample_poly();
  Dataset pds = pd;
  add_field(pds, "s", 1, [](const Vec3& p) { return std::array<double, 1>{1 + p.z}; });
  WarpScalarOptions n;
  n.scalars = "s";
  const PolyData w = std::get<PolyData>(warp_by_scalar(pds, n));
  const DataArray& normals = *pd.point_data.normals();
  for (std::size_t i = 0; i < 5; ++i) {
    const Vec3 nrm{normals.get(i, 0), normals.get(i, 1), normals.get(i, 2)};
    EXPECT_NEAR(norm(w.points[i] - (pd.points[i] + nrm * (1 + pd.points[i].z))), 0, 1e-6);
  }
  // Without normals and without a direction, or with a zero direction: errors.
  expect_error([&] { (void)warp_by_scalar(img); }, "no active point normals");
  o.direction = Vec3{0, 0, 0};
  expect_error([&] { (void)warp_by_scalar(img, o); }, "direction must be finite and not zero");
}

TEST(Displacement, IsTheDotProductOfVectorAndNormal) {
  PolyData pd = test::sample_poly();
  Dataset ds = pd;
  add_field(ds, "v", 3, [](const Vec3& p) { return std::array<double, 3>{p.x, 2 * p.y, -p.z}; },
            AttributeRole::Vectors);
  const DataArray d = displacement(ds);
  ASSERT_EQ(d.tuples(), 5u);
  const DataArray& n = *pd.point_data.normals();
  for (std::size_t i = 0; i < 5; ++i) {
    const Vec3 p = pd.points[i];
    EXPECT_FLOAT_EQ(d.get(i), float(p.x * n.get(i, 0) + 2 * p.y * n.get(i, 1) - p.z * n.get(i, 2)));
  }
  DisplacementOptions o;
  o.normals = "v";
  o.vectors = "Normals";
  EXPECT_NO_THROW((void)displacement(ds, o));
  o.normals = "point_ids";
  expect_error([&] { (void)displacement(ds, o); }, "'point_ids' has 1 component, 3 needed");
}

// A linear field's gradient is exact on every dataset type (tolerance: double rounding).
TEST(Gradient, LinearFieldsAreExactOnEveryDatasetType) {
  std::vector<Dataset> inputs = {image({5, 4, 3}, {-1, 2, 0.5}, {0.5, 0.25, 2}),
                                 image({4, 3, 2}, {0, 0, 0}, {-1, 1, -0.5}),  // negative spacing
                                 curved_grid(), solid_cells(), to_unstructured(curved_grid())};
  for (Dataset& ds : inputs) {
    add_field(ds, "f", 1, linear);
    GradientOptions o;
    o.array = "f";
    const GradientResult r = gradient(ds, o);
    ASSERT_EQ(r.gradient.components(), 3);
    ASSERT_EQ(r.gradient.tuples(), num_points(ds));
    EXPECT_EQ(r.gradient.name(), "Gradient");
    for (std::size_t i = 0; i < num_points(ds); ++i) expect_gradient(r.gradient, i, kSlope, 1e-9);
  }
}

// On a surface only the tangential part exists: a plane z = 0 gives (2, -3, 0); a line along
// x gives the x part only. A 2D image (nz = 1) likewise. Degenerate cells are left out.
TEST(Gradient, SurfacesAndLinesGiveTheTangentialPart) {
  PolyData pd;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) pd.points.push_back({0.5 * i, 0.7 * j + 0.1 * i, 0});
  pd.polys.add({0, 1, 4, 3});
  pd.polys.add({1, 2, 5});
  pd.polys.add({1, 5, 4});
  pd.polys.add({6, 7, 8});  // degenerate (collinear): no derivative, left out of the average
  pd.strips.add({3, 6, 4, 7, 5, 8});
  Dataset ds = pd;
  add_field(ds, "f", 1, linear);
  const GradientResult r = gradient(ds, {.array = "f"});
  for (std::size_t i = 0; i < 9; ++i) expect_gradient(r.gradient, i, {2, -3, 0}, 1e-9);

  PolyData line;
  for (int i = 0; i < 4; ++i) line.points.push_back({1.5 * i, 0, 0});
  line.lines.add({0, 1, 2, 3});
  Dataset ls = line;
  add_field(ls, "f", 1, linear);
  const GradientResult lr = gradient(ls, {.array = "f"});
  for (std::size_t i = 0; i < 4; ++i) expect_gradient(lr.gradient, i, {2, 0, 0}, 1e-9);

  Dataset flat = image({4, 5, 1}, {0, 0, 3}, {0.5, 0.5, 1});
  add_field(flat, "f", 1, linear);
  const GradientResult fr = gradient(flat, {.array = "f"});
  for (std::size_t i = 0; i < 20; ++i) expect_gradient(fr.gradient, i, {2, -3, 0}, 1e-9);
}

// Central differences are exact for quadratics inside an image: d(x^2)/dx = 2x there.
TEST(Gradient, ImageInteriorIsSecondOrder) {
  Dataset img = image({6, 3, 3}, {0, 0, 0}, {0.5, 1, 1});
  add_field(img, "q", 1, [](const Vec3& p) { return std::array<double, 1>{p.x * p.x}; });
  const GradientResult r = gradient(img, {.array = "q"});
  const auto& im = std::get<ImageData>(img);
  for (Index k = 0; k < 3; ++k)
    for (Index j = 0; j < 3; ++j)
      for (Index i = 1; i < 5; ++i) {
        const auto id = std::size_t(im.point_id(i, j, k));
        expect_gradient(r.gradient, id, {2 * im.point(i, j, k).x, 0, 0}, 1e-12);
      }
}

// Rigid rotation about z: divergence 0, vorticity (0, 0, 2); the radial field: divergence 3,
// vorticity 0. The gradient of a vector has 9 components, d v_c / d x_a at 3 c + a.
TEST(Gradient, DivergenceAndVorticityOfVectorFields) {
  std::vector<Dataset> inputs = {image({4, 4, 3}, {-1, -1, 0}, {0.5, 0.5, 0.5}), curved_grid(),
                                 solid_cells()};
  for (Dataset& ds : inputs) {
    add_field(ds, "rot", 3, [](const Vec3& p) { return std::array<double, 3>{-p.y, p.x, 0}; },
              AttributeRole::Vectors);
    add_field(ds, "rad", 3, [](const Vec3& p) { return std::array<double, 3>{p.x, p.y, p.z}; });
    GradientOptions o;
    o.array = "rot";
    o.divergence = o.vorticity = true;
    const GradientResult r = gradient(ds, o);
    ASSERT_TRUE(r.divergence && r.vorticity);
    EXPECT_EQ(r.gradient.components(), 9);
    for (std::size_t i = 0; i < num_points(ds); ++i) {
      EXPECT_NEAR(r.divergence->get(i), 0, 1e-9);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(r.vorticity->get(i, a), a == 2 ? 2 : 0, 1e-9);
      EXPECT_NEAR(r.gradient.get(i, 1), -1, 1e-9);  // d(-y)/dy
      EXPECT_NEAR(r.gradient.get(i, 3), 1, 1e-9);   // d(x)/dx of v_y
    }
    o.array = "rad";
    o.compute_gradient = false;
    const GradientResult q = gradient(ds, o);
    EXPECT_TRUE(q.gradient.empty());
    for (std::size_t i = 0; i < num_points(ds); ++i) {
      EXPECT_NEAR(q.divergence->get(i), 3, 1e-9);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(q.vorticity->get(i, a), 0, 1e-9);
    }
  }
}

// A NaN value makes the gradient NaN at the points of the cells using it, in that component only,
// on every dataset type (unstructured grids refused the whole array before).
TEST(Gradient, NaNValuesGiveNaNOnlyAroundThem) {
  std::vector<Dataset> inputs = {image({5, 4, 3}, {-1, 2, 0.5}, {0.5, 0.25, 2}), curved_grid(),
                                 solid_cells(), to_unstructured(curved_grid())};
  for (Dataset& ds : inputs) {
    add_field(ds, "f", 2, [](const Vec3& p) { return std::array<double, 2>{linear(p)[0], p.x}; });
    const std::size_t bad = num_points(ds) / 2;
    point_data(ds).get("f").set(bad, 0, std::numeric_limits<double>::quiet_NaN());
    GradientOptions o;
    o.array = "f";
    const GradientResult r = gradient(ds, o);
    // Points sharing a cell with `bad`.
    std::vector<char> near(num_points(ds), 0);
    std::vector<Index> ids;
    for (std::size_t c = 0; c < num_cells(ds); ++c) {
      cell_point_ids(ds, static_cast<Index>(c), ids);
      if (std::find(ids.begin(), ids.end(), static_cast<Index>(bad)) == ids.end()) continue;
      for (Index id : ids) near[static_cast<std::size_t>(id)] = 1;
    }
    std::size_t nan_rows = 0;
    for (std::size_t i = 0; i < num_points(ds); ++i) {
      const bool nan0 = std::isnan(r.gradient.get(i, 0));
      nan_rows += nan0 ? 1 : 0;
      if (!near[i]) {
        EXPECT_FALSE(nan0) << i;
      }
      for (int a = 3; a < 6; ++a) EXPECT_FALSE(std::isnan(r.gradient.get(i, a))) << i;  // x: finite
      EXPECT_NEAR(r.gradient.get(i, 3), 1, 1e-9) << i;
    }
    EXPECT_GT(nan_rows, 0u);
    EXPECT_LE(nan_rows, static_cast<std::size_t>(std::count(near.begin(), near.end(), 1)));
  }
}

TEST(Gradient, BadRequestsAreErrors) {
  const StructuredGrid sg = test::sample_structured();
  GradientOptions o;
  o.divergence = true;
  expect_error([&] { (void)gradient(sg, o); }, "divergence needs a 3-component point array; 'density' has 1");
  o = {};
  o.compute_gradient = false;
  expect_error([&] { (void)gradient(sg, o); }, "nothing to compute");
  o = {};
  o.array = "Velocity";
  expect_error([&] { (void)gradient(sg, o); }, "no point array 'Velocity' (point arrays: 'density')");
  // The active scalars by default: density grows by 0.125 per point id.
  const GradientResult r = gradient(sg);
  EXPECT_EQ(r.gradient.tuples(), sg.num_points());
}
