#include "isoforge/core/parallel.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <atomic>
#include <vector>

using namespace isoforge;

TEST(ParallelForRange, CoversEveryItemOnceWithAndWithoutProgress) {
  for (const bool with_progress : {false, true}) {
    const std::size_t n = 100003;
    std::vector<std::atomic<int>> hits(n);
    std::vector<double> fractions;
    ProgressCallback progress;
    if (with_progress) {
      progress = [&](double f) {
        fractions.push_back(f);
        return true;
      };
    }
    parallel_for_range(
        n, 100,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1);
        },
        progress, "test");
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << i;
    if (with_progress) {
      // One report per slice (up to 64), increasing, the last one 1.
      ASSERT_GE(fractions.size(), 32u);
      ASSERT_LE(fractions.size(), 64u);
      for (std::size_t k = 1; k < fractions.size(); ++k) EXPECT_LT(fractions[k - 1], fractions[k]);
      EXPECT_EQ(fractions.back(), 1.0);
    }
  }
}

TEST(ParallelForRange, CancelStopsBetweenSlices) {
  std::atomic<std::size_t> done{0};
  int calls = 0;
  const ProgressCallback stop = [&](double) { return ++calls < 3; };
  EXPECT_THROW(parallel_for_range(
                   1 << 20, 1, [&](std::size_t b, std::size_t e) { done += e - b; }, stop, "test"),
               Cancelled);
  EXPECT_EQ(calls, 3);
  EXPECT_LT(done.load(), std::size_t{1} << 20);  // slices after the third never ran
}

TEST(ParallelForRange, EmptyRangeReportsCompletion) {
  int calls = 0;
  parallel_for_range(
      0, 1, [](std::size_t, std::size_t) { FAIL(); },
      [&](double f) {
        EXPECT_EQ(f, 1.0);
        ++calls;
        return true;
      });
  EXPECT_EQ(calls, 1);
}

TEST(ProgressRange, MapsIntoTheParentsInterval) {
  std::vector<double> seen;
  const ProgressCallback parent = [&](double f) {
    seen.push_back(f);
    return true;
  };
  const ProgressCallback child = progress_range(parent, 0.25, 0.75);
  EXPECT_TRUE(child(0.0));
  EXPECT_TRUE(child(0.5));
  EXPECT_TRUE(child(1.0));
  EXPECT_EQ(seen, (std::vector<double>{0.25, 0.5, 0.75}));
  EXPECT_FALSE(static_cast<bool>(progress_range({}, 0, 1)));
}

TEST(ParallelFindFirst, FindsTheLowestIndexForAnyGrainAndThreadCount) {
  const std::size_t n = 1'000'003;
  // Marked indices in several chunks; the lowest must come back whichever chunk finishes first.
  std::vector<char> bad(n, 0);
  for (std::size_t i : {999'999u, 700'001u, 523'457u, 523'458u}) bad[i] = 1;
  const auto first = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (bad[i]) return i;
    }
    return e;
  };
  for (const int threads : {1, 2, 4}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    for (const std::size_t grain : {1u, 7u, 1000u, 65536u, 2'000'000u}) {
      EXPECT_EQ(parallel_find_first(n, grain, first), 523'457u) << threads << " " << grain;
    }
  }
  bad.assign(n, 0);
  EXPECT_EQ(parallel_find_first(n, 1000, first), n);  // none: n
  bad[0] = 1;
  EXPECT_EQ(parallel_find_first(n, 1000, first), 0u);
  EXPECT_EQ(parallel_find_first(0, 1000, first), 0u);  // empty range: n = 0
}
