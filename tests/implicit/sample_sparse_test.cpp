#include "support/result.hpp"
#include "support/surface_checks.hpp"
#include "isoforge/implicit/sample_sparse.hpp"

#include <gtest/gtest.h>

#include <string>
#include <tbb/global_control.h>

#include <cmath>

using namespace isoforge;
using isoforge::test::cube_grid;
using isoforge::test::expect_closed_manifold;
using isoforge::test::signed_volume;
using F = ImplicitFunction;

namespace {


}  // namespace

TEST(SparseSample, BandEqualsDenseSamplesExactly) {
  const F f = ice_cream_cone();
  Bounds b;
  b.extend({-0.1, -0.7, -0.7});
  const double h = 2.1 / 80;
  GridSpec g;
  g.origin = b.min;
  g.spacing = {h, h, h};
  g.dims = {81, 54, 54};
  SparseSampleOptions o;
  o.half_width = 3;
  SparseSampleStats stats;
  const auto grid = test::split_result(sample_level_set(f, g, o), stats);
  const ImageData dense = sample_image(f, g);
  const auto v = dense.point_data.scalars()->values<float>();
  const double band = 3 * h;
  auto acc = grid->getConstAccessor();
  std::size_t expected_active = 0;
  for (Index k = 0; k < g.dims[2]; ++k)
    for (Index j = 0; j < g.dims[1]; ++j)
      for (Index i = 0; i < g.dims[0]; ++i) {
        const float d = v[static_cast<std::size_t>(dense.point_id(i, j, k))];
        const openvdb::Coord c(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
        // Dense values are evaluated in double and rounded like the sparse ones: compare the
        // double-precision band decision through the float value's sign and magnitude.
        const bool in_band = std::abs(f.value(dense.point(dense.point_id(i, j, k)))) < band;
        ASSERT_EQ(acc.isValueOn(c), in_band) << i << " " << j << " " << k;
        if (in_band) {
          ++expected_active;
          ASSERT_EQ(acc.getValue(c), d);  // bit-identical on the band
        } else {
          ASSERT_EQ(std::signbit(acc.getValue(c)), std::signbit(d)) << i << " " << j << " " << k;
          ASSERT_EQ(std::abs(acc.getValue(c)), static_cast<float>(band));
        }
      }
  EXPECT_EQ(stats.active_voxels, expected_active);
  EXPECT_EQ(grid->activeVoxelCount(), expected_active);
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_FLOAT_EQ(grid->background(), static_cast<float>(band));
  EXPECT_DOUBLE_EQ(grid->voxelSize()[0], h);
}

TEST(SparseSample, SkipsFarRegionsAndTilesTheInside) {
  // A sphere of radius 0.8 in [-1, 1]^3 at 513^3: most 8^3 blocks are culled.
  const GridSpec g = cube_grid(-1, 1, 513);
  SparseSampleStats stats;
  const auto grid = test::split_result(sample_level_set(F::sphere({0, 0, 0}, 0.8), g, {}), stats);
  const double voxels = 513.0 * 513.0 * 513.0;
  // The band (6 voxels) plus the 8-voxel leaves around a 205-voxel-radius sphere is about 6% of
  // the volume; without culling it would be all of it.
  EXPECT_LT(static_cast<double>(stats.evaluated_voxels), 0.08 * voxels);
  EXPECT_GT(stats.inside_tiles, 0u);
  // Deep inside reads -background, far outside +background.
  auto acc = grid->getConstAccessor();
  EXPECT_EQ(acc.getValue(openvdb::Coord(256, 256, 256)), -grid->background());
  EXPECT_EQ(acc.getValue(openvdb::Coord(2, 2, 2)), grid->background());
}

TEST(SparseSample, MemoryScalesWithAreaNotVolume) {
  const F f = F::torus({0, 0, 0}, {0, 0, 1}, 0.6, 0.25);
  SparseSampleStats s1, s2;
  (void)test::split_result(sample_level_set(f, cube_grid(-1, 1, 257), {}), s1);
  (void)test::split_result(sample_level_set(f, cube_grid(-1, 1, 513), {}), s2);
  const double ratio = static_cast<double>(s2.active_voxels) / static_cast<double>(s1.active_voxels);
  EXPECT_GT(ratio, 3.5);  // doubling the resolution: area x4 (volume would be x8)
  EXPECT_LT(ratio, 4.5);
  const double mem_ratio = static_cast<double>(s2.memory_bytes) / static_cast<double>(s1.memory_bytes);
  EXPECT_LT(mem_ratio, 5.0);
}

TEST(SparseSample, DeterministicForAnyThreadCount) {
  const F f = F::box({-0.5, -0.4, -0.3}, {0.5, 0.4, 0.3}) - F::sphere({0.5, 0.4, 0.3}, 0.35);
  const GridSpec g = cube_grid(-1, 1, 150);
  openvdb::FloatGrid::Ptr one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = sample_level_set(f, g).output;
  }
  const auto many = sample_level_set(f, g).output;
  ASSERT_EQ(one->activeVoxelCount(), many->activeVoxelCount());
  auto a = one->getConstAccessor();
  for (auto it = many->cbeginValueOn(); it; ++it) {
    ASSERT_EQ(a.getValue(it.getCoord()), *it);
    ASSERT_TRUE(a.isValueOn(it.getCoord()));
  }
}

TEST(SparseSample, BadOptionsAreErrors) {
  GridSpec g = cube_grid(-1, 1, 16);
  g.spacing.y *= 2;
  EXPECT_THROW((void)sample_level_set(F::sphere({0, 0, 0}, 1), g), Error);
  SparseSampleOptions o;
  o.half_width = 0;
  EXPECT_THROW((void)sample_level_set(F::sphere({0, 0, 0}, 1), cube_grid(-1, 1, 16), o), Error);
  // Voxels smaller than OpenVDB's transforms accept: isoforge's Error, naming the voxel size.
  GridSpec tiny = cube_grid(-1e-6, 1e-6, 16);
  try {
    (void)sample_level_set(F::sphere({0, 0, 0}, 1e-6), tiny);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("OpenVDB cannot use the voxel size"), std::string::npos)
        << e.what();
  }
}
