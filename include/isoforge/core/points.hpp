#pragma once
/// \file
/// `Points`: xyz coordinates stored as a 3-component float32 (default) or float64 `DataArray`.

#include <cstddef>
#include <span>
#include <utility>

#include "isoforge/core/data_array.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge {

/// Point coordinates. float32 by default (as VTK, OpenVDB and meshoptimizer store them);
/// float64 when a file or algorithm asks for it. Exact predicates in `verify/` run on the stored
/// values, so a decision never disagrees with the data.
class Points {
 public:
  Points() : data_("Points", ScalarType::Float32, 3) {}
  /// `n` points at the origin. \throw Error unless type is Float32 or Float64.
  explicit Points(std::size_t n, ScalarType type = ScalarType::Float32);
  /// Adopts a 3-component Float32/Float64 array. \throw Error otherwise.
  explicit Points(DataArray array);

  [[nodiscard]] std::size_t size() const { return data_.tuples(); }
  [[nodiscard]] bool empty() const { return size() == 0; }
  [[nodiscard]] ScalarType type() const { return data_.type(); }

  [[nodiscard]] Vec3 operator[](std::size_t i) const {
    if (data_.type() == ScalarType::Float32) {
      const float* p = data_.values<float>().data() + 3 * i;
      return {p[0], p[1], p[2]};
    }
    const double* p = data_.values<double>().data() + 3 * i;
    return {p[0], p[1], p[2]};
  }
  void set(std::size_t i, const Vec3& p);
  /// p as this array stores it (rounded to float for Float32): what `set` then `operator[]`
  /// give back. Algorithms that decide on coordinates (exact predicates) decide on these.
  [[nodiscard]] Vec3 stored(const Vec3& p) const;
  void push_back(const Vec3& p);
  void resize(std::size_t n) { data_.resize(n); }
  void reserve(std::size_t n) { data_.reserve(n); }

  /// The float32 coordinates, xyz interleaved. \throw Error if stored as float64.
  [[nodiscard]] std::span<const float> floats() const { return data_.values<float>(); }
  [[nodiscard]] std::span<float> floats() { return data_.values<float>(); }

  [[nodiscard]] const DataArray& array() const { return data_; }
  [[nodiscard]] DataArray& array() { return data_; }

  [[nodiscard]] Bounds bounds() const;
  /// Index of the first non-finite coordinate, or size() if all are finite.
  [[nodiscard]] std::size_t first_non_finite() const;

  friend bool operator==(const Points&, const Points&) = default;

 private:
  DataArray data_;
};

}  // namespace isoforge
