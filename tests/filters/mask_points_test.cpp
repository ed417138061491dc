#include "isoforge/filters/mask_points.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "support/expect_error.hpp"

using namespace isoforge;

namespace {

PolyData line_of_points(std::size_t n) {
  PolyData pd;
  DataArray s("s", ScalarType::Float64, 1, n);
  for (std::size_t i = 0; i < n; ++i) {
    pd.points.push_back({static_cast<double>(i), 0, 0});
    s.set(i, 0, 10.0 * static_cast<double>(i));
  }
  pd.point_data.add(std::move(s), AttributeRole::Scalars);
  return pd;
}

}  // namespace

TEST(MaskPoints, EveryNthKeepsIdsZeroNTwoN) {
  const PolyData pd = line_of_points(10);
  MaskOptions o;
  o.every = 3;
  EXPECT_EQ(mask_point_ids(pd, o), (std::vector<Index>{0, 3, 6, 9}));
  o.every = 1;  // 1 keeps everything, like 0
  EXPECT_EQ(mask_point_ids(pd, o).size(), 10u);
}

TEST(MaskPoints, MaxPointsSpreadsOverTheKeptOnes) {
  const PolyData pd = line_of_points(10);
  MaskOptions o;
  o.max_points = 4;  // kept[floor(i * 10 / 4)] for i = 0..3
  EXPECT_EQ(mask_point_ids(pd, o), (std::vector<Index>{0, 2, 5, 7}));
  o.every = 2;       // 0 2 4 6 8, then at most 4: kept[0, 1, 2, 3] (floor(i * 5 / 4))
  EXPECT_EQ(mask_point_ids(pd, o), (std::vector<Index>{0, 2, 4, 6}));
}

TEST(MaskPoints, RandomIsExactSeededAndUniform) {
  const PolyData pd = line_of_points(100);
  MaskOptions o;
  o.random = 10;
  o.seed = 42;
  const auto a = mask_point_ids(pd, o);
  ASSERT_EQ(a.size(), 10u);
  EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
  EXPECT_EQ(std::set<Index>(a.begin(), a.end()).size(), 10u);  // distinct
  EXPECT_EQ(mask_point_ids(pd, o), a);                         // same seed, same points
  o.seed = 43;
  EXPECT_NE(mask_point_ids(pd, o), a);
  // Over 2000 seeds every id is kept about 2000 * 10 / 100 = 200 times (binomial, sd ~13.4);
  // +-70 is more than 5 sd, so a correct sampler passes and a biased one (e.g. always the
  // first ids) fails.
  std::vector<int> hits(100, 0);
  for (std::uint64_t seed = 0; seed < 2000; ++seed) {
    o.seed = seed;
    for (const Index id : mask_point_ids(pd, o)) ++hits[static_cast<std::size_t>(id)];
  }
  for (int h : hits) {
    EXPECT_GT(h, 130);
    EXPECT_LT(h, 270);
  }
  o.random = 1000;  // more than there are: all of them
  EXPECT_EQ(mask_point_ids(pd, o).size(), 100u);
}

TEST(MaskPoints, VoxelKeepsTheLowestIdPerCell) {
  ImageData img;
  img.dims = {4, 4, 1};  // points at x, y in {0, 1, 2, 3}
  MaskOptions o;
  o.voxel = 2;  // cells [0, 2) and [2, 4) per axis: 4 cells, lowest ids 0, 2, 8, 10
  EXPECT_EQ(mask_point_ids(img, o), (std::vector<Index>{0, 2, 8, 10}));
  o.voxel = 10;  // one cell
  EXPECT_EQ(mask_point_ids(img, o), (std::vector<Index>{0}));
  o.voxel = 0.5;  // one point per cell: all
  EXPECT_EQ(mask_point_ids(img, o).size(), 16u);
}

TEST(MaskPoints, PolyDataOfVerticesWithAttributesCarried) {
  const PolyData pd = line_of_points(10);
  MaskOptions o;
  o.every = 4;
  const PolyData out = mask_points(pd, o);
  ASSERT_EQ(out.num_points(), 3u);  // 0, 4, 8
  EXPECT_EQ(out.verts.size(), 3u);
  EXPECT_EQ(out.num_cells(), 3u);
  EXPECT_EQ(out.points[1], (Vec3{4, 0, 0}));
  EXPECT_EQ(out.point_data.get("s").get(2), 80.0);
  EXPECT_EQ(out.point_data.active_name(AttributeRole::Scalars), "s");
  EXPECT_EQ(out.point_data.get("OriginalPointIds").get(2), 8.0);
  EXPECT_NO_THROW(out.validate());
}

TEST(MaskPoints, AnyDatasetType) {
  StructuredGrid sg;
  sg.dims = {3, 1, 1};
  for (int i = 0; i < 3; ++i) sg.points.push_back({0, static_cast<double>(i), 0});
  MaskOptions o;
  o.every = 2;
  const PolyData a = mask_points(sg, o);
  ASSERT_EQ(a.num_points(), 2u);
  EXPECT_EQ(a.points[1], (Vec3{0, 2, 0}));
  UnstructuredGrid ug;
  for (int i = 0; i < 5; ++i) ug.points.push_back({static_cast<double>(i), 1, 0});
  ug.add_cell(CellType::PolyVertex, {0, 1, 2, 3, 4});
  const PolyData b = mask_points(ug, o);
  EXPECT_EQ(b.num_points(), 3u);
  EXPECT_EQ(b.points[2], (Vec3{4, 1, 0}));
}

TEST(MaskPoints, ContradictoryOrBadOptionsAreErrors) {
  const PolyData pd = line_of_points(5);
  MaskOptions o;
  o.every = 2;
  o.random = 3;
  test::expect_error([&] { (void)mask_point_ids(pd, o); }, "exclude each other");
  MaskOptions v;
  v.voxel = -1;
  test::expect_error([&] { (void)mask_point_ids(pd, v); }, "voxel must be a finite size");
  v.voxel = std::numeric_limits<double>::quiet_NaN();
  test::expect_error([&] { (void)mask_point_ids(pd, v); }, "voxel must be a finite size");
  v.voxel = 1e-300;  // 5 / 1e-300 cells along x: too many to number
  test::expect_error([&] { (void)mask_point_ids(pd, v); }, "too small");
}
