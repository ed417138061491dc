#pragma once
// A 4-ary min-heap over a std::vector, for the decimation queues: half the levels of a binary
// heap, and a node's four children next to each other in memory (one or two cache lines), so a
// pop over millions of entries misses the cache about half as often as std::pop_heap. `Later`
// is the comparator std::push_heap would take (a "later than" b: b comes out first). With a
// total order the entries come out in the same order as from std::pop_heap.

#include <cstddef>
#include <utility>
#include <vector>

namespace isoforge::reduce {

template <class T, class Later>
class DaryHeap {
 public:
  [[nodiscard]] bool empty() const { return items_.empty(); }
  [[nodiscard]] std::size_t size() const { return items_.size(); }
  void clear() { items_.clear(); }
  void reserve(std::size_t n) { items_.reserve(n); }

  /// Replaces the contents by `items` in heap order (O(n)).
  void assign(std::vector<T> items) {
    items_ = std::move(items);
    const std::size_t n = items_.size();
    if (n < 2) return;
    for (std::size_t i = (n - 2) / kArity + 1; i-- > 0;) sift_down(i);
  }

  void push(const T& item) {
    items_.push_back(item);
    std::size_t i = items_.size() - 1;
    const T x = items_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / kArity;
      if (!later_(items_[parent], x)) break;
      items_[i] = items_[parent];
      i = parent;
    }
    items_[i] = x;
  }

  /// Removes and returns the first entry (the heap must not be empty).
  T pop() {
    const T top = items_.front();
    const T last = items_.back();
    items_.pop_back();
    if (!items_.empty()) {
      items_.front() = last;
      sift_down(0);
    }
    return top;
  }

 private:
  static constexpr std::size_t kArity = 4;

  void sift_down(std::size_t i) {
    const std::size_t n = items_.size();
    const T x = items_[i];
    for (;;) {
      const std::size_t first = kArity * i + 1;
      if (first >= n) break;
      const std::size_t end = first + kArity < n ? first + kArity : n;
      std::size_t best = first;
      for (std::size_t c = first + 1; c < end; ++c) {
        if (later_(items_[best], items_[c])) best = c;
      }
      if (!later_(x, items_[best])) break;
      items_[i] = items_[best];
      i = best;
    }
    items_[i] = x;
  }

  std::vector<T> items_;
  Later later_;
};

}  // namespace isoforge::reduce
