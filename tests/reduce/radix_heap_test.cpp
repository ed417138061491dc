#include "reduce/radix_heap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace isoforge::reduce {
namespace {

struct Item {
  std::uint32_t key;
  unsigned id;
};

TEST(RadixHeap, OrderKeyOrdersFloats) {
  const std::vector<float> values{-std::numeric_limits<float>::infinity(), -1e30f, -2.5f, -1e-30f,
                                  -0.0f, 0.0f, 1e-40f, 1e-30f, 1.0f, 2.5f, 1e30f,
                                  std::numeric_limits<float>::infinity()};
  for (std::size_t i = 1; i < values.size(); ++i) {
    EXPECT_LT(order_key(values[i - 1]), order_key(values[i])) << values[i - 1] << " " << values[i];
  }
}

TEST(RadixHeap, PopsTheSmallestKeyUnderInterleavedPushes) {
  std::mt19937 rng(7);
  for (std::uint32_t range : {1u, 50u, 1u << 20, 0xFFFFFFFFu}) {
    for (std::size_t n : {1u, 2u, 5u, 17u, 3000u}) {
      std::uniform_int_distribution<std::uint32_t> key(0, range);
      RadixHeap<Item> heap;
      std::vector<Item> held;
      for (unsigned i = 0; i < n; ++i) {
        const Item x{key(rng), i};
        heap.push(x);
        held.push_back(x);
      }
      std::uint32_t last = 0;
      unsigned next_id = static_cast<unsigned>(n);
      // Pops and pushes interleaved, as the decimation queue does; pushes at or above the last
      // key popped come out in key order.
      while (!held.empty()) {
        ASSERT_EQ(heap.size(), held.size());
        const Item top = heap.pop();
        const auto smallest = std::min_element(
            held.begin(), held.end(), [](const Item& a, const Item& b) { return a.key < b.key; });
        ASSERT_EQ(top.key, smallest->key) << "range " << range << " n " << n;
        const auto it = std::find_if(held.begin(), held.end(),
                                     [&](const Item& x) { return x.id == top.id; });
        ASSERT_NE(it, held.end());
        held.erase(it);
        last = top.key;
        if (next_id < 2 * n && key(rng) % 2 == 0) {
          const std::uint32_t k = std::max(last, key(rng));
          heap.push({k, next_id});
          held.push_back({k, next_id});
          ++next_id;
        }
      }
      EXPECT_TRUE(heap.empty());
    }
  }
}

TEST(RadixHeap, KeysBelowTheLastPopComeOutNext) {
  RadixHeap<Item> heap;
  for (unsigned i = 0; i < 10; ++i) heap.push({100 + i, i});
  EXPECT_EQ(heap.pop().id, 0u);
  heap.push({3, 42});  // below the last key popped (100): raised to it
  const Item next = heap.pop();
  EXPECT_EQ(next.id, 42u);
  EXPECT_EQ(next.key, 100u);
  EXPECT_EQ(heap.pop().id, 1u);
  heap.clear();
  EXPECT_TRUE(heap.empty());
  heap.push({3, 7});  // after clear, keys start again from 0
  EXPECT_EQ(heap.pop().key, 3u);
}

TEST(RadixHeap, AssignPopsAsPushingInOrderWould) {
  // Keys with the top bit set (all in one bucket: the storage is taken over), then keys spread
  // over buckets; ties included, whose order (last in, first out) must be the pushes' too.
  std::mt19937 rng(11);
  for (const std::uint32_t low : {0x80000000u, 0u}) {
    std::uniform_int_distribution<std::uint32_t> key(low, low + 40);
    Buffer<Item> items;
    RadixHeap<Item> pushed;
    for (unsigned i = 0; i < 500; ++i) {
      items.push_back({key(rng), i});
      pushed.push(items.back());
    }
    RadixHeap<Item> assigned;
    assigned.push({1, 1000});  // left over: assign empties the heap first
    assigned.assign(items);
    ASSERT_EQ(assigned.size(), pushed.size());
    while (!pushed.empty()) {
      const Item a = assigned.pop(), b = pushed.pop();
      ASSERT_EQ(a.key, b.key);
      ASSERT_EQ(a.id, b.id);
    }
    EXPECT_TRUE(assigned.empty());
  }
}

}  // namespace
}  // namespace isoforge::reduce
