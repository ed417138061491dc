#include "isoforge/implicit/select.hpp"
#include "isoforge/filters/shrink.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace isoforge;
using F = ImplicitFunction;

namespace {

// 10 x 10 x 10 voxels on [0, 1]^3 (11^3 points), with point and cell data.
ImageData voxel_grid() {
  ImageData img;
  img.dims = {11, 11, 11};
  img.spacing = {0.1, 0.1, 0.1};
  DataArray s("s", ScalarType::Float32, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) s.set(i, 0, static_cast<double>(i));
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  DataArray c("c", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t i = 0; i < img.num_cells(); ++i) c.set(i, 0, static_cast<double>(i));
  img.cell_data.add(std::move(c));
  return img;
}

}  // namespace

TEST(Select, VoxelsInsideASphereCountedIndependently) {
  const ImageData img = voxel_grid();
  const Vec3 center{0.5, 0.5, 0.5};
  const double r = 0.42;
  // Independent count: a voxel is inside when all 8 corners are within r of the center.
  std::size_t all = 0, any = 0;
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) {
        int in = 0;
        for (int c = 0; c < 8; ++c) {
          const Vec3 p{0.1 * (i + (c & 1)), 0.1 * (j + ((c >> 1) & 1)), 0.1 * (k + ((c >> 2) & 1))};
          in += norm(p - center) <= r ? 1 : 0;
        }
        all += in == 8 ? 1 : 0;
        any += in > 0 ? 1 : 0;
      }
  ASSERT_GT(all, 0u);
  const F sphere = F::sphere(center, r);
  const UnstructuredGrid inside = extract_cells(img, sphere);
  EXPECT_EQ(inside.num_cells(), all);
  SelectOptions boundary;
  boundary.any_point = true;
  EXPECT_EQ(extract_cells(img, sphere, boundary).num_cells(), any);
  SelectOptions outside;
  outside.inside = false;
  // Outside cells have all 8 points outside: the complement of "any point inside".
  EXPECT_EQ(extract_cells(img, sphere, outside).num_cells(), 1000 - any);
  EXPECT_NO_THROW(inside.validate());
  for (auto t : inside.types) EXPECT_EQ(t, CellType::Voxel);
}

TEST(Select, CarriesDataAndOriginalIds) {
  const ImageData img = voxel_grid();
  const UnstructuredGrid out = extract_cells(img, F::box({-1, -1, -1}, {0.15, 0.15, 0.15}));
  // Only voxel (0, 0, 0) has all corners in [0, 0.15]^3... corners at 0 and 0.1: yes.
  ASSERT_EQ(out.num_cells(), 1u);
  ASSERT_EQ(out.num_points(), 8u);
  const auto& pid = out.point_data.get("OriginalPointIds");
  const auto& s = out.point_data.get("s");
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(s.get(i), pid.get(i));  // s was the point id
    // Points are stored as float32 (the default), so compare with the rounded coordinates.
    const Vec3 p = img.point(static_cast<Index>(pid.get(i)));
    const float fx = static_cast<float>(p.x), fy = static_cast<float>(p.y), fz = static_cast<float>(p.z);
    EXPECT_EQ(out.points[i].x, fx);
    EXPECT_EQ(out.points[i].y, fy);
    EXPECT_EQ(out.points[i].z, fz);
  }
  EXPECT_EQ(out.cell_data.get("OriginalCellIds").get(0), 0.0);
  EXPECT_EQ(out.cell_data.get("c").get(0), 0.0);
  EXPECT_EQ(out.point_data.scalars()->name(), "s");
}

TEST(Select, Figure124aPixelsInsideAnEllipse) {
  // A 2D image of 40 x 30 pixels and the ellipse (x/0.8)^2 + (y/0.5)^2 = 1 as a quadric.
  ImageData img;
  img.dims = {41, 31, 1};
  img.origin = {-1, -0.75, 0};
  img.spacing = {0.05, 0.05, 1};
  const F ellipse = F::quadric({1 / 0.64, 1 / 0.25, 0, 0, 0, 0, 0, 0, 0, -1});
  std::size_t expected = 0;
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 40; ++i) {
      bool all = true;
      for (int c = 0; c < 4; ++c) {
        const double x = -1 + 0.05 * (i + (c & 1)), y = -0.75 + 0.05 * (j + (c >> 1));
        all = all && (x * x / 0.64 + y * y / 0.25 - 1 <= 0);
      }
      expected += all ? 1 : 0;
    }
  const UnstructuredGrid out = extract_cells(img, ellipse);
  EXPECT_EQ(out.num_cells(), expected);
  EXPECT_GT(expected, 400u);  // the ellipse covers most of its 1.6 x 1.0 box
  for (auto t : out.types) EXPECT_EQ(t, CellType::Pixel);
}

TEST(Select, WorksOnUnstructuredAndPolyData) {
  PolyData pd;
  for (int i = 0; i < 4; ++i) pd.points.push_back({double(i), 0, 0});
  pd.lines.add({0, 1});
  pd.lines.add({1, 2});
  pd.lines.add({2, 3});
  const UnstructuredGrid out = extract_cells(pd, F::plane({1.5, 0, 0}, {1, 0, 0}));
  EXPECT_EQ(out.num_cells(), 1u);  // only the segment 0-1 lies at x <= 1.5
  EXPECT_EQ(out.num_points(), 2u);
}

TEST(Select, Figure124bVoxelsInTheUnionOfTwoEllipsoidsShrunk) {
  // 20^3 voxels on [-1, 1]^3; the union of two ellipsoids (scaled unit spheres) crossing at the
  // origin, as in the chapter's Fig. 1.24b; selected voxels shrunk 50%.
  ImageData img;
  img.dims = {21, 21, 21};
  img.origin = {-1, -1, -1};
  img.spacing = {0.1, 0.1, 0.1};
  const Vec3 a{0.83, 0.41, 0.41}, b{0.41, 0.83, 0.41};
  const F both = F::sphere({0, 0, 0}, 1).transformed(Affine::scaling(a)) |
                 F::sphere({0, 0, 0}, 1).transformed(Affine::scaling(b));
  auto inside = [](const Vec3& p, const Vec3& s) {
    return (p.x / s.x) * (p.x / s.x) + (p.y / s.y) * (p.y / s.y) + (p.z / s.z) * (p.z / s.z) <= 1;
  };
  std::size_t expected = 0;
  for (Index k = 0; k < 20; ++k)
    for (Index j = 0; j < 20; ++j)
      for (Index i = 0; i < 20; ++i) {
        bool all = true;
        for (int c = 0; c < 8; ++c) {
          const Vec3 p = img.point(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          all = all && (inside(p, a) || inside(p, b));
        }
        expected += all ? 1 : 0;
      }
  const UnstructuredGrid selected = extract_cells(img, both);
  EXPECT_EQ(selected.num_cells(), expected);
  EXPECT_GT(expected, 100u);
  const UnstructuredGrid shrunk = shrink(selected, 0.5);
  ASSERT_EQ(shrunk.num_cells(), expected);
  EXPECT_EQ(shrunk.num_points(), 8 * expected);
  for (std::size_t c = 0; c < shrunk.num_cells(); ++c) {
    Bounds cb;
    for (Index id : shrunk.cells.cell(c)) cb.extend(shrunk.points[static_cast<std::size_t>(id)]);
    EXPECT_NEAR(cb.size().x, 0.05, 1e-6);  // half of the 0.1 spacing (float32 points)
    EXPECT_NEAR(cb.size().y, 0.05, 1e-6);
    EXPECT_NEAR(cb.size().z, 0.05, 1e-6);
  }
}
