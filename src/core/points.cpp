#include "isoforge/core/points.hpp"

#include <cmath>

#include "isoforge/core/parallel.hpp"

namespace isoforge {

Points::Points(std::size_t n, ScalarType type) : data_("Points", type, 3, n) {
  if (type != ScalarType::Float32 && type != ScalarType::Float64) {
    throw Error("Points: coordinates must be Float32 or Float64, not " +
                std::string(scalar_type_name(type)));
  }
}

Points::Points(DataArray array) : data_(std::move(array)) {
  if (data_.components() != 3) {
    throw Error("Points: array '" + data_.name() + "' has " + std::to_string(data_.components()) +
                " components, expected 3");
  }
  if (data_.type() != ScalarType::Float32 && data_.type() != ScalarType::Float64) {
    data_ = data_.converted(ScalarType::Float64);
  }
}

Vec3 Points::stored(const Vec3& p) const {
  if (data_.type() != ScalarType::Float32) return p;
  // Through memory: GCC 12 at -O3 was seen to drop a double -> float -> double round trip.
  volatile float x = static_cast<float>(p.x), y = static_cast<float>(p.y),
                 z = static_cast<float>(p.z);
  return {static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)};
}

void Points::set(std::size_t i, const Vec3& p) {
  if (data_.type() == ScalarType::Float32) {
    float* q = data_.values<float>().data() + 3 * i;
    q[0] = static_cast<float>(p.x);
    q[1] = static_cast<float>(p.y);
    q[2] = static_cast<float>(p.z);
  } else {
    double* q = data_.values<double>().data() + 3 * i;
    q[0] = p.x;
    q[1] = p.y;
    q[2] = p.z;
  }
}

void Points::push_back(const Vec3& p) {
  if (data_.type() == ScalarType::Float32) {
    auto& v = data_.vector<float>();
    v.push_back(static_cast<float>(p.x));
    v.push_back(static_cast<float>(p.y));
    v.push_back(static_cast<float>(p.z));
  } else {
    auto& v = data_.vector<double>();
    v.push_back(p.x);
    v.push_back(p.y);
    v.push_back(p.z);
  }
}

Bounds Points::bounds() const {
  Bounds b;
  const std::size_t n = size();
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 p = (*this)[i];
    if (is_finite(p)) b.extend(p);
  }
  return b;
}

std::size_t Points::first_non_finite() const {
  return parallel_find_first(size(), std::size_t{1} << 15, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (!is_finite((*this)[i])) return i;
    }
    return e;
  });
}

}  // namespace isoforge
