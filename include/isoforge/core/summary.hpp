#pragma once
/// \file
/// What a dataset holds, without its values: type, dimensions, counts, cell types, bounds and
/// every array's type, size and value ranges. `summarize(ds)` takes it from a dataset in memory;
/// `summarize_file` (io/io.hpp) from a file in one streaming pass, without loading the dataset.

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "isoforge/core/attributes.hpp"
#include "isoforge/core/cell_type.hpp"
#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Ranges of an array's values, accumulated over any number of pieces in any order: per
/// component and, with several components, of the tuples' magnitude. NaN values are ignored; a
/// range with lo > hi holds no value (empty or all NaN).
class ValueRanges {
 public:
  explicit ValueRanges(int components = 1);
  /// Adds `tuples` tuples of `type` values in host byte order (whole tuples; large pieces are
  /// split over all threads).
  void add(ScalarType type, const void* values, std::size_t tuples);
  void merge(const ValueRanges& other);

  [[nodiscard]] int components() const { return static_cast<int>(component_.size()); }
  [[nodiscard]] std::pair<double, double> component(int c) const {
    return component_[static_cast<std::size_t>(c)];
  }
  [[nodiscard]] std::pair<double, double> magnitude() const { return magnitude_; }

 private:
  std::vector<std::pair<double, double>> component_;
  std::pair<double, double> magnitude_;
};

struct ArraySummary {
  std::string name;
  ScalarType type = ScalarType::Float32;
  int components = 1;
  std::uint64_t tuples = 0;
  ValueRanges ranges;
};

struct AttributesSummary {
  std::vector<ArraySummary> arrays;
  std::array<std::string, kAttributeRoleCount> active;  ///< active array name per role

  /// The array named `name`, or null.
  [[nodiscard]] ArraySummary* find(const std::string& name);
  [[nodiscard]] const ArraySummary* find(const std::string& name) const;
  /// Adds `a`'s tuples and ranges to the array of its name (appended if new).
  void merge_array(ArraySummary a);
};

struct DatasetSummary {
  std::size_t kind = 0;  ///< as `Dataset::index()`: image, structured, polygonal, unstructured
  Dims dims{};           ///< image data and structured grids
  Vec3 origin{}, spacing{1, 1, 1};  ///< image data
  std::uint64_t points = 0;
  std::uint64_t cells = 0;
  std::map<CellType, std::uint64_t> cell_types;
  Bounds bounds;
  AttributesSummary point_data, cell_data, field_data;
  /// Whether it was computed without loading the dataset (`summarize_file`).
  bool streamed = false;
};

/// "image data", "structured grid", "polygonal data", "unstructured grid" for `kind`.
[[nodiscard]] std::string_view dataset_kind_name(std::size_t kind);

/// The summary of a dataset in memory (one pass over each array).
[[nodiscard]] DatasetSummary summarize(DatasetRef ds);
/// The summary of one array.
[[nodiscard]] ArraySummary summarize(const DataArray& a);

}  // namespace isoforge
