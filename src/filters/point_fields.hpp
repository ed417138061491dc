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

}  // namespace isoforge::filters_detail
