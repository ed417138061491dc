#include "isoforge/core/cell_array.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "isoforge/core/error.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {

/// Elements per task of the checks (flat passes: a million cells is a few hundred microseconds).
constexpr std::size_t kCheckGrain = std::size_t{1} << 16;

}  // namespace

std::size_t first_decrease(std::span<const Index> values) {
  return parallel_find_first(values.size(), kCheckGrain, [&](std::size_t b, std::size_t e) {
    Index prev = b > 0 ? values[b - 1] : 0;
    for (std::size_t i = b; i < e; ++i) {
      if (values[i] < prev) return i;
      prev = values[i];
    }
    return e;
  });
}

std::size_t first_out_of_range(std::span<const Index> ids, std::size_t num_points) {
  const auto n = static_cast<std::uint64_t>(num_points);
  return parallel_find_first(ids.size(), kCheckGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      if (static_cast<std::uint64_t>(ids[k]) >= n) return k;  // negative ids wrap above n
    }
    return e;
  });
}

CellArray::CellArray(Buffer<Index> offsets, Buffer<Index> connectivity)
    : offsets_(std::move(offsets)), connectivity_(std::move(connectivity)) {
  if (offsets_.empty() || offsets_.front() != 0) {
    throw Error("CellArray: offsets must start with 0");
  }
  if (const std::size_t i = first_decrease(offsets_); i < offsets_.size()) {
    throw Error("CellArray: offsets decrease at cell " + std::to_string(i - 1));
  }
  if (offsets_.back() != static_cast<Index>(connectivity_.size())) {
    throw Error("CellArray: last offset " + std::to_string(offsets_.back()) +
                " does not equal the connectivity size " + std::to_string(connectivity_.size()));
  }
}

void CellArray::add(std::span<const Index> ids) {
  connectivity_.insert(connectivity_.end(), ids.begin(), ids.end());
  offsets_.push_back(static_cast<Index>(connectivity_.size()));
}

void CellArray::reserve(std::size_t cells, std::size_t ids) {
  offsets_.reserve(cells + 1);
  connectivity_.reserve(ids);
}

void CellArray::clear() {
  offsets_.assign(1, 0);
  connectivity_.clear();
}

std::size_t CellArray::first_smaller_than(std::size_t min_points) const {
  const auto min = static_cast<Index>(min_points);
  return parallel_find_first(size(), kCheckGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      if (offsets_[c + 1] - offsets_[c] < min) return c;
    }
    return e;
  });
}

void CellArray::validate(std::size_t num_points, const char* what) const {
  // Flat passes over the offsets and the connectivity, on all threads; the cell of a bad index is
  // found afterwards (the offsets are then known to be sorted).
  if (offsets_.empty() || offsets_.front() != 0) {
    throw Error(std::string(what) + ": offsets must start with 0");
  }
  if (const std::size_t i = first_decrease(offsets_); i < offsets_.size()) {
    throw Error(std::string(what) + ": offsets decrease at cell " + std::to_string(i - 1));
  }
  if (offsets_.back() != static_cast<Index>(connectivity_.size())) {
    throw Error(std::string(what) + ": last offset does not equal the connectivity size");
  }
  const std::size_t bad = first_out_of_range(connectivity_, num_points);
  if (bad < connectivity_.size()) {
    // The cell holding position `bad`: the last whose offset is ≤ bad (empty cells before it
    // share its offset).
    const auto at = std::upper_bound(offsets_.begin(), offsets_.end(), static_cast<Index>(bad));
    const auto c = static_cast<std::size_t>(at - offsets_.begin()) - 1;
    throw Error(std::string(what) + ": cell " + std::to_string(c) + " refers to point " +
                std::to_string(connectivity_[bad]) + ", outside [0, " + std::to_string(num_points) +
                ")");
  }
}

}  // namespace isoforge
