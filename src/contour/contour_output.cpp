// What every contour kernel shares to build its output (contour_output.hpp).

#include "contour_output.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "isoforge/core/normals.hpp"

namespace isoforge::contour_detail {

void check_values(const ContourOptions& options, const char* who) {
  if (options.values.empty()) throw Error(fmt::format("{}: no isovalues given", who));
  for (double v : options.values) {
    if (!std::isfinite(v)) throw Error(fmt::format("{}: isovalue {} is not finite", who, v));
  }
}

const DataArray& contour_scalars(const Attributes& point_data, const ContourOptions& options,
                                 const char* who) {
  check_values(options, who);
  const DataArray* a =
      options.array.empty() ? point_data.scalars() : point_data.find(options.array);
  if (!a) {
    if (options.array.empty()) {
      throw Error(fmt::format("{}: the input has no active point scalars (name an array)", who));
    }
    throw Error(fmt::format("{}: no point array named '{}'", who, options.array));
  }
  if (a->components() != 1) {
    throw Error(fmt::format("{}: array '{}' has {} components; contouring needs one", who,
                            a->name(), a->components()));
  }
  return *a;
}

ContourArrays::ContourArrays(const Attributes& point_data, const Attributes& cell_data,
                             std::size_t points, std::size_t cells, const ContourOptions& options) {
  if (options.interpolate_attributes) {
    attributes = AttributeInterpolator(point_data, cell_data, points, cells);
    this->cell_data = attributes.has_cell_arrays();
  }
  if (options.normals == ContourNormals::Gradient) {
    normal_array_ = DataArray::uninitialized("Normals", ScalarType::Float32, 3, points);
    normals = normal_array_.values<float>().data();
  }
}

void ContourArrays::move_into(PolyData& out) {
  attributes.move_into(out.point_data, out.cell_data);
  if (normals) out.point_data.add(std::move(normal_array_), AttributeRole::Normals);
  normals = nullptr;
}

PolyData triangle_output(std::size_t points, std::size_t triangles) {
  PolyData pd;
  pd.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, points));
  pd.polys.offsets().resize(triangles + 1);
  pd.polys.connectivity().resize(3 * triangles);
  return pd;
}

void add_isovalue_index(PolyData& pd, int index) {
  DataArray a = DataArray::uninitialized("IsovalueIndex", ScalarType::Int32, 1, pd.points.size());
  std::int32_t* v = a.values<std::int32_t>().data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pd.points.size(), 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::fill(v + r.begin(), v + r.end(), static_cast<std::int32_t>(index));
                    });
  pd.point_data.add(std::move(a));
}

void finish_output(PolyData& pd, const ContourOptions& options) {
  if (options.flip) {
    for (CellArray* ca : {&pd.lines, &pd.polys}) {
      for (std::size_t c = 0; c < ca->size(); ++c) {
        auto ids = ca->cell(c);
        std::reverse(ids.begin(), ids.end());
      }
    }
  }
  if (options.normals == ContourNormals::Triangles) {
    pd.point_data.add(point_normals(pd), AttributeRole::Normals);
  }
}

}  // namespace isoforge::contour_detail
