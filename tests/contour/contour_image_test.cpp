#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>

#include "support/result.hpp"
#include "support/surface_checks.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/implicit/sample.hpp"

using namespace isoforge;
using isoforge::test::cube_grid;
using isoforge::test::expect_closed_manifold;
using isoforge::test::signed_volume;
using F = ImplicitFunction;

namespace {

ImageData image_of(Dims dims, const std::vector<float>& values, Vec3 spacing = {1, 1, 1}) {
  ImageData img;
  img.dims = dims;
  img.spacing = spacing;
  img.point_data.add(DataArray::from_vector<float>("s", 1, values), AttributeRole::Scalars);
  return img;
}

// Every closed-surface property the contour promises.


PolyData contour_function(const F& f, double lo, double hi, Index n, ContourOptions o = {}) {
  Bounds b;
  b.extend({lo, lo, lo});
  b.extend({hi, hi, hi});
  return contour_image(sample_image(f, GridSpec::from_bounds(b, {n, n, n})), o).output;
}

}  // namespace

TEST(ContourImage, EveryCubeCaseIsClosedAndManifoldWhenEnclosed) {
  // The 8 corners of the middle voxel of a 4^3 grid take every above/below pattern, with random
  // magnitudes so both resolutions of each ambiguous face occur; all other samples are below,
  // so the surface must close around the above corners.
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> mag(0.05f, 1.0f);
  std::size_t ambiguous = 0;
  for (unsigned c = 0; c < 256; ++c) {
    for (int trial = 0; trial < 12; ++trial) {
      std::vector<float> v(64, -1.0f);
      for (int corner = 0; corner < 8; ++corner) {
        const int i = 1 + (corner & 1), j = 1 + ((corner >> 1) & 1), k = 1 + ((corner >> 2) & 1);
        v[static_cast<std::size_t>(i + 4 * (j + 4 * k))] = ((c >> corner) & 1) ? mag(rng) : -mag(rng);
      }
      ContourStats st;
      const PolyData pd = test::split_result(contour_image(image_of({4, 4, 4}, v), {}), st);
      ambiguous += st.ambiguous_faces;
      if (c == 0) {
        EXPECT_EQ(pd.polys.size(), 0u);
        continue;
      }
      expect_closed_manifold(pd, "case " + std::to_string(c));
      // Normals point toward increasing values, here into the enclosed above region, so the
      // signed volume is negative.
      EXPECT_LT(signed_volume(pd), 0) << "case " << c;
    }
  }
  EXPECT_GT(ambiguous, 0u);
}

TEST(ContourImage, RandomTwoByTwoByTwoBlocksAreCrackFree) {
  // 2x2x2 cells (3^3 samples) of random signs and magnitudes inside a below-valued border:
  // every combination of ambiguous faces between neighbouring cells must still close up.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::bernoulli_distribution coin(0.5);
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<float> v(125, -1.0f);
    for (int k = 1; k <= 3; ++k)
      for (int j = 1; j <= 3; ++j)
        for (int i = 1; i <= 3; ++i) {
          float m = std::abs(u(rng)) + 0.01f;
          v[static_cast<std::size_t>(i + 5 * (j + 5 * k))] = coin(rng) ? m : -m;
        }
    const PolyData pd = contour_image(image_of({5, 5, 5}, v)).output;
    if (pd.polys.empty()) continue;
    expect_closed_manifold(pd, "trial " + std::to_string(trial));
  }
}

TEST(ContourImage, SphereTorusDoubleTorusHaveTheirGenus) {
  const F sphere = F::sphere({0, 0, 0}, 0.8);
  const F torus = F::torus({0, 0, 0}, {0, 0, 1}, 0.55, 0.22);
  const F double_torus = F::torus({-0.45, 0, 0}, {0, 0, 1}, 0.4, 0.15) | F::torus({0.45, 0, 0}, {0, 0, 1}, 0.4, 0.15);
  struct Case { const F* f; long genus; };
  for (const Case& c : {Case{&sphere, 0}, Case{&torus, 1}, Case{&double_torus, 2}}) {
    for (Index n : {24, 33, 64}) {
      const PolyData pd = contour_function(*c.f, -1.05, 1.05, n);
      expect_closed_manifold(pd, "n = " + std::to_string(n));
      const SurfaceTopology t = analyze_topology(pd);
      ASSERT_EQ(t.components.size(), 1u) << "n = " << n;
      EXPECT_EQ(t.components[0].genus, c.genus) << "n = " << n;
    }
  }
}

TEST(ContourImage, SphereVolumeConvergesAtSecondOrder) {
  const double r = 0.7;
  const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  std::vector<double> h, err;
  for (Index n : {17, 33, 65, 129}) {
    const PolyData pd = contour_function(F::sphere({0.013, -0.021, 0.007}, r), -1, 1, n);
    h.push_back(2.0 / static_cast<double>(n - 1));
    err.push_back(std::abs(signed_volume(pd) - exact) / exact);
  }
  // Least-squares slope of log(error) against log(h).
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  const double m = static_cast<double>(h.size());
  const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  EXPECT_GT(slope, 1.8);
  EXPECT_LT(slope, 2.4);
  EXPECT_LT(err.back(), 1e-3);
}

TEST(ContourImage, IntegerDataAtAnIntegerValueStaysManifoldWithoutDegeneracies) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> d(0, 2);
  for (int trial = 0; trial < 40; ++trial) {
    const Index n = 9;
    std::vector<float> v(static_cast<std::size_t>(n * n * n), 0.0f);  // border 0 < 1: closed
    for (Index k = 1; k < n - 1; ++k)
      for (Index j = 1; j < n - 1; ++j)
        for (Index i = 1; i < n - 1; ++i) v[static_cast<std::size_t>(i + n * (j + n * k))] = static_cast<float>(d(rng));
    ContourOptions o;
    o.values = {1.0};  // many samples equal the isovalue exactly
    const PolyData pd = contour_image(image_of({n, n, n}, v), o).output;
    ASSERT_GT(pd.polys.size(), 0u);
    expect_closed_manifold(pd, "trial " + std::to_string(trial));
    // No zero-area triangle and no two points at the same place.
    for (std::size_t c = 0; c < pd.polys.size(); ++c) {
      auto ids = pd.polys.cell(c);
      const Vec3 a = pd.points[static_cast<std::size_t>(ids[0])], b = pd.points[static_cast<std::size_t>(ids[1])],
                 e = pd.points[static_cast<std::size_t>(ids[2])];
      ASSERT_GT(norm2(cross(b - a, e - a)), 0.0) << "trial " << trial;
    }
    std::vector<std::array<double, 3>> pts;
    for (std::size_t i = 0; i < pd.points.size(); ++i) pts.push_back({pd.points[i].x, pd.points[i].y, pd.points[i].z});
    std::sort(pts.begin(), pts.end());
    EXPECT_EQ(std::adjacent_find(pts.begin(), pts.end()), pts.end()) << "trial " << trial;
  }
}

// A NaN sample is undefined: the crossings of its edges are not made, and the triangles that
// would use them are left out (a hole), while every other triangle is as if it were below.
TEST(ContourImage, NaNSamplesLeaveHoles) {
  std::vector<float> v(125, -1.0f);
  v[static_cast<std::size_t>(2 + 5 * (2 + 5 * 2))] = 1.0f;  // one above sample in the middle
  const PolyData full = contour_image(image_of({5, 5, 5}, v)).output;
  expect_closed_manifold(full, "full");
  v[static_cast<std::size_t>(3 + 5 * (2 + 5 * 2))] = std::numeric_limits<float>::quiet_NaN();
  ContourStats st;
  const PolyData pd = test::split_result(contour_image(image_of({5, 5, 5}, v)), st);
  // The full surface less the point on the edge toward the NaN sample and its triangles.
  std::size_t mid = full.points.size();
  for (std::size_t i = 0; i < full.points.size(); ++i) {
    if (full.points[i] == Vec3{2.5, 2, 2}) mid = i;
  }
  ASSERT_LT(mid, full.points.size());
  std::size_t using_mid = 0;
  for (std::size_t c = 0; c < full.polys.size(); ++c) {
    const auto ids = full.polys.cell(c);
    using_mid += std::count(ids.begin(), ids.end(), static_cast<Index>(mid)) > 0 ? 1 : 0;
  }
  EXPECT_GT(using_mid, 0u);
  EXPECT_EQ(pd.points.size(), full.points.size() - 1);
  EXPECT_EQ(pd.polys.size(), full.polys.size() - using_mid);
  EXPECT_EQ(st.points, pd.points.size());
  EXPECT_EQ(st.cells, pd.polys.size());
  const DataArray& s = pd.point_data.get("s");
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    ASSERT_TRUE(is_finite(pd.points[i]));
    ASSERT_TRUE(std::isfinite(s.get(i)));
    ASSERT_NE(pd.points[i], (Vec3{2.5, 2, 2}));
  }
}

// Probed data is NaN outside the probed dataset: the surface ends at the last layer of defined
// samples, with exactly the triangles of the fully defined cells, and nothing undefined.
TEST(ContourImage, NaNRegionEndsTheSurfaceAtTheDefinedSamples) {
  const Index n = 24;
  const ImageData whole = sample_image(F::sphere({0.1, -0.05, 0.02}, 0.7),
                                       GridSpec::from_bounds(Bounds{{-1, -1, -1}, {1, 1, 1}}, {n, n, n}));
  const PolyData full = contour_image(whole).output;
  ImageData holed = whole;
  const Index first = 7;  // samples with i < first are undefined
  auto values = holed.point_data.get(holed.point_data.scalars()->name()).values<float>();
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < first; ++i)
        values[static_cast<std::size_t>(holed.point_id(i, j, k))] = std::numeric_limits<float>::quiet_NaN();
  const PolyData pd = contour_image(holed).output;
  const double x0 = holed.point(first, 0, 0).x;
  // Points of edges between defined samples have x >= x0 (crossings never sit on a sample).
  std::size_t expected = 0;
  for (std::size_t c = 0; c < full.polys.size(); ++c) {
    const auto ids = full.polys.cell(c);
    expected += std::all_of(ids.begin(), ids.end(), [&](Index id) {
                  return full.points[static_cast<std::size_t>(id)].x >= x0 - 1e-6;
                }) ? 1 : 0;
  }
  EXPECT_GT(expected, 100u);
  EXPECT_LT(expected, full.polys.size());
  EXPECT_EQ(pd.polys.size(), expected);
  const DataArray& s = pd.point_data.get(whole.point_data.scalars()->name());
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    ASSERT_TRUE(is_finite(pd.points[i]));
    ASSERT_GE(pd.points[i].x, x0 - 1e-6);
    ASSERT_TRUE(std::isfinite(s.get(i)));
  }
  // Manifold, and the edges used once (the hole's rim) lie in the plane of the first defined
  // layer.
  std::map<std::pair<Index, Index>, int> uses;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    for (std::size_t e = 0; e < 3; ++e) {
      const Index a = ids[e], b = ids[(e + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::size_t rim = 0;
  for (const auto& [e, u] : uses) {
    ASSERT_LE(u, 2);
    if (u == 1) {
      ++rim;
      EXPECT_NEAR(pd.points[static_cast<std::size_t>(e.first)].x, x0, 1e-6);
      EXPECT_NEAR(pd.points[static_cast<std::size_t>(e.second)].x, x0, 1e-6);
    }
  }
  EXPECT_GT(rim, 8u);
}

TEST(ContourImage, DeterministicForAnyThreadCount) {
  const F f = F::torus({0, 0, 0}, {0, 1, 1}, 0.5, 0.2) | F::sphere({0.3, 0.2, 0.1}, 0.35);
  Bounds b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  const ImageData img = sample_image(f, GridSpec::from_bounds(b, {70, 81, 93}));
  ContourOptions o;
  o.values = {-0.1, 0.0, 0.05};
  o.normals = ContourNormals::Gradient;
  PolyData one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = contour_image(img, o).output;
  }
  const PolyData many = contour_image(img, o).output;
  EXPECT_TRUE(one == many);
  // Three isovalues, each tagged.
  const auto& idx = many.point_data.get("IsovalueIndex");
  EXPECT_EQ(idx.range().first, 0);
  EXPECT_EQ(idx.range().second, 2);
}

TEST(ContourImage, InterpolatesPointDataAndCopiesCellData) {
  const Index n = 12;
  Bounds b;
  b.extend({-1, -1, -1});
  b.extend({1, 1, 1});
  ImageData img = sample_image(F::sphere({0, 0, 0}, 0.6), GridSpec::from_bounds(b, {n, n, n}));
  DataArray x("x", ScalarType::Float64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) x.set(i, 0, img.point(static_cast<Index>(i)).x);
  img.point_data.add(std::move(x));
  DataArray vox("voxel", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t i = 0; i < img.num_cells(); ++i) vox.set(i, 0, static_cast<double>(i));
  img.cell_data.add(std::move(vox));
  const PolyData pd = contour_image(img).output;
  const DataArray& xi = pd.point_data.get("x");
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    EXPECT_NEAR(xi.get(i), pd.points[i].x, 1e-6);  // linear fields interpolate exactly
  }
  // The contoured scalar interpolates to the isovalue (to the 1/1024 clamp at most).
  const auto [lo, hi] = pd.point_data.get("F").range();
  EXPECT_LT(std::max(std::abs(lo), std::abs(hi)), 1e-6);
  const DataArray& cv = pd.cell_data.get("voxel");
  const double h = 2.0 / static_cast<double>(n - 1);
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    auto ids = pd.polys.cell(c);
    Vec3 centroid{0, 0, 0};
    for (Index id : ids) centroid += pd.points[static_cast<std::size_t>(id)] / 3.0;
    const auto i = static_cast<Index>(std::floor((centroid.x + 1) / h));
    const auto j = static_cast<Index>(std::floor((centroid.y + 1) / h));
    const auto k = static_cast<Index>(std::floor((centroid.z + 1) / h));
    EXPECT_EQ(static_cast<Index>(cv.get(c)), i + (n - 1) * (j + (n - 1) * k));
  }
}

TEST(ContourImage, NormalsPointTowardIncreasingValuesUnlessFlipped) {
  const F sphere = F::sphere({0, 0, 0}, 0.6);
  for (auto mode : {ContourNormals::Gradient, ContourNormals::Triangles}) {
    for (bool flip : {false, true}) {
      ContourOptions o;
      o.normals = mode;
      o.flip = flip;
      const PolyData pd = contour_function(sphere, -1, 1, 24, o);
      const DataArray* n = pd.point_data.normals();
      ASSERT_NE(n, nullptr);
      for (std::size_t i = 0; i < pd.points.size(); ++i) {
        const Vec3 nn{n->get(i, 0), n->get(i, 1), n->get(i, 2)};
        EXPECT_NEAR(norm(nn), 1.0, 1e-5);
        const double radial = dot(nn, pd.points[i] / norm(pd.points[i]));
        EXPECT_GT(flip ? -radial : radial, 0.9);
      }
      EXPECT_GT(flip ? -signed_volume(pd) : signed_volume(pd), 0);
    }
  }
}

TEST(ContourImage, ProgressAdvancesWithinOneIsovalue) {
  // One isovalue of a 96^3 volume: the counting and generating passes report as they go, not
  // only at the end (a large contour used to sit at 0% until it finished).
  const Index n = 96;
  std::vector<float> v(static_cast<std::size_t>(n * n * n));
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i)
        v[static_cast<std::size_t>(i + n * (j + n * k))] =
            static_cast<float>(std::sin(0.3 * double(i)) + std::sin(0.2 * double(j)) + std::cos(0.25 * double(k)));
  const ImageData img = image_of({n, n, n}, v);
  ContourOptions o;
  o.values = {0.5};
  std::vector<double> seen;
  o.progress = [&](double f) {
    seen.push_back(f);
    return true;
  };
  const ContourResult r = contour(img, o);
  EXPECT_GT(r.stats.cells, 10000u);
  ASSERT_GE(seen.size(), 20u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GT(std::count_if(seen.begin(), seen.end(), [](double f) { return f > 0 && f < 1; }), 10);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  // Cancelling midway stops the contour.
  o.progress = [](double f) { return f < 0.3; };
  EXPECT_THROW((void)contour(img, o), Cancelled);
}

TEST(ContourImage, BadInputIsAClearError) {
  ImageData img = image_of({3, 3, 3}, std::vector<float>(27, 0.0f));
  ContourOptions o;
  o.values = {};
  EXPECT_THROW((void)contour_image(img, o), Error);
  o.values = {std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW((void)contour_image(img, o), Error);
  o.values = {0};
  o.array = "missing";
  try {
    (void)contour_image(img, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'missing'"), std::string::npos);
  }
  img.point_data.add(DataArray("v3", ScalarType::Float32, 3, 27));
  o.array = "v3";
  EXPECT_THROW((void)contour_image(img, o), Error);
}
