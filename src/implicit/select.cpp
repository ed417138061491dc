// Selection of cells by an implicit function (VTK textbook section 1.5.2.2, vtkExtractGeometry).

#include "isoforge/implicit/select.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "isoforge/implicit/sample.hpp"
#include "isoforge/core/subset.hpp"

namespace isoforge {

UnstructuredGrid extract_cells(DatasetRef input, const ImplicitFunction& f,
                               const SelectOptions& options) {
  validate(input);
  const std::size_t np = num_points(input);
  const std::size_t nc = num_cells(input);
  const DataArray values = sample_points(f, input, "F", ScalarType::Float64);
  const auto v = values.values<double>();
  std::vector<std::uint8_t> in_region(np);
  for (std::size_t i = 0; i < np; ++i) {
    in_region[i] = options.inside ? (v[i] <= 0) : (v[i] > 0);
  }
  std::vector<Index> cells;
  std::vector<Index> ids;
  for (std::size_t c = 0; c < nc; ++c) {
    cell_point_ids(input, static_cast<Index>(c), ids);
    bool all = true, any = false;
    for (Index id : ids) {
      const bool r = in_region[static_cast<std::size_t>(id)] != 0;
      all = all && r;
      any = any || r;
    }
    if (options.any_point ? any : all) cells.push_back(static_cast<Index>(c));
  }
  return subset_cells(input, cells, options.original_ids);
}

}  // namespace isoforge
