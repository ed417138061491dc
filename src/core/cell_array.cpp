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

/// The first cell whose offset is above the next one's, or offsets.size() - 1 (≥ 1 offsets).
std::size_t first_decrease(const Buffer<Index>& offsets) {
  return parallel_find_first(offsets.size() - 1, kCheckGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (offsets[i + 1] < offsets[i]) return i;
    }
    return e;
  });
}

}  // namespace

CellArray::CellArray(Buffer<Index> offsets, Buffer<Index> connectivity)
    : offsets_(std::move(offsets)), connectivity_(std::move(connectivity)) {
  if (offsets_.empty() || offsets_.front() != 0) {
    throw Error("CellArray: offsets must start with 0");
  }
  if (const std::size_t c = first_decrease(offsets_); c + 1 < offsets_.size()) {
    throw Error("CellArray: offsets decrease at cell " + std::to_string(c));
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

void CellArray::validate(std::size_t num_points, const char* what) const {
  // Flat passes over the offsets and the connectivity, on all threads; the cell of a bad index is
  // found afterwards (the offsets are then known to be sorted).
  if (offsets_.empty() || offsets_.front() != 0) {
    throw Error(std::string(what) + ": offsets must start with 0");
  }
  if (const std::size_t c = first_decrease(offsets_); c + 1 < offsets_.size()) {
    throw Error(std::string(what) + ": offsets decrease at cell " + std::to_string(c));
  }
  if (offsets_.back() != static_cast<Index>(connectivity_.size())) {
    throw Error(std::string(what) + ": last offset does not equal the connectivity size");
  }
  const auto n = static_cast<std::uint64_t>(num_points);
  const std::size_t bad =
      parallel_find_first(connectivity_.size(), kCheckGrain, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
          // Negative ids wrap to values ≥ n.
          if (static_cast<std::uint64_t>(connectivity_[k]) >= n) return k;
        }
        return e;
      });
  if (bad < connectivity_.size()) {
    // The cell holding position `bad`: the last whose offset is ≤ bad (empty cells before it
    // share its offset).
    const auto at = std::upper_bound(offsets_.begin(), offsets_.end(), static_cast<Index>(bad));
    const auto c = static_cast<std::size_t>(at - offsets_.begin()) - 1;
    throw Error(std::string(what) + ": cell " + std::to_string(c) + " refers to point " +
                std::to_string(connectivity_[bad]) + ", outside [0, " + std::to_string(n) + ")");
  }
}

}  // namespace isoforge
