#include "isoforge/implicit/sample.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

using namespace isoforge;
using F = ImplicitFunction;

TEST(Sample, GridFromBoundsPutsSamplesOnTheCorners) {
  Bounds b;
  b.extend({-1, -2, 0});
  b.extend({1, 2, 4});
  const GridSpec g = GridSpec::from_bounds(b, {5, 9, 3});
  EXPECT_EQ(g.spacing, (Vec3{0.5, 0.5, 2}));
  EXPECT_EQ(g.coordinate(0, 4), 1.0);
  EXPECT_EQ(g.coordinate(1, 8), 2.0);
  EXPECT_THROW((void)GridSpec::from_bounds(b, {0, 2, 2}), Error);
  Bounds flat;
  flat.extend({0, 0, 0});
  flat.extend({1, 1, 0});
  EXPECT_THROW((void)GridSpec::from_bounds(flat, {3, 3, 3}), Error);  // zero z extent, 3 samples
  EXPECT_NO_THROW((void)GridSpec::from_bounds(flat, {3, 3, 1}));
}

TEST(Sample, ValuesEqualPointwiseEvaluation) {
  const F f = ice_cream_cone();
  Bounds b;
  b.extend({-0.1, -0.7, -0.7});
  b.extend({2.0, 0.7, 0.7});
  const GridSpec g = GridSpec::from_bounds(b, {37, 21, 19});  // rows longer than no block size
  const ImageData img = sample_image(f, g);
  ASSERT_EQ(img.dims, g.dims);
  const auto v = img.point_data.scalars()->values<float>();
  ASSERT_EQ(v.size(), img.num_points());
  for (Index k = 0; k < g.dims[2]; ++k)
    for (Index j = 0; j < g.dims[1]; ++j)
      for (Index i = 0; i < g.dims[0]; ++i) {
        const double expect = f.value({g.coordinate(0, i), g.coordinate(1, j), g.coordinate(2, k)});
        ASSERT_EQ(v[static_cast<std::size_t>(img.point_id(i, j, k))], static_cast<float>(expect));
      }
  // Float64 output keeps the doubles.
  SampleOptions o;
  o.type = ScalarType::Float64;
  const ImageData d = sample_image(f, g, o);
  EXPECT_EQ(d.point_data.scalars()->values<double>()[123],
            f.value(d.point(123)));
}

TEST(Sample, DeterministicForAnyThreadCount) {
  const F f = F::torus({0, 0, 0}, {0, 0, 1}, 0.6, 0.2) - F::sphere({0.6, 0, 0}, 0.3);
  Bounds b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  const GridSpec g = GridSpec::from_bounds(b, {64, 64, 64});
  SampleOptions o;
  o.normals = true;
  ImageData one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = sample_image(f, g, o);
  }
  many = sample_image(f, g, o);
  EXPECT_TRUE(one == many);
}

TEST(Sample, NormalsAreUnitGradientsPointingOutward) {
  const F f = F::sphere({0, 0, 0}, 0.5);
  Bounds b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  SampleOptions o;
  o.normals = true;
  o.gradients = true;
  const ImageData img = sample_image(f, GridSpec::from_bounds(b, {9, 9, 9}), o);
  const DataArray* n = img.point_data.normals();
  ASSERT_NE(n, nullptr);
  ASSERT_NE(img.point_data.find("Gradient"), nullptr);
  for (std::size_t id = 0; id < img.num_points(); ++id) {
    const Vec3 p = img.point(static_cast<Index>(id));
    if (norm(p) < 1e-9) continue;
    const Vec3 nn{n->get(id, 0), n->get(id, 1), n->get(id, 2)};
    EXPECT_NEAR(norm(nn), 1.0, 1e-6);
    EXPECT_GT(dot(nn, p), 0);  // outward: toward increasing F
  }
}

TEST(Sample, ProgressAndCancellation) {
  Bounds b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  SampleOptions o;
  int calls = 0;
  double last = 0;
  o.progress = [&](double f) {
    ++calls;
    EXPECT_GE(f, last);
    last = f;
    return true;
  };
  (void)sample_image(F::sphere({0, 0, 0}, 1), GridSpec::from_bounds(b, {16, 16, 64}), o);
  EXPECT_GE(calls, 2);
  EXPECT_EQ(last, 1.0);
  o.progress = [](double) { return false; };
  EXPECT_THROW((void)sample_image(F::sphere({0, 0, 0}, 1), GridSpec::from_bounds(b, {16, 16, 64}), o),
               Cancelled);
}

TEST(Sample, OntoThePointsOfAnyDataset) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({2, 0, 0});
  pd.points.push_back({0, 0, 3});
  const DataArray a = sample_points(F::sphere({0, 0, 0}, 1), pd, "dist");
  EXPECT_EQ(a.name(), "dist");
  EXPECT_EQ(a.tuples(), 3u);
  EXPECT_EQ(a.get(0), -1.0);
  EXPECT_EQ(a.get(1), 1.0);
  EXPECT_EQ(a.get(2), 2.0);
}
