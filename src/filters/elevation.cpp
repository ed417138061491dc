// Elevation (vtkElevationFilter) and the point-field lookup shared by the attribute filters.

#include "isoforge/filters/elevation.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "isoforge/core/parallel.hpp"
#include "point_fields.hpp"

namespace isoforge {

namespace filters_detail {

const DataArray& point_field(DatasetRef ds, const std::string& name, AttributeRole role,
                             int components, std::string_view what) {
  const Attributes& pd = point_data(ds);
  const DataArray* a = name.empty() ? pd.active(role) : pd.find(name);
  if (!a) {
    throw Error(name.empty()
                    ? fmt::format("{}: the input has no active point {}; name one (point arrays: {})",
                                  what, attribute_role_name(role), pd.names())
                    : fmt::format("{}: no point array '{}' (point arrays: {})", what, name,
                                  pd.names()));
  }
  if (components > 0 && a->components() != components) {
    throw Error(fmt::format("{}: point array '{}' has {} component{}, {} needed", what, a->name(),
                            a->components(), a->components() == 1 ? "" : "s", components));
  }
  return *a;
}

}  // namespace filters_detail

DataArray elevation(DatasetRef input, const ElevationOptions& o) {
  using filters_detail::finite;
  if (!finite(o.low_point) || !finite(o.high_point)) {
    throw Error("elevation: the low and high points must be finite");
  }
  const Vec3 axis = o.high_point - o.low_point;
  const double length2 = norm2(axis);
  if (!(length2 > 0)) throw Error("elevation: the low and high points must differ");
  if (!std::isfinite(o.range[0]) || !std::isfinite(o.range[1])) {
    throw Error("elevation: the range must be finite");
  }
  if (o.name.empty()) throw Error("elevation: the output array needs a name");
  validate(input);
  const std::size_t n = num_points(input);
  DataArray out = DataArray::uninitialized(o.name, ScalarType::Float32, 1, n);
  float* v = out.values<float>().data();
  const double r0 = o.range[0], dr = o.range[1] - o.range[0];
  auto value = [&](const Vec3& p) {
    double t = dot(p - o.low_point, axis) / length2;
    if (o.clamp) t = std::clamp(t, 0.0, 1.0);
    return static_cast<float>(r0 + dr * t);
  };
  parallel_for_range(
      n, 1 << 14,
      [&](std::size_t b, std::size_t e) {
        if (const ImageData* img = input.get_if<ImageData>()) {
          for (std::size_t i = b; i < e; ++i) v[i] = value(img->point(static_cast<Index>(i)));
        } else {
          input.visit([&](const auto& d) {
            if constexpr (!std::is_same_v<std::decay_t<decltype(d)>, ImageData>) {
              for (std::size_t i = b; i < e; ++i) v[i] = value(d.points[i]);
            }
          });
        }
      },
      o.progress, "elevation");
  return out;
}

}  // namespace isoforge
