// The implicit modeller and the chapter's figures 1.26-1.29 as library recipes.

#include "isoforge/model/implicit_modeller.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "isoforge/contour/connectivity.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/closest_point.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/csg_sparse.hpp"
#include "isoforge/model/implicit_modeller_sparse.hpp"
#include "support/result.hpp"
#include "support/expect_error.hpp"
#include "support/meshes.hpp"

using isoforge::test::expect_error;

using namespace isoforge;

namespace {

PolyData hello() {
  return std::get<PolyData>(read(ISOFORGE_DATA_DIR "/hello.vtk"));
}

Bounds box(Vec3 lo, Vec3 hi) {
  Bounds b;
  b.min = lo;
  b.max = hi;
  return b;
}

template <class T>
std::vector<T> values(const ImageData& img) {
  const auto v = img.point_data.scalars()->values<T>();
  return {v.begin(), v.end()};
}

// Points of `surface` whose IsovalueIndex is `index`.
std::vector<Vec3> points_of(const PolyData& surface, int index) {
  std::vector<Vec3> out;
  const DataArray& iso = surface.point_data.get("IsovalueIndex");
  for (std::size_t i = 0; i < surface.num_points(); ++i) {
    if (iso.get(i) == index) out.push_back(surface.points[i]);
  }
  return out;
}

// The surface's polygons whose points all have IsovalueIndex `index`.
PolyData surface_of(const PolyData& surface, int index) {
  PolyData out = surface;
  out.polys.clear();
  const DataArray& iso = surface.point_data.get("IsovalueIndex");
  for (std::size_t c = 0; c < surface.polys.size(); ++c) {
    const auto ids = surface.polys.cell(c);
    if (iso.get(std::size_t(ids[0])) == index) out.polys.add(ids);
  }
  return out;
}

// A closed, outward surface of revolution about z with radius r(z) (a dumbbell: two bulbs joined
// by a neck), poles at z = ±1.
PolyData dumbbell(int rings = 80, int segments = 64) {
  const auto radius = [](double z) {
    const double bulb = 0.6 * std::sqrt(std::max(0.0, 1 - z * z));
    const double neck = 0.15 + 0.45 * std::pow(std::abs(z), 1.5);
    return std::min(bulb, neck) + 0 * z;
  };
  return test::polar_surface({0, 0, -1}, {0, 0, 1}, rings, segments, [&](int i, int j) {
    const double z = -std::cos(std::numbers::pi * i / rings);
    const double r = radius(z);
    const double ph = 2 * std::numbers::pi * j / segments;
    return Vec3{r * std::cos(ph), r * std::sin(ph), z};
  });
}

}  // namespace

TEST(ImplicitModeller, VtkDefaultsBoundsAndMaximumDistance) {
  // vtkImplicitModeller on hello.vtk with its defaults: 50^3 over the input bounds
  // (0..9, 0..2, 0..0) grown by 0.0125 * 9 = 0.1125 per side; maximum distance 0.1 * 9.
  const PolyData in = hello();
  const ModellerGrid mg = implicit_modeller_grid(in.bounds());
  EXPECT_DOUBLE_EQ(mg.max_distance, 0.9);
  EXPECT_DOUBLE_EQ(mg.grid.origin.x, -0.1125);
  EXPECT_DOUBLE_EQ(mg.grid.origin.z, -0.1125);
  EXPECT_DOUBLE_EQ(mg.grid.spacing.x, 9.225 / 49);
  EXPECT_EQ(mg.grid.dims, (Dims{50, 50, 50}));
  DistanceStats stats;
  const ImageData img = test::split_result(implicit_modeller(in, {}), stats);
  EXPECT_EQ(img.point_data.scalars()->name(), "ImageScalars");
  EXPECT_EQ(img.point_data.scalars()->type(), ScalarType::Float32);
  const auto v = values<float>(img);
  // Capped boundary, exact interior (VTK's own output agrees bit for bit: see the peer script).
  EXPECT_EQ(v[std::size_t(img.point_id(0, 25, 25))], float(kVtkFloatMax));
  EXPECT_EQ(v[std::size_t(img.point_id(25, 25, 49))], float(kVtkFloatMax));
  const Vec3 x = img.point(img.point_id(1, 25, 25));
  double ref = 1e300;
  for (std::size_t c = 0; c < in.lines.size(); ++c) {
    const auto ids = in.lines.cell(c);
    ref = std::min(ref, std::sqrt(segment_distance2(x, in.points[ids[0]], in.points[ids[1]])));
  }
  EXPECT_FLOAT_EQ(v[std::size_t(img.point_id(1, 25, 25))], float(ref));
  // Explicit bounds are grown too (VTK does), by 0.0125 of their largest side.
  ImplicitModellerOptions o;
  o.model_bounds = box({-1, -1, -1}, {10, 3, 1});
  const ModellerGrid g2 = implicit_modeller_grid(in.bounds(), o);
  EXPECT_DOUBLE_EQ(g2.grid.origin.x, -1.1375);
  EXPECT_DOUBLE_EQ(g2.max_distance, 1.1);
  o.adjust_bounds = false;
  EXPECT_DOUBLE_EQ(implicit_modeller_grid(in.bounds(), o).grid.origin.y, -1.0);
}

TEST(ImplicitModeller, FarValueClampAndCapping) {
  const PolyData in = hello();
  ImplicitModellerOptions o;
  o.sample_dimensions = {40, 12, 8};
  o.maximum_distance = 0.05;  // 0.45 world units
  o.capping = false;
  const auto far = values<float>(implicit_modeller(in, o).output);
  o.clamp = true;
  const auto clamped = values<float>(implicit_modeller(in, o).output);
  o.output_type = ScalarType::Float64;
  const ImageData img64 = implicit_modeller(in, o).output;
  const auto d64 = values<double>(img64);
  std::size_t beyond = 0;
  for (std::size_t i = 0; i < far.size(); ++i) {
    if (far[i] == float(kVtkFloatMax)) {
      ++beyond;
      ASSERT_EQ(clamped[i], 0.45f);
      ASSERT_EQ(d64[i], 0.45);
    } else {
      ASSERT_LT(far[i], 0.45f);
      ASSERT_EQ(clamped[i], far[i]);
      ASSERT_EQ(float(d64[i]), far[i]);
    }
  }
  EXPECT_GT(beyond, 0u);
  // Capping: every boundary sample holds the cap value, nothing else changes.
  o.capping = true;
  o.cap_value = 7;
  const ImageData capped = implicit_modeller(in, o).output;
  const auto c = values<double>(capped);
  for (Index k = 0; k < 8; ++k)
    for (Index j = 0; j < 12; ++j)
      for (Index i = 0; i < 40; ++i) {
        const auto id = std::size_t(capped.point_id(i, j, k));
        const bool boundary = i == 0 || j == 0 || k == 0 || i == 39 || j == 11 || k == 7;
        ASSERT_EQ(c[id], boundary ? 7.0 : d64[id]);
      }
}

// VTK's output scalar types: integers hold trunc(distance × scale), scale 1 or (with
// ScaleToMaximumDistance) the type's maximum over the maximum distance; cap and far values default
// to the type's VTK maximum (1e299 for Float64). The peer script compares these with VTK's.
TEST(ImplicitModeller, OutputScalarTypesAsVtk) {
  const PolyData in = hello();
  ImplicitModellerOptions o;
  o.sample_dimensions = {40, 12, 8};
  o.maximum_distance = 0.05;  // 0.45 world units
  o.output_type = ScalarType::Float64;
  const ImageData ref = implicit_modeller(in, o).output;
  const auto d = values<double>(ref);
  EXPECT_EQ(d[std::size_t(ref.point_id(0, 5, 5))], kVtkDoubleMax);  // capped
  EXPECT_EQ(vtk_type_max(ScalarType::Float64), kVtkDoubleMax);
  EXPECT_EQ(vtk_type_max(ScalarType::Float32), kVtkFloatMax);
  EXPECT_EQ(vtk_type_max(ScalarType::Int16), 32767.0);
  std::size_t beyond = 0;
  for (double v : d) beyond += v == kVtkDoubleMax;
  for (const auto& [type, scaled] : {std::pair{ScalarType::UInt8, true}, std::pair{ScalarType::Int16, false},
                                     std::pair{ScalarType::UInt16, true}, std::pair{ScalarType::Int32, true}}) {
    o.output_type = type;
    o.scale_to_maximum_distance = scaled;
    const ImageData img = implicit_modeller(in, o).output;
    const DataArray& a = *img.point_data.scalars();
    ASSERT_EQ(a.type(), type);
    const double tmax = vtk_type_max(type);
    const double scale = scaled ? tmax / 0.45 : 1.0;
    std::size_t far = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double v = a.get(i);
      if (d[i] == kVtkDoubleMax) {
        ASSERT_EQ(v, tmax) << i;  // capped or beyond the band
        ++far;
      } else {
        ASSERT_EQ(v, std::trunc(d[i] * scale)) << i;
        ASSERT_LT(v, tmax);
      }
    }
    EXPECT_EQ(far, beyond);
  }
  // Clamped: beyond the band the maximum distance, converted like the distances
  // (trunc(maxd × 65535 / maxd): 65535, or 65534 when the product rounds below).
  o.capping = false;
  o.output_type = ScalarType::Float64;
  o.scale_to_maximum_distance = false;
  const auto open = values<double>(implicit_modeller(in, o).output);
  o.output_type = ScalarType::UInt16;
  o.scale_to_maximum_distance = true;
  o.clamp = true;
  const ImageData clamped = implicit_modeller(in, o).output;
  std::size_t at_max = 0;
  for (std::size_t i = 0; i < open.size(); ++i) {
    const double v = clamped.point_data.scalars()->get(i);
    if (open[i] == kVtkDoubleMax) {
      ASSERT_GE(v, 65534.0);
      ++at_max;
    } else {
      ASSERT_LT(v, 65535.0);
    }
  }
  EXPECT_GT(at_max, 0u);
  // Signed distances into an unsigned type cannot be stored.
  o.signed_distance = true;
  expect_error([&] { (void)implicit_modeller(in, o); }, "signed output type");
}

// Fig. 1.28: the HELLO strokes thickened on a 110 x 40 x 20 volume at offset 0.25 (VTK's Hello
// example: model bounds (-1, 10, -1, 3, -1, 1), maximum distance 0.25 of the largest side).
TEST(ImplicitModeller, HelloOffsetSurfaceIsFiveClosedManifoldLetters) {
  ImplicitModellerOptions o;
  o.sample_dimensions = {110, 40, 20};
  o.model_bounds = box({-1, -1, -1}, {10, 3, 1});
  o.maximum_distance = 0.25;
  const ImageData img = implicit_modeller(hello(), o).output;
  EXPECT_NE(img.spacing.x, img.spacing.y);  // per-axis spacing
  const PolyData surface = offset_surfaces(img, {0.25}).output;
  const SurfaceTopology t = analyze_topology(surface);
  EXPECT_TRUE(t.closed());
  EXPECT_TRUE(t.manifold());
  EXPECT_TRUE(t.oriented());
  // Five surfaces: the letters H, E, L, L, O. Each letter's strokes touch (H's bar meets both
  // posts, E's arms meet its spine, each L's two strokes share a corner, O's four sides form a
  // loop), while neighbouring letters are 1 unit apart — more than the 2 x 0.25 the two tubes
  // span — so the union of the tubes has exactly one component per letter. The O's loop makes
  // its surface a torus (genus 1); the other letters are spheres (genus 0).
  ASSERT_EQ(t.components.size(), 5u);
  std::multiset<long> genera;
  for (const auto& c : t.components) {
    EXPECT_TRUE(c.closed);
    genera.insert(c.genus);
  }
  EXPECT_EQ(genera, (std::multiset<long>{0, 0, 0, 0, 1}));
  // connectivity() agrees and separates them (Fig. 1.29's tool).
  EXPECT_EQ(connectivity(surface).stats.components, 5u);
}

// Fig. 1.26: distance functions to a point, a line and a triangle; several offset surfaces of
// each from one contour call.
TEST(ImplicitModeller, OffsetSurfacesOfAPointALineAndATriangle) {
  PolyData point, line, tri;
  point.points.push_back({0, 0, 0});
  point.verts.add({0});
  line.points.push_back({-0.5, 0, 0});
  line.points.push_back({0.5, 0, 0});
  line.lines.add({0, 1});
  for (const Vec3& p : {Vec3{-0.5, -0.4, 0}, Vec3{0.5, -0.4, 0}, Vec3{0, 0.5, 0}})
    tri.points.push_back(p);
  tri.polys.add({0, 1, 2});
  const std::vector<double> offsets{0.15, 0.3, 0.45};
  for (const PolyData* gen : {&point, &line, &tri}) {
    ImplicitModellerOptions o;
    o.sample_dimensions = {61, 61, 61};
    o.model_bounds = box({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2});
    o.maximum_distance = 0.25;  // 0.6 world units, beyond every offset
    const ImageData img = implicit_modeller(*gen, o).output;
    const PolyData all = offset_surfaces(img, offsets).output;
    const double h = img.spacing.x;
    for (int k = 0; k < 3; ++k) {
      const std::vector<Vec3> pts = points_of(all, k);
      ASSERT_GT(pts.size(), 100u);
      for (const Vec3& p : pts) {
        double d;
        if (gen == &point) {
          d = norm(p);
        } else if (gen == &line) {
          d = std::sqrt(segment_distance2(p, line.points[0], line.points[1]));
        } else {
          d = std::sqrt(triangle_distance2(p, tri.points[0], tri.points[1], tri.points[2]));
        }
        // Linear interpolation of the distance along grid edges: O(h^2 / d) error.
        ASSERT_NEAR(d, offsets[std::size_t(k)], 0.1 * h) << k;
      }
      const SurfaceTopology t = analyze_topology(surface_of(all, k));
      EXPECT_TRUE(t.closed());
      EXPECT_TRUE(t.manifold());
      EXPECT_EQ(t.components.size(), 1u);
    }
  }
}

// Fig. 1.27: union, intersection and difference of a point's and a line's offset solids (a ball
// of radius 0.5 about the origin and a capsule of radius 0.25 about the x axis from -1 to 1),
// dense and sparse.
TEST(ImplicitModeller, BooleansOfPointAndLineGenerators) {
  PolyData point, line;
  point.points.push_back({0, 0, 0});
  point.verts.add({0});
  line.points.push_back({-1, 0, 0});
  line.points.push_back({1, 0, 0});
  line.lines.add({0, 1});
  const auto ball = [](const Vec3& p) { return norm(p) - 0.5; };
  const auto capsule = [&](const Vec3& p) {
    return std::sqrt(segment_distance2(p, {-1, 0, 0}, {1, 0, 0})) - 0.25;
  };
  const GridSpec g = GridSpec::from_bounds(box({-1.5, -1, -1}, {1.5, 1, 1}), {61, 41, 41});
  DistanceOptions o;
  o.max_distance = 0.75;
  const ImageData dp = offset(distance_image(point, g, o).output, 0.5);
  const ImageData dl = offset(distance_image(line, g, o).output, 0.25);
  const double h = g.spacing.x;
  const auto check = [&](const PolyData& s, CsgOperation op, const char* what) {
    ASSERT_GT(s.num_points(), 100u) << what;
    for (std::size_t i = 0; i < s.num_points(); ++i) {
      const Vec3 p = s.points[i];
      const double a = ball(p), b = capsule(p);
      const double f = op == CsgOperation::Union          ? std::min(a, b)
                       : op == CsgOperation::Intersection ? std::max(a, b)
                                                          : std::max(a, -b);
      ASSERT_NEAR(f, 0, 0.5 * h) << what << " " << i;
    }
    const SurfaceTopology t = analyze_topology(s);
    EXPECT_TRUE(t.closed()) << what;
    EXPECT_TRUE(t.manifold()) << what;
  };
  // The sparse level sets: unsigned distance fields offset into solids, then OpenVDB's CSG.
  const auto sp = offset(*distance_grid(point, g, o).output, 0.5);
  const auto sl = offset(*distance_grid(line, g, o).output, 0.25);
  std::size_t components[3];
  long genus[3];
  for (CsgOperation op :
       {CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference}) {
    const PolyData dense = offset_surfaces(csg(dp, dl, op), {0.0}).output;
    check(dense, op, "dense");
    const auto grid = csg(*sp, *sl, op);
    const PolyData sparse = offset_surfaces(*grid, {0.0}).output;
    check(sparse, op, "sparse");
    // Same field on the band, so the same surface size.
    EXPECT_EQ(sparse.polys.size(), dense.polys.size()) << csg_operation_name(op);
    const SurfaceTopology t = analyze_topology(dense);
    components[int(op)] = t.components.size();
    genus[int(op)] = t.components.empty() ? -1 : t.components[0].genus;
  }
  EXPECT_EQ(components[0], 1u);  // the ball threaded on the capsule
  EXPECT_EQ(genus[0], 0);
  EXPECT_EQ(components[1], 1u);  // the capsule's middle, inside the ball
  EXPECT_EQ(genus[1], 0);
  EXPECT_EQ(components[2], 1u);  // the ball with a tunnel bored through it: a ring
  EXPECT_EQ(genus[2], 1);
}

// Fig. 1.29: a concave generator gives several surfaces. The inner offset of a dumbbell at a
// distance larger than its neck's radius splits into one surface per bulb; connectivity
// separates them.
TEST(ImplicitModeller, ConcaveGeneratorGivesSeveralSurfaces) {
  const PolyData mesh = dumbbell();
  ASSERT_TRUE(analyze_topology(mesh).closed());
  ImplicitModellerOptions o;
  o.sample_dimensions = {48, 48, 72};
  o.model_bounds = box({-0.8, -0.8, -1.2}, {0.8, 0.8, 1.2});
  o.adjust_bounds = false;
  o.maximum_distance = 0.15;  // 0.36
  o.signed_distance = true;
  o.clamp = true;
  const ImageData img = implicit_modeller(mesh, o).output;
  const PolyData outer = offset_surfaces(img, {0.1}).output;
  const PolyData inner = offset_surfaces(img, {-0.2}).output;  // deeper than the neck (radius 0.15)
  EXPECT_EQ(connectivity(outer).stats.components, 1u);
  const ConnectivityResult r = connectivity(inner);
  EXPECT_EQ(r.stats.components, 2u);
  for (std::size_t c = 0; c < 2; ++c) EXPECT_GT(r.stats.sizes[c], 100u);
  EXPECT_TRUE(analyze_topology(inner).closed());
}

TEST(ImplicitModeller, SparseMatchesDenseOnTheBand) {
  ImplicitModellerOptions o;
  o.sample_dimensions = {72, 72, 72};
  o.model_bounds = box({-1, -1, -1}, {10, 10, 10});  // a cube: cubic voxels
  o.maximum_distance = 0.05;
  const PolyData in = hello();
  const ImageData dense = implicit_modeller(in, o).output;
  const auto grid = implicit_modeller_vdb(in, o).output;
  const auto v = values<float>(dense);
  std::size_t active = 0;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    ASSERT_EQ(*it, v[std::size_t(dense.point_id(c.x(), c.y(), c.z()))]);
    ++active;
  }
  std::size_t band = 0;
  for (float x : v) band += x < float(0.05 * 11);
  EXPECT_EQ(active, band);
  // The sparse contour equals the dense one (the cap is far from the strokes).
  ContourOptions c;
  c.values = {0.25};
  EXPECT_EQ(contour_vdb(*grid, c).output.polys.size(), contour_image(dense, c).output.polys.size());
}

TEST(ImplicitModeller, BadInputIsAnErrorNamingTheProblem) {
  const PolyData in = hello();
  expect_error([] { (void)implicit_modeller(PolyData{}); }, "empty");
  ImplicitModellerOptions o;
  o.sample_dimensions = {1, 40, 20};
  expect_error([&] { (void)implicit_modeller(in, o); }, "at least 2");
  o.sample_dimensions = {50, 50, 50};
  for (double bad : {0.0, -0.1, 1.5, std::nan("")}) {
    o.maximum_distance = bad;
    expect_error([&] { (void)implicit_modeller(in, o); }, "maximum distance");
  }
  o.maximum_distance = 0.1;
  PolyData nan = in;
  nan.points.set(3, {INFINITY, 0, 0});
  expect_error([&] { (void)implicit_modeller(nan, o); }, "point 3 is not finite");
  o.scale_to_maximum_distance = true;  // needs an integer type
  expect_error([&] { (void)implicit_modeller(in, o); }, "integer output type");
  o.scale_to_maximum_distance = false;
  o.output_type = ScalarType::UInt8;
  o.cap_value = 300;
  expect_error([&] { (void)implicit_modeller(in, o); }, "does not fit");
  o.cap_value.reset();
  o.far_value = -1;
  expect_error([&] { (void)implicit_modeller(in, o); }, "far value -1 does not fit UInt8");
  o.far_value.reset();
  o.output_type = ScalarType::Float32;
  o.far_value = 1e299;
  expect_error([&] { (void)implicit_modeller(in, o); }, "does not fit Float32");
  o.far_value.reset();
  PolyData single;
  single.points.push_back({1, 2, 3});
  single.verts.add({0});
  expect_error([&] { (void)implicit_modeller(single, o); }, "zero extent");
  o.model_bounds = box({0, 0, 0}, {4, 4, 4});
  EXPECT_NO_THROW((void)implicit_modeller(single, o));
}
