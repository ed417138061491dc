// Booleans and offsets of dense distance fields (model/csg.hpp): the formulas of Equations
// 1.15-1.17 per sample (Ricci, "A constructive geometry for computer graphics", Computer Journal
// 16(2), 1973).

#include "isoforge/model/csg.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace isoforge {

namespace {

const DataArray& scalars_of(const ImageData& img, const char* what) {
  const DataArray* s = img.point_data.scalars();
  if (!s) throw Error(std::string(what) + ": the image has no active scalars");
  if (s->components() != 1) {
    throw Error(std::string(what) + ": the scalars '" + s->name() + "' have " +
                std::to_string(s->components()) + " components, need 1");
  }
  return *s;
}

}  // namespace

std::string_view csg_operation_name(CsgOperation op) {
  switch (op) {
    case CsgOperation::Union:
      return "union";
    case CsgOperation::Intersection:
      return "intersection";
    case CsgOperation::Difference:
      return "difference";
  }
  return "?";
}

CsgOperation csg_operation_from_name(std::string_view name) {
  if (name == "union") return CsgOperation::Union;
  if (name == "intersection") return CsgOperation::Intersection;
  if (name == "difference") return CsgOperation::Difference;
  throw Error("csg: unknown operation '" + std::string(name) +
              "' (union, intersection or difference)");
}

ImageData csg(const ImageData& a, const ImageData& b, CsgOperation op) {
  a.validate();
  b.validate();
  if (a.dims != b.dims || !(a.origin == b.origin) || !(a.spacing == b.spacing)) {
    throw Error("csg: the images are not on the same grid (dims, origin and spacing must match)");
  }
  const DataArray& sa = scalars_of(a, "csg");
  const DataArray& sb = scalars_of(b, "csg");
  ImageData out = ImageData{a.dims, a.origin, a.spacing, {}, {}, {}};
  const std::size_t n = a.num_points();
  const auto combine = [op](double x, double y) {
    switch (op) {
      case CsgOperation::Union:
        return std::min(x, y);
      case CsgOperation::Intersection:
        return std::max(x, y);
      case CsgOperation::Difference:
        return std::max(x, -y);
    }
    return x;
  };
  if (sa.type() == ScalarType::Float32 && sb.type() == ScalarType::Float32) {
    DataArray r = DataArray::uninitialized(sa.name(), ScalarType::Float32, 1, n);
    const float* x = sa.values<float>().data();
    const float* y = sb.values<float>().data();
    float* z = r.values<float>().data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& rg) {
                        for (std::size_t i = rg.begin(); i != rg.end(); ++i) {
                          z[i] = static_cast<float>(combine(x[i], y[i]));
                        }
                      });
    out.point_data.add(std::move(r), AttributeRole::Scalars);
  } else {
    DataArray r = DataArray::uninitialized(sa.name(), ScalarType::Float64, 1, n);
    double* z = r.values<double>().data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& rg) {
                        for (std::size_t i = rg.begin(); i != rg.end(); ++i) {
                          z[i] = combine(sa.get(i), sb.get(i));
                        }
                      });
    out.point_data.add(std::move(r), AttributeRole::Scalars);
  }
  return out;
}

ImageData offset(const ImageData& field, double distance) {
  field.validate();
  if (!std::isfinite(distance)) throw Error("offset: the distance is not finite");
  const DataArray& s = scalars_of(field, "offset");
  ImageData out = ImageData{field.dims, field.origin, field.spacing, {}, {}, {}};
  DataArray r = s;
  r.visit([&](auto& buf) {
    using T = typename std::decay_t<decltype(buf)>::value_type;
    if constexpr (std::is_floating_point_v<T>) {
      if (!(std::abs(distance) <= double(std::numeric_limits<T>::max()))) {
        throw Error(
            fmt::format("offset: the distance {:g} is beyond the range of the {} scalars "
                        "'{}'",
                        distance, scalar_type_name(s.type()), s.name()));
      }
      const T d = static_cast<T>(distance);
      bool overflow = false;
      for (auto& v : buf) {
        const T w = v - d;
        overflow = overflow || (std::isfinite(v) && !std::isfinite(w));
        v = w;
      }
      if (overflow) {
        throw Error(
            fmt::format("offset: a value of the {} scalars '{}' minus the distance {:g} "
                        "overflows",
                        scalar_type_name(s.type()), s.name(), distance));
      }
    } else {
      throw Error("offset: the scalars '" + s.name() + "' are not floating point");
    }
  });
  out.point_data.add(std::move(r), AttributeRole::Scalars);
  return out;
}

ContourResult offset_surfaces(const ImageData& field, const std::vector<double>& distances,
                              ContourOptions options) {
  if (distances.empty()) throw Error("offset surfaces: no distances given");
  options.values = distances;
  return contour_image(field, options);
}

}  // namespace isoforge
