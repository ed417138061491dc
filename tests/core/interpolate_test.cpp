#include "isoforge/core/interpolate.hpp"

#include <gtest/gtest.h>

#include <cstdint>

using namespace isoforge;

namespace {

// Point data: a Float64 scalar (active), an Int32 array with a lookup table, a 3-component
// Float32 vector (active vectors); cell data: an Int64 id per cell.
struct Source {
  Attributes points, cells;
  Source() {
    points.add(DataArray::from_vector<double>("s", 1, {0.0, 10.0, 20.0, 30.0}),
               AttributeRole::Scalars);
    DataArray labels = DataArray::from_vector<std::int32_t>("label", 1, {0, 3, 7, -5});
    labels.set_lookup_table("colours");
    points.add(std::move(labels));
    points.add(DataArray::from_vector<float>("v", 3, {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}),
               AttributeRole::Vectors);
    cells.add(DataArray::from_vector<std::int64_t>("id", 1, {100, 200}));
  }
};

}  // namespace

TEST(AttributeInterpolator, InterpolatesEveryTypeAndRoundsIntegers) {
  const Source src;
  AttributeInterpolator a(src.points, src.cells, 3, 2);
  a.interpolate(0, 0, 1, 0.25);  // s = 2.5, label = round(0.75) = 1
  a.interpolate(1, 1, 2, 0.5);   // s = 15, label = 5
  const AttributeInterpolator::Term terms[] = {{0, 0.5}, {2, 0.25}, {3, 0.25}};
  a.combine(2, terms);  // s = 12.5, label = round(1.75 - 1.25) = round(0.5) = 1 (as VTK)
  a.copy_cell(0, 1);
  a.copy_cell(1, 0);
  Attributes pd, cd;
  a.move_into(pd, cd);
  const auto s = pd.get("s").values<double>();
  EXPECT_DOUBLE_EQ(s[0], 2.5);
  EXPECT_DOUBLE_EQ(s[1], 15.0);
  EXPECT_DOUBLE_EQ(s[2], 12.5);
  const auto l = pd.get("label").values<std::int32_t>();
  EXPECT_EQ(l[0], 1);
  EXPECT_EQ(l[1], 5);
  EXPECT_EQ(l[2], 1);  // halves away from zero, as VTK (a cut at a tie gave 4 where VTK gives 5)
  {
    AttributeInterpolator b(src.points, src.cells, 1, 0);
    b.interpolate(0, 0, 3, 0.9);  // label = 0.9 * -5 = -4.5 -> -5
    Attributes pb, cb;
    b.move_into(pb, cb);
    EXPECT_EQ(pb.get("label").values<std::int32_t>()[0], -5);
  }
  const auto v = pd.get("v").values<float>();
  EXPECT_FLOAT_EQ(v[3], 0.0f);  // (0,1,0) and (0,0,1) halfway: (0, 0.5, 0.5)
  EXPECT_FLOAT_EQ(v[4], 0.5f);
  EXPECT_FLOAT_EQ(v[5], 0.5f);
  EXPECT_EQ(cd.get("id").values<std::int64_t>()[0], 200);
  EXPECT_EQ(cd.get("id").values<std::int64_t>()[1], 100);
  // Names, order, roles and lookup tables carried.
  ASSERT_EQ(pd.size(), 3u);
  EXPECT_EQ(pd[0].name(), "s");
  EXPECT_EQ(pd.active_name(AttributeRole::Scalars), "s");
  EXPECT_EQ(pd.active_name(AttributeRole::Vectors), "v");
  EXPECT_EQ(pd.get("label").lookup_table(), "colours");
  EXPECT_EQ(pd.get("s").tuples(), 3u);
  EXPECT_EQ(cd.get("id").tuples(), 2u);
}

TEST(AttributeInterpolator, CopyPointKeepsValuesExactly) {
  Attributes points, cells;
  // 2^53 + 1 is not a double: an int64 copied through double would lose its last bit.
  points.add(DataArray::from_vector<std::int64_t>("big", 1, {(std::int64_t{1} << 53) + 1}));
  AttributeInterpolator a(points, cells, 1, 0);
  a.copy_point(0, 0);
  Attributes pd, cd;
  a.move_into(pd, cd);
  EXPECT_EQ(pd.get("big").values<std::int64_t>()[0], (std::int64_t{1} << 53) + 1);
}

TEST(AttributeInterpolator, DefaultCarriesNothing) {
  AttributeInterpolator a;
  a.interpolate(5, 1, 2, 0.5);
  a.copy_cell(3, 4);
  EXPECT_FALSE(a.has_point_arrays());
  EXPECT_FALSE(a.has_cell_arrays());
  Attributes pd, cd;
  a.move_into(pd, cd);
  EXPECT_TRUE(pd.empty());
  EXPECT_TRUE(cd.empty());
}
