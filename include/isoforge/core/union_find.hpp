#pragma once
/// \file
/// A disjoint-set forest (union-find) over the integers 0 .. n − 1, shared by the surface
/// topology analysis, connectivity labelling and decimation.

#include <cstddef>
#include <numeric>
#include <vector>

namespace isoforge {

/// Disjoint sets of 0 .. n − 1 with path halving. `T` is the element type (std::uint32_t halves
/// the memory traffic of large inputs). The root of every set is its smallest element, whatever
/// the order of the unions, so anything numbered by roots is deterministic.
template <class T = std::size_t>
class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), T{0});
  }

  [[nodiscard]] std::size_t size() const { return parent_.size(); }

  /// The root (smallest element) of the set of `x`.
  T find(T x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  /// Joins the sets of `a` and `b`; returns false if they were already one set.
  bool unite(T a, T b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (a < b) {
      parent_[b] = a;
    } else {
      parent_[a] = b;
    }
    return true;
  }

 private:
  std::vector<T> parent_;
};

}  // namespace isoforge
