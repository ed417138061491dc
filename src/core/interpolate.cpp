// Carrying attributes to new points and cells (core/interpolate.hpp).

#include "isoforge/core/interpolate.hpp"

#include <cmath>
#include <cstring>
#include <type_traits>

namespace isoforge {

namespace {

template <class T>
void combine_typed(const DataArray& src, DataArray& dst, std::size_t out,
                   std::span<const AttributeInterpolator::Term> terms) {
  const auto nc = static_cast<std::size_t>(src.components());
  const T* s = src.values<T>().data();
  T* d = dst.values<T>().data();
  for (std::size_t c = 0; c < nc; ++c) {
    double v = 0;
    for (const auto& [id, w] : terms) v += w * static_cast<double>(s[id * nc + c]);
    if constexpr (std::is_floating_point_v<T>) {
      d[out * nc + c] = static_cast<T>(v);
    } else {
      d[out * nc + c] = static_cast<T>(std::round(v));  // halves away from zero, as VTK
    }
  }
}

void copy_tuple_raw(const DataArray& src, DataArray& dst, std::size_t out, std::size_t in) {
  const std::size_t bytes = scalar_size(src.type()) * static_cast<std::size_t>(src.components());
  std::memcpy(dst.bytes() + out * bytes, src.bytes() + in * bytes, bytes);
}

/// Arrays shaped like `src`'s with `tuples` tuples each (uninitialized), and its roles.
Attributes shaped_like(const Attributes& src, std::size_t tuples) {
  Attributes out;
  for (const DataArray& a : src) {
    DataArray d = DataArray::uninitialized(a.name(), a.type(), a.components(), tuples);
    d.set_lookup_table(a.lookup_table());
    out.add(std::move(d));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!src.active_name(role).empty()) out.set_active(role, src.active_name(role));
  }
  return out;
}

/// Moves every array of `from` (and its roles) into `to`.
void move_arrays(Attributes& from, Attributes& to) {
  for (std::size_t i = 0; i < from.size(); ++i) to.add(std::move(from[i]));
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!from.active_name(role).empty()) to.set_active(role, from.active_name(role));
  }
  from.clear();
}

}  // namespace

AttributeInterpolator::AttributeInterpolator(const Attributes& point_data,
                                             const Attributes& cell_data, std::size_t points,
                                             std::size_t cells)
    : src_points_(&point_data),
      src_cells_(&cell_data),
      points_(shaped_like(point_data, points)),
      cells_(shaped_like(cell_data, cells)) {
  for (const DataArray& a : point_data) {
    combine_.push_back(a.visit([](const auto& v) -> CombineFn {
      using T = typename std::decay_t<decltype(v)>::value_type;
      return &combine_typed<T>;
    }));
  }
}

void AttributeInterpolator::interpolate(std::size_t out, std::size_t a, std::size_t b,
                                        double t) const {
  const Term terms[2] = {{a, 1.0 - t}, {b, t}};
  combine(out, terms);
}

void AttributeInterpolator::combine(std::size_t out, std::span<const Term> terms) const {
  // Distinct output tuples are distinct bytes: concurrent writes are safe.
  auto& dst = const_cast<Attributes&>(points_);
  for (std::size_t i = 0; i < combine_.size(); ++i)
    combine_[i]((*src_points_)[i], dst[i], out, terms);
}

void AttributeInterpolator::copy_point(std::size_t out, std::size_t in) const {
  auto& dst = const_cast<Attributes&>(points_);
  for (std::size_t i = 0; i < points_.size(); ++i)
    copy_tuple_raw((*src_points_)[i], dst[i], out, in);
}

void AttributeInterpolator::copy_cell(std::size_t out, std::size_t in) const {
  auto& dst = const_cast<Attributes&>(cells_);
  for (std::size_t i = 0; i < cells_.size(); ++i) copy_tuple_raw((*src_cells_)[i], dst[i], out, in);
}

void AttributeInterpolator::move_into(Attributes& point_data, Attributes& cell_data) {
  move_arrays(points_, point_data);
  move_arrays(cells_, cell_data);
  combine_.clear();
}

}  // namespace isoforge
