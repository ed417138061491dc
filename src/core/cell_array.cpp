#include "isoforge/core/cell_array.hpp"

#include <string>

#include "isoforge/core/error.hpp"

namespace isoforge {

CellArray::CellArray(Buffer<Index> offsets, Buffer<Index> connectivity)
    : offsets_(std::move(offsets)), connectivity_(std::move(connectivity)) {
  if (offsets_.empty() || offsets_.front() != 0) {
    throw Error("CellArray: offsets must start with 0");
  }
  for (std::size_t i = 1; i < offsets_.size(); ++i) {
    if (offsets_[i] < offsets_[i - 1]) {
      throw Error("CellArray: offsets decrease at cell " + std::to_string(i - 1));
    }
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
  if (offsets_.empty() || offsets_.front() != 0) {
    throw Error(std::string(what) + ": offsets must start with 0");
  }
  for (std::size_t i = 1; i < offsets_.size(); ++i) {
    if (offsets_[i] < offsets_[i - 1]) {
      throw Error(std::string(what) + ": offsets decrease at cell " + std::to_string(i - 1));
    }
  }
  if (offsets_.back() != static_cast<Index>(connectivity_.size())) {
    throw Error(std::string(what) + ": last offset does not equal the connectivity size");
  }
  const auto n = static_cast<Index>(num_points);
  for (std::size_t c = 0; c + 1 < offsets_.size(); ++c) {
    for (Index k = offsets_[c]; k < offsets_[c + 1]; ++k) {
      Index id = connectivity_[static_cast<std::size_t>(k)];
      if (id < 0 || id >= n) {
        throw Error(std::string(what) + ": cell " + std::to_string(c) + " refers to point " +
                    std::to_string(id) + ", outside [0, " + std::to_string(n) + ")");
      }
    }
  }
}

}  // namespace isoforge
