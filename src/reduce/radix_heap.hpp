#pragma once
// A radix heap (Ahuja, Mehlhorn, Orlin and Tarjan 1990) over 32-bit keys, for the decimation
// queue: entries sit in 33 buckets by the highest bit in which their key differs from the last
// key popped, and a pop that empties bucket 0 redistributes the next non-empty bucket around its
// smallest key. Every entry moves down a bucket at most 32 times and every move is an append,
// so a pop over millions of entries costs a few sequential passes instead of a binary heap's
// cache misses at each level (the heap's sift-down was a sixth of a 1M-triangle decimation).
//
// A radix heap is monotone: a key pushed below the last key popped is raised to it, and so comes
// out next, as it would from an exact heap. Entries of equal key come out last in first. The
// order depends only on the sequence of pushes and pops.
//
// The buckets are Buffers (core/buffer.hpp): their growth takes mapped blocks from its cache
// instead of fresh pages, whose first touch was a third of a 100k-triangle decimation's page
// faults.

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "isoforge/core/buffer.hpp"

namespace isoforge::reduce {

/// The 32-bit key that orders floats as their values (negative ones included).
inline std::uint32_t order_key(float x) {
  const auto bits = std::bit_cast<std::uint32_t>(x);
  return (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
}

/// T has a public `std::uint32_t key`.
template <class T>
class RadixHeap {
 public:
  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] std::size_t size() const { return size_; }

  /// Empties the heap and lets keys start again from 0.
  void clear() {
    for (auto& b : buckets_) b.clear();
    size_ = 0;
    last_ = 0;
  }

  /// Empties the heap and fills it with `items`, as pushing them in order would; when they all
  /// fall in one bucket (keys of costs ≥ 0 all have the top bit set) it takes over their storage
  /// (`items` gets the bucket's old storage, empty).
  void assign(Buffer<T>& items) {
    clear();
    if (items.empty()) return;
    const std::size_t b = bucket(items.front().key);
    bool one = true;
    for (const T& x : items) one = one && bucket(x.key) == b;
    if (one) {
      buckets_[b].swap(items);
      size_ = buckets_[b].size();
      return;
    }
    for (const T& x : items) push(x);
    items.clear();
  }

  void push(T item) {
    if (item.key < last_) item.key = last_;
    buckets_[bucket(item.key)].push_back(item);
    ++size_;
  }

  /// Removes and returns an entry of the smallest key (the heap must not be empty).
  T pop() {
    if (buckets_[0].empty()) {
      std::size_t i = 1;
      while (buckets_[i].empty()) ++i;
      Buffer<T>& from = buckets_[i];
      std::uint32_t smallest = from.front().key;
      for (const T& x : from) smallest = x.key < smallest ? x.key : smallest;
      last_ = smallest;
      for (const T& x : from) buckets_[bucket(x.key)].push_back(x);
      from.clear();
    }
    const T top = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return top;
  }

 private:
  [[nodiscard]] std::size_t bucket(std::uint32_t key) const {
    return key == last_ ? 0 : static_cast<std::size_t>(32 - std::countl_zero(key ^ last_));
  }

  std::array<Buffer<T>, 33> buckets_;
  std::uint32_t last_ = 0;
  std::size_t size_ = 0;
};

}  // namespace isoforge::reduce
