#pragma once
// Private to filters/: the point arrays that elevation, warp, gradient and streamlines read
// (named, or the active one of a role), with errors that list what the dataset has; small vector
// helpers the filters share (tuples, frames carried along lines).

#include <cmath>
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

/// v / |v|, or 0 for a zero or non-finite v.
inline Vec3 unit_or_zero(const Vec3& v) {
  const double l = norm(v);
  return l > 0 && std::isfinite(l) ? v / l : Vec3{0, 0, 0};
}

/// Some unit vector perpendicular to unit t (deterministic: t crossed with its smallest axis).
inline Vec3 perpendicular(const Vec3& t) {
  const double ax = std::abs(t.x), ay = std::abs(t.y), az = std::abs(t.z);
  const Vec3 axis = ax <= ay && ax <= az ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  return unit_or_zero(cross(t, axis));
}

/// The next normal of a frame carried along a curve: the previous one projected on the plane
/// normal to unit t (a discrete parallel transport: Bishop, "There is more than one way to frame
/// a curve", 1975), so the frame does not twist.
inline Vec3 transport(const Vec3& previous, const Vec3& t) {
  const Vec3 projected = previous - t * dot(previous, t);
  return norm2(projected) > 1e-24 ? unit_or_zero(projected) : perpendicular(t);
}

}  // namespace isoforge::filters_detail
