#pragma once
/// \file
/// `CellArray`: variable-size cells as offsets + connectivity (the VTK 9 layout).

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

#include "isoforge/core/buffer.hpp"

namespace isoforge {

/// Point index type used by all connectivity.
using Index = std::int64_t;

/// The first position whose value is below the one before it (or below 0, at position 0), or
/// values.size() if they are sorted and non-negative: the check of cell offsets and ends. A flat
/// pass on all threads.
[[nodiscard]] std::size_t first_decrease(std::span<const Index> values);
/// The first position whose id lies outside [0, num_points), or ids.size(): the check of
/// connectivity. A flat pass on all threads.
[[nodiscard]] std::size_t first_out_of_range(std::span<const Index> ids, std::size_t num_points);

/// Cells stored as `offsets` (size = cells + 1, offsets[0] = 0, non-decreasing) and
/// `connectivity` (point ids, cell i is connectivity[offsets[i] .. offsets[i+1])).
class CellArray {
 public:
  CellArray() = default;
  /// Adopts offsets + connectivity. \throw Error if offsets are not a valid prefix sum of
  /// connectivity (first 0, non-decreasing, last == connectivity.size()).
  CellArray(Buffer<Index> offsets, Buffer<Index> connectivity);
  CellArray(const std::vector<Index>& offsets, const std::vector<Index>& connectivity)
      : CellArray(Buffer<Index>(offsets.begin(), offsets.end()),
                  Buffer<Index>(connectivity.begin(), connectivity.end())) {}

  [[nodiscard]] std::size_t size() const { return offsets_.size() - 1; }
  [[nodiscard]] bool empty() const { return size() == 0; }
  [[nodiscard]] std::size_t cell_size(std::size_t cell) const {
    return static_cast<std::size_t>(offsets_[cell + 1] - offsets_[cell]);
  }
  [[nodiscard]] std::span<const Index> cell(std::size_t cell) const {
    return {connectivity_.data() + offsets_[cell], cell_size(cell)};
  }
  [[nodiscard]] std::span<Index> cell(std::size_t cell) {
    return {connectivity_.data() + offsets_[cell], cell_size(cell)};
  }

  void add(std::span<const Index> ids);
  void add(std::initializer_list<Index> ids) { add(std::span<const Index>(ids.begin(), ids.size())); }
  void reserve(std::size_t cells, std::size_t ids);
  void clear();

  [[nodiscard]] const Buffer<Index>& offsets() const { return offsets_; }
  [[nodiscard]] const Buffer<Index>& connectivity() const { return connectivity_; }
  /// Direct access for bulk builders; call `validate` afterwards. Note that `resize(n)` leaves
  /// new ids uninitialized (see Buffer): write every one, or use `resize(n, 0)`.
  [[nodiscard]] Buffer<Index>& offsets() { return offsets_; }
  [[nodiscard]] Buffer<Index>& connectivity() { return connectivity_; }

  /// Checks the offsets invariant and that every id is in [0, num_points).
  /// \throw Error mentioning `what` (e.g. "polys") and the first bad cell.
  void validate(std::size_t num_points, const char* what) const;
  /// The first cell of fewer than `min_points` points, or size(). A flat pass on all threads.
  [[nodiscard]] std::size_t first_smaller_than(std::size_t min_points) const;

  friend bool operator==(const CellArray&, const CellArray&) = default;

 private:
  Buffer<Index> offsets_{0};
  Buffer<Index> connectivity_;
};

}  // namespace isoforge
