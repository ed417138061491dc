#include "isoforge/core/buffer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace isoforge {
namespace {

// A freed large block is kept and handed to the next request of the same size (memory already
// mapped), while live blocks stay distinct; a zero-filling resize of a reused block is zeros.
TEST(Buffer, FreedLargeBlocksAreReused) {
  const std::size_t n = detail::kLargeBlockBytes / sizeof(double) + 5;
  const double* first = nullptr;
  {
    Buffer<double> a(n);
    std::fill(a.begin(), a.end(), 42.0);
    first = a.data();
  }
  Buffer<double> b(n);
  EXPECT_EQ(b.data(), first);
  Buffer<double> c;
  c.resize(n, 0.0);
  EXPECT_NE(c.data(), b.data());
  b.clear();
  b.shrink_to_fit();  // back to the cache
  Buffer<double> d;
  d.resize(n, 0.0);
  EXPECT_EQ(std::accumulate(d.begin(), d.end(), 0.0), 0.0);
}

TEST(Buffer, LargeBlocksAreHugePageAligned) {
  Buffer<float> b;
  b.resize(detail::kHugeBlockBytes / sizeof(float) + 3);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::uintptr_t{2} << 20), 0u);
  Buffer<float> middle(detail::kLargeBlockBytes / sizeof(float) + 3);  // mapped, page aligned
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(middle.data()) % 4096, 0u);
  Buffer<float> small(16);
  EXPECT_NE(small.data(), nullptr);
}

TEST(Buffer, ContentSurvivesGrowthAcrossTheLargeBlockThreshold) {
  // Grows from malloc'ed blocks into mapped ones and copies back down again.
  Buffer<std::int64_t> b;
  const std::size_t n = 3 * detail::kLargeBlockBytes / sizeof(std::int64_t) + 17;
  for (std::size_t i = 0; i < n; ++i) b.push_back(static_cast<std::int64_t>(i) * 7 - 3);
  for (std::size_t i = 0; i < n; i += 4099) ASSERT_EQ(b[i], static_cast<std::int64_t>(i) * 7 - 3);
  EXPECT_EQ(b.back(), static_cast<std::int64_t>(n - 1) * 7 - 3);

  Buffer<std::int64_t> copy = b;
  EXPECT_EQ(copy, b);
  copy.resize(100);
  copy.shrink_to_fit();
  EXPECT_EQ(copy.size(), 100u);
  EXPECT_EQ(copy[99], 99 * 7 - 3);
}

// Sizes in the same class share blocks: a freed block serves a request a little smaller. A
// request a size class larger gets another block.
TEST(Buffer, FreedBlocksServeSimilarSizes) {
  for (const std::size_t bytes : {detail::kLargeBlockBytes * 3, detail::kHugeBlockBytes * 5}) {
    const std::size_t n = bytes / sizeof(float);
    const float* first = nullptr;
    {
      Buffer<float> a(n);
      a.back() = 1;
      first = a.data();
    }
    {
      Buffer<float> b(n - n / 10);
      EXPECT_EQ(b.data(), first) << bytes;
      b.back() = 2;
    }
    Buffer<float> c(n + n / 2);  // too large for that block, which stays cached
    c.back() = 3;
    Buffer<float> d(n);
    EXPECT_EQ(d.data(), first) << bytes;
  }
}

// The cache holds a bounded amount: freeing more than it holds releases the oldest blocks, and
// the newest freed block is still handed back.
TEST(Buffer, FullCacheKeepsTheNewestBlocks) {
  const std::size_t n = (std::size_t{24} << 20) / sizeof(double);  // 24 MiB each
  std::vector<Buffer<double>> blocks;
  for (int i = 0; i < 4; ++i) blocks.emplace_back(n + static_cast<std::size_t>(i));
  const double* newest = blocks.back().data();
  blocks.clear();  // frees 96 MiB into a 64 MiB cache, oldest first
  Buffer<double> again(n + 3);
  EXPECT_EQ(again.data(), newest);
}

TEST(Buffer, ZeroFillingResizeStillZeroFillsLargeBlocks) {
  Buffer<double> b;
  b.resize(detail::kLargeBlockBytes / sizeof(double) * 2, 0.0);
  EXPECT_EQ(std::accumulate(b.begin(), b.end(), 0.0), 0.0);
}

}  // namespace
}  // namespace isoforge
