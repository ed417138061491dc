// Shrinking cells toward their centroids (VTK's vtkShrinkFilter).

#include "isoforge/filters/shrink.hpp"

#include "isoforge/core/subset.hpp"

namespace isoforge {

UnstructuredGrid shrink(DatasetRef input, double factor) {
  if (!(factor >= 0 && factor <= 1)) {
    throw Error("shrink: factor must be in [0, 1], got " + std::to_string(factor));
  }
  validate(input);
  const std::size_t nc = num_cells(input);
  std::size_t total = 0;
  std::vector<Index> ids;
  for (std::size_t c = 0; c < nc; ++c) {
    cell_point_ids(input, static_cast<Index>(c), ids);
    total += ids.size();
  }
  UnstructuredGrid out;
  out.points = Points(total);
  out.point_data = empty_like(point_data(input), total);
  out.types.reserve(nc);
  out.cells.reserve(nc, total);
  std::size_t next = 0;
  std::vector<Index> new_ids;
  for (std::size_t c = 0; c < nc; ++c) {
    cell_point_ids(input, static_cast<Index>(c), ids);
    Vec3 centroid{0, 0, 0};
    for (Index id : ids) centroid += point(input, id);
    centroid = centroid / static_cast<double>(ids.size());
    new_ids.clear();
    for (Index id : ids) {
      out.points.set(next, centroid + (point(input, id) - centroid) * factor);
      copy_tuple(point_data(input), static_cast<std::size_t>(id), out.point_data, next);
      new_ids.push_back(static_cast<Index>(next++));
    }
    out.add_cell(cell_type(input, static_cast<Index>(c)), new_ids);
  }
  out.cell_data = cell_data(input);
  out.field_data = field_data(input);
  return out;
}

}  // namespace isoforge
