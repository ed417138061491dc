// Warping by a vector or a scalar (vtkWarpVector, vtkWarpScalar) and the displacement plot's
// scalar (vtkVectorDot).

#include "isoforge/filters/warp.hpp"

#include <fmt/core.h>

#include "isoforge/core/parallel.hpp"
#include "point_fields.hpp"

namespace isoforge {

namespace {

using filters_detail::finite;
using filters_detail::point_field;
using filters_detail::tuple3;

/// The input's points, stored as Float32 unless the input's are Float64, each moved by
/// move(id, p); the input's topology and all its data. Image data becomes a structured grid.
template <class Move>
Dataset displaced(DatasetRef input, const ProgressCallback& progress, const char* what,
                  const Move& move) {
  const std::size_t n = num_points(input);
  const ImageData* img = input.get_if<ImageData>();
  const Points* src = img ? nullptr : input.visit([](const auto& d) -> const Points* {
    if constexpr (std::is_same_v<std::decay_t<decltype(d)>, ImageData>) {
      return nullptr;
    } else {
      return &d.points;
    }
  });
  Points pts(n, src ? src->type() : ScalarType::Float32);
  parallel_for_range(
      n, 1 << 14,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const Vec3 p = img ? img->point(static_cast<Index>(i)) : (*src)[i];
          pts.set(i, move(i, p));
        }
      },
      progress, what);
  if (img) {
    StructuredGrid g;
    g.dims = img->dims;
    g.points = std::move(pts);
    g.point_data = img->point_data;
    g.cell_data = img->cell_data;
    g.field_data = img->field_data;
    return g;
  }
  // Everything but the points, copied once.
  return input.visit([&](const auto& d) -> Dataset {
    using T = std::decay_t<decltype(d)>;
    T out;
    if constexpr (std::is_same_v<T, StructuredGrid>) {
      out.dims = d.dims;
    } else if constexpr (std::is_same_v<T, PolyData>) {
      out.verts = d.verts;
      out.lines = d.lines;
      out.polys = d.polys;
      out.strips = d.strips;
    } else if constexpr (std::is_same_v<T, UnstructuredGrid>) {
      out.types = d.types;
      out.cells = d.cells;
    }
    if constexpr (!std::is_same_v<T, ImageData>) out.points = std::move(pts);
    out.point_data = d.point_data;
    out.cell_data = d.cell_data;
    out.field_data = d.field_data;
    return out;
  });
}


}  // namespace

Dataset warp_by_vector(DatasetRef input, const WarpVectorOptions& o) {
  if (!std::isfinite(o.scale)) throw Error("warp: the scale factor must be finite");
  validate(input);
  const DataArray& v = point_field(input, o.vectors, AttributeRole::Vectors, 3, "warp");
  const double scale = o.scale;
  return displaced(input, o.progress, "warp",
                   [&](std::size_t i, const Vec3& p) { return p + tuple3(v, i) * scale; });
}

Dataset warp_by_scalar(DatasetRef input, const WarpScalarOptions& o) {
  if (!std::isfinite(o.scale)) throw Error("warp: the scale factor must be finite");
  Vec3 direction{};
  if (o.direction) {
    direction = unit_direction(*o.direction);
    if (direction == Vec3{}) throw Error("warp: the direction must be finite and not zero");
  }
  validate(input);
  const DataArray& s = point_field(input, o.scalars, AttributeRole::Scalars, 1, "warp");
  const DataArray* normals =
      o.direction ? nullptr : &point_field(input, o.normals, AttributeRole::Normals, 3, "warp");
  const double scale = o.scale;
  return displaced(input, o.progress, "warp", [&](std::size_t i, const Vec3& p) {
    const Vec3 n = normals ? tuple3(*normals, i) : direction;
    return p + n * (scale * s.get(i));
  });
}

DataArray displacement(DatasetRef input, const DisplacementOptions& o) {
  if (o.name.empty()) throw Error("displacement: the output array needs a name");
  validate(input);
  const DataArray& v = point_field(input, o.vectors, AttributeRole::Vectors, 3, "displacement");
  const DataArray& nrm = point_field(input, o.normals, AttributeRole::Normals, 3, "displacement");
  const std::size_t n = num_points(input);
  DataArray out = DataArray::uninitialized(o.name, ScalarType::Float32, 1, n);
  float* d = out.values<float>().data();
  parallel_for_range(n, 1 << 14, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) d[i] = static_cast<float>(dot(tuple3(v, i), tuple3(nrm, i)));
  });
  return out;
}

}  // namespace isoforge
