#include "isoforge/filters/shrink.hpp"

#include <gtest/gtest.h>

using namespace isoforge;

TEST(Shrink, HalvesEveryCellAboutItsCentroid) {
  ImageData img;
  img.dims = {3, 2, 2};  // two unit voxels
  DataArray s("s", ScalarType::Float64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) s.set(i, 0, static_cast<double>(i) * 10);
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  img.cell_data.add(DataArray::from_vector<std::int32_t>("c", 1, {7, 9}));
  const UnstructuredGrid out = shrink(img, 0.5);
  ASSERT_EQ(out.num_cells(), 2u);
  ASSERT_EQ(out.num_points(), 16u);  // every cell owns its points
  EXPECT_EQ(out.cell_data.get("c").get(1), 9.0);
  // Cell 1 spans [1, 2] x [0, 1] x [0, 1]: centroid (1.5, .5, .5), shrunk corners at +-0.25.
  const auto ids = out.cells.cell(1);
  for (Index id : ids) {
    const Vec3 p = out.points[static_cast<std::size_t>(id)];
    EXPECT_DOUBLE_EQ(std::abs(p.x - 1.5), 0.25);
    EXPECT_DOUBLE_EQ(std::abs(p.y - 0.5), 0.25);
    EXPECT_DOUBLE_EQ(std::abs(p.z - 0.5), 0.25);
  }
  // Point data follows the points: the first point of cell 1 is image point 1 (s = 10).
  EXPECT_EQ(out.point_data.get("s").get(static_cast<std::size_t>(ids[0])), 10.0);
  EXPECT_NO_THROW(out.validate());
}

TEST(Shrink, FactorOneIsIdentityAndBadFactorsAreErrors) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({1, 0, 0});
  pd.points.push_back({0, 1, 0});
  pd.polys.add({0, 1, 2});
  const UnstructuredGrid same = shrink(pd, 1.0);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(same.points[i], pd.points[i]);
  EXPECT_THROW((void)shrink(pd, 1.5), Error);
  EXPECT_THROW((void)shrink(pd, -0.1), Error);
}
