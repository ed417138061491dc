#include "isoforge/filters/glyph.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <set>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/filters/compute_normals.hpp"
#include "isoforge/io/io.hpp"
#include "support/expect_error.hpp"
#include "support/surface_checks.hpp"

using namespace isoforge;

namespace {

// Area of a regular r-gon of circumradius R.
double polygon_area(int r, double R) {
  return 0.5 * r * R * R * std::sin(2 * std::numbers::pi / r);
}

// Every triangle's normal agrees with its points' normals (within 90 degrees).
void expect_normals_outward(const PolyData& pd, const std::string& what) {
  const DataArray& n = pd.point_data.get("Normals");
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    const Vec3 a = pd.points[static_cast<std::size_t>(ids[0])];
    const Vec3 f = cross(pd.points[static_cast<std::size_t>(ids[1])] - a,
                         pd.points[static_cast<std::size_t>(ids[2])] - a);
    for (const Index id : ids) {
      const auto i = static_cast<std::size_t>(id);
      EXPECT_GT(dot(f, Vec3{n.get(i, 0), n.get(i, 1), n.get(i, 2)}), 0) << what << " cell " << c;
    }
  }
}

PolyData three_points_with_vectors() {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({10, 0, 0});
  pd.points.push_back({0, 10, 0});
  pd.point_data.add(DataArray::from_vector<float>("V", 3, {1, 0, 0, 0, 2, 0, 0, 0, -3}),
                    AttributeRole::Vectors);
  pd.point_data.add(DataArray::from_vector<double>("s", 1, {0, 5, 10}), AttributeRole::Scalars);
  return pd;
}

Vec3 at(const PolyData& pd, std::size_t i) { return pd.points[i]; }

}  // namespace

TEST(GlyphSource, CountsVolumesAndOutwardNormals) {
  // Cone (6 sides): apex, side ring, cap ring = 13 points; 6 side + 4 cap triangles. Its volume
  // is the hexagonal base's area times the height 1, over 3.
  const PolyData cone = glyph_source(GlyphShape::Cone, 6);
  EXPECT_EQ(cone.num_points(), 13u);
  EXPECT_EQ(cone.polys.size(), 10u);
  EXPECT_NEAR(test::signed_volume(cone), polygon_area(6, 0.5) / 3, 1e-6);
  expect_normals_outward(cone, "cone");
  // Cube: 4 points and 2 triangles per face, volume 1.
  const PolyData cube = glyph_source(GlyphShape::Cube);
  EXPECT_EQ(cube.num_points(), 24u);
  EXPECT_EQ(cube.polys.size(), 12u);
  EXPECT_NEAR(test::signed_volume(cube), 1.0, 1e-6);
  expect_normals_outward(cube, "cube");
  // Arrow (8 sides): cap, 2 shaft rings, 2 annulus rings, tip ring = 6 rings + apex; triangles
  // 6 cap + 16 shaft + 16 annulus + 8 tip. Volume: the shaft prism plus the tip pyramid.
  const PolyData arrow = glyph_source(GlyphShape::Arrow, 8);
  EXPECT_EQ(arrow.num_points(), 6u * 8 + 1);
  EXPECT_EQ(arrow.polys.size(), 6u * 8 - 2);
  EXPECT_NEAR(test::signed_volume(arrow),
              polygon_area(8, 0.03) * 0.65 + polygon_area(8, 0.1) * 0.35 / 3, 1e-6);
  expect_normals_outward(arrow, "arrow");
  // Sphere (8 slices, 4 stacks): 2 poles + 3 rings of 8; 2 * 8 fan + 2 * 8 * 2 band triangles.
  const PolyData sphere = glyph_source(GlyphShape::Sphere, 8);
  EXPECT_EQ(sphere.num_points(), 2u + 3 * 8);
  EXPECT_EQ(sphere.polys.size(), 16u + 32);
  const double v = test::signed_volume(sphere);
  EXPECT_GT(v, 0.5 * 4 / 3 * std::numbers::pi / 8);  // above half the ball's volume
  EXPECT_LT(v, 4.0 / 3 * std::numbers::pi / 8);       // inscribed: below the ball's
  expect_normals_outward(sphere, "sphere");
  // Each shape spans [-0.5, 0.5] along x (the arrow and line [0, 1]).
  EXPECT_DOUBLE_EQ(cone.bounds().min.x, -0.5);
  EXPECT_DOUBLE_EQ(cone.bounds().max.x, 0.5);
  EXPECT_DOUBLE_EQ(arrow.bounds().max.x, 1.0);
  const PolyData line = glyph_source(GlyphShape::Line);
  EXPECT_EQ(line.num_points(), 2u);
  EXPECT_EQ(line.lines.size(), 1u);
  test::expect_error([] { (void)glyph_source(GlyphShape::Cone, 2); }, "resolution must be >= 3");
}

TEST(Glyph, ConesTurnedToTheVectorsAndScaledByTheirLength) {
  const PolyData pd = three_points_with_vectors();
  GlyphOptions o;
  o.scale = GlyphScale::Vector;
  const auto [out, stats] = glyph(pd, GlyphShape::Cone, o);
  ASSERT_EQ(stats.glyphs, 3u);
  ASSERT_EQ(out.num_points(), 3u * 13);
  EXPECT_EQ(out.polys.size(), 3u * 10);
  EXPECT_EQ(stats.orient_array, "V");
  EXPECT_DOUBLE_EQ(stats.min_scale, 1);
  EXPECT_DOUBLE_EQ(stats.max_scale, 3);
  // The apex (source point 0, at +0.5 on the axis) of glyph g is p + 0.5 |v| v / |v|.
  EXPECT_NEAR(norm(at(out, 0) - Vec3{0.5, 0, 0}), 0, 1e-6);
  EXPECT_NEAR(norm(at(out, 13) - Vec3{10, 1, 0}), 0, 1e-6);
  EXPECT_NEAR(norm(at(out, 26) - Vec3{0, 10, -1.5}), 0, 1e-6);
  // The apex's normal is the axis, turned.
  const DataArray& n = out.point_data.get("Normals");
  EXPECT_NEAR(n.get(26, 2), -1, 1e-6);
  EXPECT_EQ(out.point_data.active_name(AttributeRole::Normals), "Normals");
  // Each glyph is the source moved rigidly: its volume is the source's times size^3.
  PolyData second;
  second.points = Points(13);
  for (std::size_t j = 0; j < 13; ++j) second.points.set(j, at(out, 13 + j));
  second.polys = glyph_source(GlyphShape::Cone).polys;
  EXPECT_NEAR(test::signed_volume(second), 8 * polygon_area(6, 0.5) / 3, 1e-4);
  expect_normals_outward(out, "glyphs");
  // Input point ids and the carried point data.
  const DataArray& ids = out.point_data.get("InputPointIds");
  EXPECT_EQ(ids.get(12), 0.0);
  EXPECT_EQ(ids.get(13), 1.0);
  EXPECT_EQ(ids.get(38), 2.0);
  EXPECT_EQ(out.point_data.get("s").get(20), 5.0);
  EXPECT_EQ(out.point_data.get("V").components(), 3);
  EXPECT_NO_THROW(out.validate());
}

TEST(Glyph, OppositeDirectionAndZeroVector) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({5, 0, 0});
  pd.point_data.add(DataArray::from_vector<double>("V", 3, {-2, 0, 0, 0, 0, 0}),
                    AttributeRole::Vectors);
  const auto [out, stats] = glyph(pd, GlyphShape::Cone);
  // -x is the half-turn about z: the apex goes to -0.5; a zero vector leaves the source's +x.
  EXPECT_NEAR(norm(at(out, 0) - Vec3{-0.5, 0, 0}), 0, 1e-12);
  EXPECT_NEAR(norm(at(out, 13) - Vec3{5.5, 0, 0}), 0, 1e-12);
  expect_normals_outward(out, "reversed");
}

TEST(Glyph, ScaleByScalarWithClampingAndColours) {
  const PolyData pd = three_points_with_vectors();
  GlyphOptions o;
  o.orient = GlyphOrient::None;
  o.scale = GlyphScale::Scalar;
  o.clamp = true;  // s = 0, 5, 10 in its own range [0, 10]: sizes 0, 0.5, 1 times the factor
  o.factor = 4;
  o.color = GlyphColor::Index;
  const auto [out, stats] = glyph(pd, GlyphShape::Cube, o);
  EXPECT_DOUBLE_EQ(stats.min_scale, 0);
  EXPECT_DOUBLE_EQ(stats.max_scale, 4);
  Bounds b1;
  for (std::size_t j = 24; j < 48; ++j) b1.extend(at(out, j));
  EXPECT_NEAR(b1.max.x - b1.min.x, 2, 1e-6);  // size 2, unrotated
  EXPECT_NEAR(b1.max.y - b1.min.y, 2, 1e-6);
  const DataArray& c = out.point_data.get("GlyphColor");
  EXPECT_EQ(c.get(0), 0.0);
  EXPECT_EQ(c.get(47), 1.0);
  EXPECT_EQ(c.get(48), 2.0);
  EXPECT_EQ(out.point_data.active_name(AttributeRole::Scalars), "GlyphColor");
  // An explicit range: [5, 10] maps 0 and 5 to 0, 10 to 1.
  o.range = std::array<double, 2>{5, 10};
  o.color = GlyphColor::Magnitude;
  const auto r = glyph(pd, GlyphShape::Cube, o);
  EXPECT_DOUBLE_EQ(r.stats.min_scale, 0);
  EXPECT_DOUBLE_EQ(r.stats.max_scale, 4);
  EXPECT_FLOAT_EQ(static_cast<float>(r.output.point_data.get("GlyphColor").get(30)), 2.0f);  // |(0,2,0)|
  // Without clamping the size is |scalar| * factor.
  o.clamp = false;
  o.factor = 0.1;
  const auto u = glyph(pd, GlyphShape::Cube, o);
  EXPECT_DOUBLE_EQ(u.stats.max_scale, 1.0);
}

TEST(Glyph, HedgehogIsOneLinePerPointToPPlusFactorV) {
  const PolyData pd = three_points_with_vectors();
  GlyphOptions o;
  o.scale = GlyphScale::Vector;
  o.factor = 2;
  const auto [out, stats] = glyph(pd, GlyphShape::Line, o);
  ASSERT_EQ(out.num_points(), 6u);
  ASSERT_EQ(out.lines.size(), 3u);
  EXPECT_EQ(out.polys.size(), 0u);
  EXPECT_FALSE(out.point_data.has("Normals"));
  EXPECT_EQ(at(out, 2), (Vec3{10, 0, 0}));
  EXPECT_EQ(at(out, 3), (Vec3{10, 4, 0}));
  EXPECT_EQ(at(out, 5), (Vec3{0, 10, -6}));
  // The general path with the same line as a custom source gives the same points.
  const auto general = glyph(pd, glyph_source(GlyphShape::Line), o);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(norm(at(general.output, i) - at(out, i)), 0, 1e-6);
  EXPECT_NO_THROW(out.validate());
}

TEST(Glyph, CustomSourceKeepsEveryCellKind) {
  PolyData src;
  src.points.push_back({0, 0, 0});
  src.points.push_back({1, 0, 0});
  src.points.push_back({0, 1, 0});
  src.verts.add({0});
  src.lines.add({0, 1});
  src.polys.add({0, 1, 2});
  src.strips.add({0, 1, 2});
  ImageData img;
  img.dims = {2, 2, 1};  // four points, no arrays: no orientation, size 1
  const auto [out, stats] = glyph(img, src);
  EXPECT_EQ(out.num_points(), 12u);
  EXPECT_EQ(out.verts.size(), 4u);
  EXPECT_EQ(out.lines.size(), 4u);
  EXPECT_EQ(out.polys.size(), 4u);
  EXPECT_EQ(out.strips.size(), 4u);
  EXPECT_EQ(out.polys.cell(3)[2], 11);
  EXPECT_EQ(at(out, 11), (Vec3{1, 2, 0}));  // point (1, 1, 0) + source (0, 1, 0)
  EXPECT_NO_THROW(out.validate());
}

TEST(Glyph, MaskingChoosesTheGlyphedPoints) {
  ImageData img;
  img.dims = {10, 10, 10};
  GlyphOptions o;
  o.mask.random = 37;
  o.mask.seed = 5;
  const auto [out, stats] = glyph(img, GlyphShape::Cone, o);
  EXPECT_EQ(stats.glyphs, 37u);
  EXPECT_EQ(out.num_points(), 37u * 13);
  const auto ids = mask_point_ids(img, o.mask);
  for (std::size_t g = 0; g < 37; ++g) {
    EXPECT_EQ(out.point_data.get("InputPointIds").get(g * 13), static_cast<double>(ids[g]));
  }
}

TEST(Glyph, SameBytesForAnyThreadCount) {
  ImageData img;
  img.dims = {60, 60, 30};  // 108 000 points: many parallel tasks
  DataArray v("V", ScalarType::Float32, 3, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    v.set(i, 0, std::sin(0.1 * static_cast<double>(i)));
    v.set(i, 1, std::cos(0.07 * static_cast<double>(i)));
    v.set(i, 2, 0.3);
  }
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  GlyphOptions o;
  o.scale = GlyphScale::Vector;
  o.mask.every = 3;
  const PolyData two = glyph(img, GlyphShape::Arrow, o).output;
  PolyData one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = glyph(img, GlyphShape::Arrow, o).output;
  }
  EXPECT_EQ(two.num_points(), 36000u * 37);
  EXPECT_TRUE(one == two);
}

TEST(Glyph, BadOptionsAreErrors) {
  const PolyData pd = three_points_with_vectors();
  PolyData bare;
  bare.points.push_back({0, 0, 0});
  GlyphOptions o;
  o.orient = GlyphOrient::Normals;
  test::expect_error([&] { (void)glyph(pd, GlyphShape::Cone, o); },
                     "orient by normals: the input has no active normals");
  o = {};
  o.vectors = "W";
  test::expect_error([&] { (void)glyph(pd, GlyphShape::Cone, o); }, "no point array 'W'");
  o = {};
  o.scalars = "V";
  o.scale = GlyphScale::Scalar;
  o.orient = GlyphOrient::None;
  EXPECT_NO_THROW((void)glyph(pd, GlyphShape::Cone, o));  // a 3-vector scales by its length
  o = {};
  o.factor = std::numeric_limits<double>::infinity();
  test::expect_error([&] { (void)glyph(pd, GlyphShape::Cone, o); }, "factor must be finite");
  o = {};
  o.clamp = true;
  o.scale = GlyphScale::Scalar;
  o.range = std::array<double, 2>{3, 3};
  test::expect_error([&] { (void)glyph(pd, GlyphShape::Cone, o); }, "MIN < MAX");
  o = {};
  o.scale = GlyphScale::Vector;
  test::expect_error([&] { (void)glyph(bare, GlyphShape::Cone, o); },
                     "scale by vector: the input has no active vectors");
  // 8e9 glyphs of 24 points cannot fit: refused before anything is allocated.
  ImageData huge;
  huge.dims = {2000, 2000, 2000};
  test::expect_error([&] { (void)glyph(huge, GlyphShape::Cube); }, "glyph: 8000000000 glyphs of 24 points needs");
  o = {};
  o.mask.every = 2;
  o.mask.voxel = 1;
  test::expect_error([&] { (void)glyph(pd, GlyphShape::Cone, o); }, "exclude each other");
}

// Fig. 1.30 of the VTK textbook: cones along the surface normals of a face (fran_cut), at
// randomly chosen points.
TEST(Glyph, Figure130ConesAlongTheNormalsOfFranCut) {
  const auto face = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/fran_cut.vtk"));
  ASSERT_EQ(face.num_points(), 2205u);
  ASSERT_EQ(face.polys.size(), 4224u);
  // The file's polygons face into the head; the figure's spikes point out (FlipNormals).
  NormalsOptions no;
  no.flip = true;
  const auto [surface, nstats] = compute_normals(face, no);
  EXPECT_EQ(surface.polys.size(), 4224u);
  EXPECT_EQ(nstats.inconsistent_edges, 0u);
  EXPECT_EQ(nstats.surfaces, 1u);
  EXPECT_EQ(nstats.flipped_polygons, 4224u);  // all of them, by the flip alone
  GlyphOptions o;
  o.orient = GlyphOrient::Normals;
  o.factor = 0.01;
  o.mask.random = 220;  // a tenth of the face's 2205 points
  o.mask.seed = 1;
  const auto [cones, stats] = glyph(surface, GlyphShape::Cone, o);
  ASSERT_EQ(stats.glyphs, 220u);
  EXPECT_EQ(cones.num_points(), 220u * 13);
  EXPECT_EQ(cones.polys.size(), 220u * 10);
  EXPECT_EQ(stats.orient_array, "Normals");
  const DataArray& normals = surface.point_data.get("Normals");
  const DataArray& ids = cones.point_data.get("InputPointIds");
  std::set<Index> distinct;
  for (std::size_t g = 0; g < 220; ++g) {
    const auto id = static_cast<std::size_t>(ids.get(g * 13));
    distinct.insert(static_cast<Index>(id));
    const Vec3 p = surface.points[id];
    const Vec3 n{normals.get(id, 0), normals.get(id, 1), normals.get(id, 2)};
    ASSERT_NEAR(norm(n), 1, 1e-6);
    // The cone's axis runs from its base's centre (mean of the cap ring, points 7..12) to the
    // apex (point 0); it is the point's normal, 0.01 long, centred on the point.
    Vec3 base{0, 0, 0};
    for (std::size_t j = 7; j < 13; ++j) base += at(cones, g * 13 + j);
    base = base / 6.0;
    const Vec3 axis = at(cones, g * 13) - base;
    EXPECT_NEAR(norm(axis), 0.01, 1e-6) << g;
    EXPECT_GT(dot(axis / norm(axis), n), 1 - 1e-6) << g;
    EXPECT_NEAR(norm((at(cones, g * 13) + base) / 2.0 - p), 0, 1e-6) << g;
  }
  EXPECT_EQ(distinct.size(), 220u);
  // The face is a shell curving round the head, and the bounding box's centre lies inside the
  // head: flipped (as the textbook's spikeF does), the normals point out of the face, away
  // from that centre, at nearly every point.
  const Bounds b = surface.bounds();
  const Vec3 centre = (b.min + b.max) / 2.0;
  std::size_t away = 0;
  for (std::size_t i = 0; i < surface.num_points(); ++i) {
    const Vec3 n{normals.get(i, 0), normals.get(i, 1), normals.get(i, 2)};
    away += dot(n, surface.points[i] - centre) > 0 ? 1 : 0;
  }
  EXPECT_GT(away, surface.num_points() * 9 / 10);
  EXPECT_NO_THROW(cones.validate());
}
