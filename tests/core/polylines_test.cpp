#include "isoforge/core/polylines.hpp"

#include <gtest/gtest.h>

#include <vector>

using namespace isoforge;

namespace {

std::vector<std::vector<Index>> lines_of(const Polylines& p) {
  std::vector<std::vector<Index>> out;
  for (std::size_t l = 0; l + 1 < p.offsets.size(); ++l) {
    out.emplace_back(p.connectivity.begin() + p.offsets[l],
                     p.connectivity.begin() + p.offsets[l + 1]);
  }
  return out;
}

}  // namespace

TEST(JoinSegments, ChainsOpenAndClosedLines) {
  // An open chain 0-1-2-3 given out of order and partly reversed, and a triangle loop 4-5-6.
  const std::vector<Index> segs = {2, 3, 1, 2, 4, 5, 0, 1, 5, 6, 6, 4};
  const Polylines p = join_segments(segs, 7);
  const auto lines = lines_of(p);
  ASSERT_EQ(lines.size(), 2u);
  // In the order of their lowest segment (0: 2-3, 2: 4-5); each along its segments' direction.
  EXPECT_EQ(lines[0], (std::vector<Index>{0, 1, 2, 3}));
  EXPECT_EQ(lines[1], (std::vector<Index>{4, 5, 6, 4}));  // closed: first point repeated
  EXPECT_EQ(p.first, (std::vector<std::size_t>{0, 2}));
}

TEST(JoinSegments, BranchPointsEndChains) {
  // A star: three segments meet at point 0 (degree 3), so none is joined there.
  const std::vector<Index> segs = {0, 1, 0, 2, 3, 0};
  const auto lines = lines_of(join_segments(segs, 4));
  ASSERT_EQ(lines.size(), 3u);
  for (const auto& l : lines) EXPECT_EQ(l.size(), 2u);
}

TEST(JoinSegments, MajorityDirectionAndJoinablePredicate) {
  // 0->1, 2->1, 2->3: two of three segments run "backward" along 0..3, so the line runs 3 .. 0.
  const std::vector<Index> segs = {0, 1, 2, 1, 3, 2};
  EXPECT_EQ(lines_of(join_segments(segs, 4))[0], (std::vector<Index>{3, 2, 1, 0}));
  // Forbidding the join of segments 0 and 1 splits the line at point 1.
  const auto split = lines_of(join_segments(segs, 4, [](std::size_t a, std::size_t b) {
    return !((a == 0 && b == 1) || (a == 1 && b == 0));
  }));
  ASSERT_EQ(split.size(), 2u);
  EXPECT_EQ(split[0], (std::vector<Index>{0, 1}));
  EXPECT_EQ(split[1], (std::vector<Index>{3, 2, 1}));
}

TEST(SameCellData, ComparesEveryArrayBytewise) {
  Attributes cd;
  cd.add(DataArray::from_vector<int>("a", 1, {1, 1, 2}));
  cd.add(DataArray::from_vector<float>("b", 2, {0, 1, 0, 1, 0, 1}));
  const SameCellData same(cd);
  EXPECT_TRUE(same(0, 1));
  EXPECT_FALSE(same(1, 2));
  EXPECT_TRUE(same(2, 2));
}
