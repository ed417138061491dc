#pragma once
// Private to filters/: the point arrays that elevation, warp and gradient read (named, or the
// active one of a role), with errors that list what the dataset has.

#include <string>
#include <string_view>

#include "isoforge/core/dataset.hpp"

namespace isoforge::filters_detail {

/// The point array `name`, or the active one of `role` when `name` is empty; it must have
/// `components` components (0: any). \throw Error "<what>: ..." naming the array and listing
/// the point arrays when it is missing or has the wrong number of components.
const DataArray& point_field(DatasetRef ds, const std::string& name, AttributeRole role,
                             int components, std::string_view what);

/// Whether x, y, z are all finite.
inline bool finite(const Vec3& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

/// Tuple i of a 3-component array (float arrays read without a type switch per value).
inline Vec3 tuple3(const DataArray& a, std::size_t i) {
  if (a.type() == ScalarType::Float32) {
    const float* p = a.values<float>().data() + 3 * i;
    return {p[0], p[1], p[2]};
  }
  return {a.get(i, 0), a.get(i, 1), a.get(i, 2)};
}

}  // namespace isoforge::filters_detail
