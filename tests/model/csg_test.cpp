#include "isoforge/model/csg_sparse.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "isoforge/core/closest_point.hpp"
#include "isoforge/model/distance_sparse.hpp"

using namespace isoforge;

namespace {

GridSpec cube_grid(double lo, double hi, Index n) {
  Bounds b;
  b.extend({lo, lo, lo});
  b.extend({hi, hi, hi});
  return GridSpec::from_bounds(b, {n, n, n});
}

PolyData single_point(const Vec3& p) {
  PolyData pd;
  pd.points.push_back(p);
  pd.verts.add({0});
  return pd;
}

}  // namespace

TEST(Csg, OperationNames) {
  for (CsgOperation op :
       {CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference}) {
    EXPECT_EQ(csg_operation_from_name(csg_operation_name(op)), op);
  }
  EXPECT_THROW((void)csg_operation_from_name("xor"), Error);
}

TEST(Csg, OffsetOfADistanceFieldIsTheSolidsLevelSet) {
  const GridSpec g = cube_grid(-1, 1, 41);
  DistanceOptions o;
  o.max_distance = 0.5;
  const auto field = distance_grid(single_point({0, 0, 0}), g, o).output;
  const auto ls = offset(*field, 0.3);
  EXPECT_EQ(ls->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_FLOAT_EQ(ls->background(), 0.2f);
  EXPECT_EQ(field->getGridClass(), openvdb::GRID_UNKNOWN);  // the input is unchanged
  auto acc = ls->getConstAccessor();
  for (auto it = ls->cbeginValueOn(); it; ++it) {
    const openvdb::Vec3d w = ls->indexToWorld(it.getCoord());
    const double ref = w.length() - 0.3;
    ASSERT_NEAR(*it, ref, 1e-6);
    ASSERT_LT(std::abs(ref), 0.2 + 1e-6);  // the band shrank to 0.5 - 0.3
  }
  // At the point the level set is -0.3, beyond the new band: inactive, -background.
  EXPECT_FLOAT_EQ(acc.getValue(openvdb::Coord(20, 20, 20)), -0.2f);
  EXPECT_FALSE(acc.isValueOn(openvdb::Coord(20, 20, 20)));
  EXPECT_FLOAT_EQ(acc.getValue(openvdb::Coord(0, 0, 0)), 0.2f);
  // Eroding it back by 0.1 leaves the level set of the ball of radius 0.2.
  auto copy = ls->deepCopy();
  offset_in_place(*copy, -0.1);
  EXPECT_FLOAT_EQ(copy->background(), 0.1f);
  for (auto it = copy->cbeginValueOn(); it; ++it) {
    ASSERT_NEAR(*it, ls->indexToWorld(it.getCoord()).length() - 0.2, 1e-6);
  }
  EXPECT_THROW((void)offset(*field, 0.5), Error);  // not inside the band
  EXPECT_THROW((void)offset(*field, NAN), Error);
}

TEST(Csg, DenseOffsetRefusesOverflow) {
  ImageData field{{2, 1, 1}, {0, 0, 0}, {1, 1, 1}, {}, {}, {}};
  DataArray f("F", ScalarType::Float32, 1, 2);
  f.values<float>()[0] = -1;
  f.values<float>()[1] = 3e38f;
  field.point_data.add(std::move(f), AttributeRole::Scalars);
  const ImageData shifted = offset(field, 1);
  EXPECT_EQ(shifted.point_data.get("F").values<float>()[0], -2.0f);
  try {
    (void)offset(field, 1e308);  // beyond Float32: it would have made every value -inf
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "offset: the distance 1e+308 is beyond the range of the Float32 scalars 'F'");
  }
  try {
    (void)offset(field, -1e38);  // 3e38 + 1e38 overflows
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "offset: a value of the Float32 scalars 'F' minus the distance -1e+38 overflows");
  }
}

TEST(Csg, SparseCopyInPlaceAndDenseAgree) {
  const GridSpec g = cube_grid(-1, 1, 49);
  DistanceOptions o;
  o.max_distance = 0.6;
  const PolyData a = single_point({-0.2, 0, 0}), b = single_point({0.25, 0.05, 0});
  const auto la = offset(*distance_grid(a, g, o).output, 0.4);
  const auto lb = offset(*distance_grid(b, g, o).output, 0.35);
  const ImageData da = offset(distance_image(a, g, o).output, 0.4);
  const ImageData db = offset(distance_image(b, g, o).output, 0.35);
  for (CsgOperation op :
       {CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference}) {
    const auto copy = csg(*la, *lb, op);
    EXPECT_EQ(la->activeVoxelCount() > 0, true);  // inputs intact
    auto ina = la->deepCopy(), inb = lb->deepCopy();
    csg_in_place(*ina, *inb, op);
    EXPECT_EQ(inb->activeVoxelCount(), 0u);  // B is consumed
    const ImageData dense = csg(da, db, op);
    const auto dv = dense.point_data.scalars()->values<float>();
    auto c1 = copy->getConstAccessor(), c2 = ina->getConstAccessor();
    std::size_t compared = 0;
    for (Index k = 0; k < 49; ++k)
      for (Index j = 0; j < 49; ++j)
        for (Index i = 0; i < 49; ++i) {
          const openvdb::Coord c{int(i), int(j), int(k)};
          ASSERT_EQ(c1.getValue(c), c2.getValue(c));
          const float d = dv[std::size_t(dense.point_id(i, j, k))];
          // On the result's band (the narrower input band, 0.2), the same numbers; elsewhere
          // the same side.
          if (std::abs(d) < 0.19f) {
            ASSERT_FLOAT_EQ(c1.getValue(c), d) << i << " " << j << " " << k;
            ++compared;
          } else {
            ASSERT_EQ(c1.getValue(c) < 0, d < 0) << i << " " << j << " " << k;
          }
        }
    EXPECT_GT(compared, 1000u);
  }
}

TEST(Csg, ErrorsNameTheProblem) {
  const GridSpec g = cube_grid(-1, 1, 17);
  DistanceOptions o;
  o.max_distance = 0.5;
  const auto field = distance_grid(single_point({0, 0, 0}), g, o).output;
  const auto ls = offset(*field, 0.2);
  try {
    (void)csg(*field, *ls, CsgOperation::Union);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a level set"), std::string::npos) << e.what();
  }
  const auto other = offset(*distance_grid(single_point({0, 0, 0}), cube_grid(-1, 1, 21), o).output, 0.2);
  try {
    (void)csg(*ls, *other, CsgOperation::Difference);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("different transforms"), std::string::npos) << e.what();
  }
  ImageData a = distance_image(single_point({0, 0, 0}), g, o).output;
  ImageData b = distance_image(single_point({0, 0, 0}), cube_grid(-1, 1, 18), o).output;
  EXPECT_THROW((void)csg(a, b, CsgOperation::Union), Error);
  EXPECT_THROW((void)offset_surfaces(*ls, {0.5}), Error);  // outside the band
  EXPECT_THROW((void)offset_surfaces(a, {}), Error);
}
