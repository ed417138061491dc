// Conversion between OpenVDB grids and image data (sparse/convert.hpp).

#include "isoforge/sparse/convert.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "isoforge/sparse/grid.hpp"
#include "support/expect_error.hpp"
#include "support/sample_datasets.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

TEST(SparseConvert, VoxelCentersMapToImagePoints) {
  ensure_openvdb_initialized();
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName("g");
  auto xf = openvdb::math::Transform::createLinearTransform(0.5);
  xf->postTranslate(openvdb::Vec3d(10, 20, 30));
  g->setTransform(xf);
  g->tree().setValue(openvdb::Coord(2, -1, 4), 1.0f);
  g->tree().setValue(openvdb::Coord(4, 0, 4), 2.0f);
  const ImageData img = vdb_to_image(*g);
  EXPECT_EQ(img.dims, (Dims{3, 2, 1}));
  EXPECT_EQ(img.origin, (Vec3{11, 19.5, 32}));  // index (2, -1, 4) * 0.5 + (10, 20, 30)
  EXPECT_EQ(img.spacing, (Vec3{0.5, 0.5, 0.5}));
  const DataArray& a = img.point_data.get("g");
  EXPECT_EQ(a.get(static_cast<std::size_t>(img.point_id(0, 0, 0))), 1.0);
  EXPECT_EQ(a.get(static_cast<std::size_t>(img.point_id(2, 1, 0))), 2.0);
  EXPECT_EQ(a.get(static_cast<std::size_t>(img.point_id(1, 0, 0))), 0.0);  // background
}

TEST(SparseConvert, ToleranceLeavesValuesNearBackgroundInactive) {
  ImageData img;
  img.dims = {3, 2, 2};
  img.origin = {1, 2, 3};
  img.spacing = {0.5, 0.5, 0.5};
  const std::vector<float> v = {0, 0.05f, -0.05f, 0.1f, 0.2f, -0.3f, 1, 0, 0.099f, -0.1f, 0.5f, 2};
  img.point_data.add(DataArray::from_vector("f", 1, v), AttributeRole::Scalars);
  // |v - 0| > 0.1 for 0.2, -0.3, 1, 0.5, 2.
  auto g = image_to_vdb(img, {"f", 0.0f, 0.1f});
  EXPECT_EQ(g->activeVoxelCount(), 5u);
  // Tolerance 0: everything but the two exact zeros.
  EXPECT_EQ(image_to_vdb(img, {"f", 0.0f, 0.0f})->activeVoxelCount(), 10u);
  // Another background: |v - 1| <= 0.5 leaves 0.5 and 1 inactive (and 0.99... none).
  EXPECT_EQ(image_to_vdb(img, {"f", 1.0f, 0.5f})->activeVoxelCount(), 10u);
  // Densifying puts the background where voxels are inactive.
  const ImageData back = vdb_to_image(*g);
  EXPECT_EQ(back.dims, (Dims{3, 2, 2}));  // 0.2 at (1,1,0) ... 2 at (2,1,1): full box
  const DataArray& a = back.point_data.get("f");
  for (std::size_t i = 0; i < v.size(); ++i) {
    const float expect = std::abs(v[i]) > 0.1f ? v[i] : 0.0f;
    EXPECT_EQ(a.get(i), expect) << i;
  }
}

TEST(SparseConvert, PruningOnTheSphereReducesTheActiveCount) {
  const ImageData img = test::sphere_distance_image();
  const auto& vals = img.point_data.get("distance").values<float>();
  for (float tol : {0.0f, 0.25f, 0.5f, 1.0f}) {
    std::size_t expect = 0;
    for (float x : vals) expect += std::abs(x) > tol ? 1 : 0;
    EXPECT_EQ(image_to_vdb(img, {{}, 0.0f, tol})->activeVoxelCount(), expect) << tol;
  }
}

TEST(SparseConvert, ConversionPreconditions) {
  ImageData img = test::sphere_distance_image();
  img.spacing = {0.2, 0.2, 0.3};
  expect_error([&] { (void)image_to_vdb(img); }, "equal positive spacing on all axes");
  img.spacing = {-0.2, -0.2, -0.2};
  expect_error([&] { (void)image_to_vdb(img); }, "equal positive spacing");
  img = test::sphere_distance_image();
  expect_error([&] { (void)image_to_vdb(img, {"missing"}); }, "no point array 'missing'");
  img.point_data.add(DataArray("vec", ScalarType::Float32, 3, img.num_points()));
  expect_error([&] { (void)image_to_vdb(img, {"vec"}); }, "array 'vec' has 3 components");
  expect_error([&] { (void)image_to_vdb(img, {{}, 0.0f, -1.0f}); }, "tolerance");
  expect_error([&] { (void)image_to_vdb(img, {{}, NAN}); }, "background is not finite");
  ImageData bare;
  bare.dims = {2, 2, 2};
  bare.point_data.add(DataArray("x", ScalarType::Float32, 1, 8));
  expect_error([&] { (void)image_to_vdb(bare); }, "no active point scalars");

  // Too many voxels.
  auto g = image_to_vdb(test::sphere_distance_image(), {{}, -1000.0f, 0.0f});
  expect_error([&] { (void)vdb_to_image(*g, 1000); },
               "active bounding box 24 x 20 x 18 = 8640 voxels exceeds the limit of 1000");
  EXPECT_NO_THROW((void)vdb_to_image(*g, 8640));
  // Non-uniform and rotated transforms.
  auto h = g->deepCopy();
  h->setTransform(openvdb::math::Transform::createLinearTransform(
      openvdb::Mat4d(openvdb::Vec4d(1, 0, 0, 0), openvdb::Vec4d(0, 2, 0, 0),
                     openvdb::Vec4d(0, 0, 1, 0), openvdb::Vec4d(0, 0, 0, 1))));
  expect_error([&] { (void)vdb_to_image(*h); }, "not a uniform scale + translation");
  h->transform().postRotate(0.3, openvdb::math::Z_AXIS);
  expect_error([&] { (void)vdb_to_image(*h); }, "not a uniform scale + translation");
  auto empty = openvdb::FloatGrid::create();
  empty->setName("e");
  expect_error([&] { (void)vdb_to_image(*empty); }, "grid 'e': the grid has no active voxels");
}
