#include "isoforge/filters/subsample.hpp"

#include <gtest/gtest.h>

#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

/// Options without designated initializers (GCC warns about the members left out).
SubsampleOptions opts(std::array<Index, 3> rate, std::optional<Voi> voi = {}, bool boundary = false) {
  SubsampleOptions o;
  o.rate = rate;
  o.voi = voi;
  o.include_boundary = boundary;
  return o;
}

ImageData numbered_image(Dims dims) {
  ImageData img;
  img.dims = dims;
  img.origin = {1, 2, 3};
  img.spacing = {0.5, 1, 2};
  DataArray id("id", ScalarType::Int64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) id.set(i, 0, double(i));
  img.point_data.add(std::move(id), AttributeRole::Scalars);
  DataArray cid("cell", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t i = 0; i < img.num_cells(); ++i) cid.set(i, 0, double(i));
  img.cell_data.add(std::move(cid));
  return img;
}

}  // namespace

TEST(Subsample, ImageEveryOtherPoint) {
  const ImageData img = numbered_image({5, 4, 3});
  const ImageData out = subsample(img, opts({2, 3, 1}));
  // i: 0 2 4 (3 points), j: 0 3 (2), k: 0 1 2 (3).
  EXPECT_EQ(out.dims, (Dims{3, 2, 3}));
  EXPECT_EQ(out.origin, img.origin);
  EXPECT_EQ(out.spacing, (Vec3{1, 3, 2}));
  const DataArray& id = out.point_data.get("id");
  // Output point (1, 1, 2) is input point (2, 3, 2) = 2 + 5 (3 + 4 * 2) = 57.
  EXPECT_EQ(id.get(std::size_t(out.point_id(1, 1, 2))), 57);
  EXPECT_EQ(out.point_data.active_name(AttributeRole::Scalars), "id");
  // Output cell (1, 0, 1) takes input cell (2, 0, 1) = 2 + 4 (0 + 3 * 1) = 14.
  EXPECT_EQ(out.cell_data.get("cell").get(1 + 2 * (0 + 1 * 1)), 14);
  // Every output point sits where its input point was.
  for (Index k = 0; k < 3; ++k)
    for (Index j = 0; j < 2; ++j)
      for (Index i = 0; i < 3; ++i)
        EXPECT_EQ(out.point(i, j, k), img.point(2 * i, 3 * j, k));
}

TEST(Subsample, ImageVoiMovesTheOrigin) {
  const ImageData img = numbered_image({6, 6, 6});
  const ImageData out = subsample(img, opts({2, 2, 2}, Voi{1, 4, 2, 2, 0, 5}));
  EXPECT_EQ(out.dims, (Dims{2, 1, 3}));  // i 1 3, j 2, k 0 2 4
  EXPECT_EQ(out.origin, img.point(1, 2, 0));
  EXPECT_EQ(out.point_data.get("id").get(std::size_t(out.point_id(1, 0, 2))),
            double(img.point_id(3, 2, 4)));
  EXPECT_EQ(out.num_cells(), 2u);  // a 2 x 1 x 3 plane of pixels
  EXPECT_EQ(out.cell_data.get("cell").tuples(), 2u);
  // Cell (0, -, 1) of the plane: input cell (1, 2, 2).
  EXPECT_EQ(out.cell_data.get("cell").get(1), double(1 + 5 * (2 + 5 * 2)));
}

TEST(Subsample, BadRatesAndVoisAreErrors) {
  const ImageData img = numbered_image({4, 4, 4});
  EXPECT_THROW((void)subsample(img, opts({0, 1, 1})), Error);
  EXPECT_THROW((void)subsample(img, opts({1, 1, 1}, Voi{0, 4, 0, 3, 0, 3})), Error);   // i1 = dims
  EXPECT_THROW((void)subsample(img, opts({1, 1, 1}, Voi{2, 1, 0, 3, 0, 3})), Error);   // inverted
  EXPECT_THROW((void)subsample(img, opts({1, 1, 1}, Voi{-1, 1, 0, 3, 0, 3})), Error);  // negative
  EXPECT_THROW((void)subsample(img, opts({1, 1, 1}, {}, true)), Error);
  PolyData pd;
  EXPECT_THROW((void)subsample(DatasetRef(pd), SubsampleOptions{}), Error);
}

TEST(Subsample, StructuredGridWithBoundary) {
  StructuredGrid g;
  g.dims = {5, 3, 2};
  g.points = Points(30, ScalarType::Float64);
  for (Index k = 0; k < 2; ++k)
    for (Index j = 0; j < 3; ++j)
      for (Index i = 0; i < 5; ++i)
        g.points.set(std::size_t(g.point_id(i, j, k)), {double(i * i), double(j), double(k) + 0.1 * double(i)});
  DataArray v("v", ScalarType::Float32, 3, 30);
  for (std::size_t i = 0; i < 30; ++i) v.set(i, 2, double(i));
  g.point_data.add(std::move(v), AttributeRole::Vectors);
  const StructuredGrid a = extract_voi(g, opts({3, 2, 1}));
  EXPECT_EQ(a.dims, (Dims{2, 2, 2}));  // i 0 3, j 0 2
  EXPECT_EQ(a.points[1], g.points[3]);
  EXPECT_EQ(a.points.type(), ScalarType::Float64);
  const StructuredGrid b = extract_voi(g, opts({3, 2, 1}, {}, true));
  EXPECT_EQ(b.dims, (Dims{3, 2, 2}));  // i 0 3 4
  EXPECT_EQ(b.points[2], g.points[4]);
  EXPECT_EQ(b.point_data.get("v").get(std::size_t(b.point_id(2, 1, 1)), 2),
            double(g.point_id(4, 2, 1)));
  EXPECT_EQ(b.point_data.active_name(AttributeRole::Vectors), "v");
  EXPECT_NO_THROW(b.validate());
}

TEST(Subsample, Figure136CombustorEveryOtherPoint) {
  // The combustor (57 x 33 x 25) at rate 2: 29 x 17 x 13 points, each one of the input's.
  ReadOptions ro;
  ro.plot3d_q = ISOFORGE_DATA_DIR "/combq.bin";
  const auto grid = std::get<StructuredGrid>(read(ISOFORGE_DATA_DIR "/combxyz.bin", ro));
  const Dataset out = subsample(grid, opts({2, 2, 2}));
  const auto& g = std::get<StructuredGrid>(out);
  EXPECT_EQ(g.dims, (Dims{29, 17, 13}));
  EXPECT_EQ(g.point_data.size(), grid.point_data.size());
  const DataArray& rho = g.point_data.get("Density");
  for (Index k = 0; k < 13; ++k)
    for (Index j = 0; j < 17; ++j)
      for (Index i = 0; i < 29; ++i) {
        const auto o = std::size_t(g.point_id(i, j, k)), in = std::size_t(grid.point_id(2 * i, 2 * j, 2 * k));
        ASSERT_EQ(g.points[o], grid.points[in]);
        ASSERT_EQ(rho.get(o), grid.point_data.get("Density").get(in));
      }
}
