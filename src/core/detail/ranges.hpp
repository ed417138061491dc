#pragma once
// Private to core: the range kernels behind DataArray::range and ValueRanges (summary.cpp).

#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <utility>

namespace isoforge::core_detail {

/// Min and max over values [b, e) of a strided column, NaNs skipped (they compare false), in
/// the stored type (exact; floats compare without conversion and the loop vectorises).
template <class T>
std::pair<double, double> column_range(const T* v, std::size_t stride, std::size_t b,
                                       std::size_t e) {
  T lo, hi;
  if constexpr (std::is_floating_point_v<T>) {
    lo = std::numeric_limits<T>::infinity();
    hi = -lo;
  } else {
    lo = std::numeric_limits<T>::max();
    hi = std::numeric_limits<T>::lowest();
  }
  for (std::size_t t = b; t < e; ++t) {
    const T x = v[t * stride];
    lo = x < lo ? x : lo;
    hi = x > hi ? x : hi;
  }
  return {static_cast<double>(lo), static_cast<double>(hi)};
}

template <class T>
std::pair<double, double> magnitude_range(const T* v, std::size_t nc, std::size_t b,
                                          std::size_t e) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (std::size_t t = b; t < e; ++t) {
    double s = 0;
    for (std::size_t c = 0; c < nc; ++c) {
      const auto x = static_cast<double>(v[t * nc + c]);
      s += x * x;
    }
    const double m = std::sqrt(s);
    lo = m < lo ? m : lo;  // a NaN magnitude compares false
    hi = m > hi ? m : hi;
  }
  return {lo, hi};
}

}  // namespace isoforge::core_detail
