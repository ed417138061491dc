#include "isoforge/core/append.hpp"

#include <gtest/gtest.h>

using namespace isoforge;

namespace {

// A part with `base` in its coordinates, one vertex, one line, one triangle; a point array "p"
// (point index + base), a cell array "c" (cell index + 10 base), and `extra` only in some parts.
PolyData part(double base, bool extra) {
  PolyData pd;
  for (int i = 0; i < 3; ++i) pd.points.push_back({base + i, 0, 0});
  pd.verts.add({0});
  pd.lines.add({0, 1});
  pd.polys.add({0, 1, 2});
  pd.point_data.add(DataArray::from_vector<double>("p", 1, {base, base + 1, base + 2}),
                    AttributeRole::Scalars);
  pd.cell_data.add(DataArray::from_vector<int>(
      "c", 1, {int(10 * base), int(10 * base) + 1, int(10 * base) + 2}));
  if (extra) pd.point_data.add(DataArray::from_vector<float>("extra", 1, {1, 2, 3}));
  return pd;
}

}  // namespace

TEST(Append, ShiftsIdsAndKeepsCellKindOrder) {
  const PolyData out = append({part(0, true), part(100, false)});
  ASSERT_EQ(out.points.size(), 6u);
  EXPECT_EQ(out.points[4].x, 101.0);
  // Verts of both parts, then lines, then polys; ids of the second part shifted by 3.
  ASSERT_EQ(out.verts.size(), 2u);
  EXPECT_EQ(out.verts.cell(1)[0], 3);
  ASSERT_EQ(out.lines.size(), 2u);
  EXPECT_EQ(out.lines.cell(1)[1], 4);
  ASSERT_EQ(out.polys.size(), 2u);
  EXPECT_EQ(out.polys.cell(1)[2], 5);
  EXPECT_NO_THROW(out.validate());
  // Point data in point order; cell data in the appended cell order (verts, lines, polys).
  const auto p = out.point_data.get("p").values<double>();
  EXPECT_EQ(std::vector<double>(p.begin(), p.end()), (std::vector<double>{0, 1, 2, 100, 101, 102}));
  const auto c = out.cell_data.get("c").values<int>();
  EXPECT_EQ(std::vector<int>(c.begin(), c.end()), (std::vector<int>{0, 1000, 1, 1001, 2, 1002}));
  // An array only one part has is dropped; roles of the first part kept.
  EXPECT_FALSE(out.point_data.has("extra"));
  EXPECT_EQ(out.point_data.active_name(AttributeRole::Scalars), "p");
}

TEST(Append, PromotesToDoublePointsAndDropsMismatchedArrays) {
  PolyData a = part(0, false), b = part(1, false);
  b.points = Points(3, ScalarType::Float64);
  b.points.set(2, {0.1, 0.2, 0.3});
  b.point_data.add(DataArray::from_vector<float>("p", 1, {1, 2, 3}));  // now Float32: mismatch
  const PolyData out = append({a, b});
  EXPECT_EQ(out.points.type(), ScalarType::Float64);
  EXPECT_EQ(out.points[5].y, 0.2);  // exactly, not through float
  EXPECT_FALSE(out.point_data.has("p"));
  EXPECT_TRUE(out.cell_data.has("c"));
}

TEST(Append, OnePartIsReturnedAsItIsAndNoneGivesEmpty) {
  const PolyData one = part(5, true);
  EXPECT_EQ(append({one}), one);
  EXPECT_EQ(append({}).num_points(), 0u);
}
