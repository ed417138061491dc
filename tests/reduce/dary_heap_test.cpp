#include "reduce/dary_heap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace isoforge::reduce {
namespace {

struct Item {
  float key;
  unsigned id;
};

struct Later {
  bool operator()(const Item& a, const Item& b) const {
    return a.key != b.key ? a.key > b.key : a.id > b.id;
  }
};

std::vector<Item> popped(DaryHeap<Item, Later>& heap) {
  std::vector<Item> out;
  while (!heap.empty()) out.push_back(heap.pop());
  return out;
}

TEST(DaryHeap, PopsInOrderAfterAssignAndPushes) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> key(0, 50);  // many equal keys: ties go by id
  for (std::size_t n : {0u, 1u, 2u, 4u, 5u, 17u, 1000u}) {
    std::vector<Item> items;
    for (unsigned i = 0; i < n; ++i) items.push_back({float(key(rng)), i});
    DaryHeap<Item, Later> heap;
    heap.assign(items);
    // Interleave pops and pushes, as the decimation queue does.
    std::vector<Item> expected = items;
    for (unsigned i = 0; i < n / 3; ++i) {
      // Every pop returns the first of what the heap holds.
      const auto first =
          std::min_element(expected.begin(), expected.end(),
                           [](const Item& a, const Item& b) { return Later{}(b, a); });
      const Item top = heap.pop();
      EXPECT_EQ(top.id, first->id) << n << " " << i;
      expected.erase(first);
      const Item extra{float(key(rng)), unsigned(n + i)};
      heap.push(extra);
      expected.push_back(extra);
    }
    EXPECT_EQ(heap.size(), expected.size());
    std::sort(expected.begin(), expected.end(),
              [](const Item& a, const Item& b) { return Later{}(b, a); });
    const std::vector<Item> rest = popped(heap);
    ASSERT_EQ(rest.size(), expected.size());
    for (std::size_t i = 0; i < rest.size(); ++i) {
      EXPECT_EQ(rest[i].id, expected[i].id) << "n=" << n << " at " << i;
    }
  }
}

}  // namespace
}  // namespace isoforge::reduce
