#include "isoforge/core/subset.hpp"

#include <cstring>

namespace isoforge {

Attributes empty_like(const Attributes& src, std::size_t tuples) {
  Attributes out;
  for (const auto& a : src) {
    DataArray b(a.name(), a.type(), a.components(), tuples);
    b.set_lookup_table(a.lookup_table());
    out.add(std::move(b));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!src.active_name(role).empty()) out.set_active(role, src.active_name(role));
  }
  return out;
}

void copy_tuple(const Attributes& src, std::size_t from, Attributes& dst, std::size_t to) {
  for (std::size_t i = 0; i < src.size(); ++i) {
    const DataArray& a = src[i];
    DataArray& b = dst[i];
    const std::size_t bytes = scalar_size(a.type()) * static_cast<std::size_t>(a.components());
    std::memcpy(b.bytes() + to * bytes, a.bytes() + from * bytes, bytes);
  }
}

UnstructuredGrid subset_cells(DatasetRef input, const std::vector<Index>& cells,
                              bool original_ids) {
  const std::size_t np = num_points(input);
  std::vector<Index> map(np, -1);
  std::vector<Index> ids;
  for (Index c : cells) {
    cell_point_ids(input, c, ids);
    for (Index id : ids) map[static_cast<std::size_t>(id)] = 0;
  }
  std::vector<Index> used;
  for (std::size_t i = 0; i < np; ++i) {
    if (map[i] == 0) {
      map[i] = static_cast<Index>(used.size());
      used.push_back(static_cast<Index>(i));
    }
  }
  UnstructuredGrid out;
  const bool doubles = input.visit([](const auto& d) {
        if constexpr (std::is_same_v<std::decay_t<decltype(d)>, ImageData>) {
          return false;
        } else {
          return d.points.type() == ScalarType::Float64;
        }
      });
  out.points = Points(used.size(), doubles ? ScalarType::Float64 : ScalarType::Float32);
  for (std::size_t i = 0; i < used.size(); ++i) out.points.set(i, point(input, used[i]));
  out.types.reserve(cells.size());
  for (Index c : cells) {
    cell_point_ids(input, c, ids);
    for (Index& id : ids) id = map[static_cast<std::size_t>(id)];
    out.add_cell(cell_type(input, c), ids);
  }
  out.point_data = empty_like(point_data(input), used.size());
  for (std::size_t i = 0; i < used.size(); ++i) {
    copy_tuple(point_data(input), static_cast<std::size_t>(used[i]), out.point_data, i);
  }
  out.cell_data = empty_like(cell_data(input), cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    copy_tuple(cell_data(input), static_cast<std::size_t>(cells[i]), out.cell_data, i);
  }
  out.field_data = field_data(input);
  if (original_ids) {
    out.point_data.add(DataArray::from_vector<std::int64_t>("OriginalPointIds", 1,
                                                            std::vector<std::int64_t>(used.begin(), used.end())));
    out.cell_data.add(DataArray::from_vector<std::int64_t>("OriginalCellIds", 1,
                                                           std::vector<std::int64_t>(cells.begin(), cells.end())));
  }
  return out;
}

}  // namespace isoforge
