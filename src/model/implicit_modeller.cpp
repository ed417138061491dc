// The implicit modeller (model/implicit_modeller.hpp): vtkImplicitModeller's grid, bounds,
// maximum distance and capping conventions over isoforge's exact distance fields.
//
// Methods implemented: W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit*,
// "Implicit Modelling" (distance to generating primitives sampled on a volume, contoured at an
// offset; capping so that offset surfaces close at the volume boundary), with the distances of
// model/distance.hpp (Eberly's point-triangle distance, banded scan conversion or BVH gather).

#include "isoforge/model/implicit_modeller.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "distance_internal.hpp"
#include "isoforge/core/memory.hpp"
#include "modeller_internal.hpp"

namespace isoforge {

namespace {

template <class T>
void cap(ImageData& img, T value) {
  T* v = img.point_data.active(AttributeRole::Scalars)->values<T>().data();
  const Index nx = img.dims[0], ny = img.dims[1], nz = img.dims[2];
  tbb::parallel_for(Index{0}, nz, [&](Index k) {
    for (Index j = 0; j < ny; ++j) {
      T* row = v + nx * (j + ny * k);
      if (k == 0 || k == nz - 1 || j == 0 || j == ny - 1) {
        std::fill(row, row + nx, value);
      } else {
        row[0] = value;
        row[nx - 1] = value;
      }
    }
  });
}

// The range of T as doubles.
template <class T>
std::pair<double, double> type_range() {
  if constexpr (std::is_floating_point_v<T>) {
    return {-static_cast<double>(std::numeric_limits<T>::max()),
            static_cast<double>(std::numeric_limits<T>::max())};
  } else {
    return {static_cast<double>(std::numeric_limits<T>::lowest()),
            static_cast<double>(std::numeric_limits<T>::max())};
  }
}

// `value` converted to T, checked to fit (`what` names it in the error).
template <class T>
T fitting(double value, ScalarType type, const char* what) {
  const auto [lo, hi] = type_range<T>();
  if (std::isnan(value) || value < lo || value > hi) {
    throw Error(fmt::format("implicit modeller: {} {:g} does not fit {}", what, value,
                            scalar_type_name(type)));
  }
  return static_cast<T>(value);
}

// A distance as T: floats rounded, integers trunc(v · scale) clamped to the type's range
// (VTK's conversion, made defined for every value).
template <class T>
T convert_distance(double v, double scale) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(v);
  } else {
    const auto [lo, hi] = type_range<T>();
    return static_cast<T>(std::clamp(std::trunc(v * scale), lo, hi));
  }
}

// The Float64 field `d` (±inf beyond the band) as T; ±inf become ±`far` (a value of T), or with
// `clamp` the converted ±`maxd`.
template <class T>
DataArray convert_field(const DataArray& d, double scale, double far, bool clamp, double maxd,
                        ScalarType type) {
  const auto src = d.values<double>();
  DataArray out = DataArray::uninitialized(d.name(), type, 1, src.size());
  T* o = out.values<T>().data();
  T far_t, neg_far;
  if (clamp) {
    far_t = convert_distance<T>(maxd, scale);
    neg_far = convert_distance<T>(-maxd, scale);
  } else {
    far_t = fitting<T>(far, type, "far value");
    neg_far = std::is_signed_v<T> ? fitting<T>(-far, type, "far value") : far_t;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, src.size(), 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        const double v = src[i];
                        o[i] = std::isinf(v) ? (v > 0 ? far_t : neg_far)
                                             : convert_distance<T>(v, scale);
                      }
                    });
  return out;
}

}  // namespace

ModellerGrid implicit_modeller_grid(const Bounds& input_bounds, const ImplicitModellerOptions& o) {
  for (int a = 0; a < 3; ++a) {
    if (o.sample_dimensions[a] < 2) {
      throw Error("implicit modeller: sample dimensions must be at least 2 along every axis, got " +
                  std::to_string(o.sample_dimensions[0]) + " x " +
                  std::to_string(o.sample_dimensions[1]) + " x " +
                  std::to_string(o.sample_dimensions[2]));
    }
  }
  if (!(o.maximum_distance > 0 && o.maximum_distance <= 1)) {
    throw Error(fmt::format("implicit modeller: maximum distance must be a fraction in (0, 1] of "
                            "the largest side, got {:g}",
                            o.maximum_distance));
  }
  if (!(o.adjust_distance >= 0) || !std::isfinite(o.adjust_distance)) {
    throw Error(fmt::format("implicit modeller: adjust distance must be finite and >= 0, got {:g}",
                            o.adjust_distance));
  }
  const Bounds b = o.model_bounds.empty() ? input_bounds : o.model_bounds;
  if (b.empty() || !is_finite(b.min) || !is_finite(b.max)) {
    throw Error("implicit modeller: the model bounds are empty or not finite");
  }
  const Vec3 size = b.size();
  const double side = std::max({size.x, size.y, size.z});
  if (!(side > 0)) {
    throw Error(
        "implicit modeller: the model bounds have zero extent along every axis (a single "
        "point needs explicit model bounds)");
  }
  Bounds mb = b;
  if (o.adjust_bounds) {
    const Vec3 pad{side * o.adjust_distance, side * o.adjust_distance, side * o.adjust_distance};
    mb.min = b.min - pad;
    mb.max = b.max + pad;
  }
  for (int a = 0; a < 3; ++a) {
    if (!(mb.max[a] > mb.min[a])) {
      throw Error("implicit modeller: the model bounds have zero extent along axis " +
                  std::to_string(a) + " (enable adjust_bounds or give model bounds)");
    }
  }
  ModellerGrid r;
  r.grid = GridSpec::from_bounds(mb, o.sample_dimensions);
  r.max_distance = side * o.maximum_distance;
  return r;
}

double vtk_type_max(ScalarType type) {
  if (type == ScalarType::Float32) return kVtkFloatMax;
  if (type == ScalarType::Float64) return kVtkDoubleMax;
  return visit_scalar_type(type, [](auto t) { return type_range<decltype(t)>().second; });
}

namespace model_detail {

void check_modeller_input(const PolyData& input) {
  if (input.num_cells() == 0 || input.points.empty()) {
    throw Error("implicit modeller: the input is empty (no vertices, lines or polygons)");
  }
  if (input.points.first_non_finite() < input.points.size()) {
    throw Error(fmt::format("implicit modeller: point {} is not finite",
                            input.points.first_non_finite()));
  }
}

DistanceOptions modeller_distance_options(const ImplicitModellerOptions& o, double max_distance) {
  DistanceOptions d;
  d.max_distance = max_distance;
  d.signed_distance = o.signed_distance;
  d.radius_array = o.radius_array;
  d.strategy = o.strategy;
  d.name = o.name;
  d.progress = o.progress;
  return d;
}

}  // namespace model_detail

ImplicitModellerResult implicit_modeller(const PolyData& input, const ImplicitModellerOptions& o) {
  using namespace model_detail;
  check_modeller_input(input);
  const ScalarType type = o.output_type;
  const double type_max = vtk_type_max(type);
  const double cap_value = o.cap_value.value_or(type_max);
  const double far_value = o.far_value.value_or(type_max);
  if (std::isnan(cap_value) || std::isnan(far_value)) {
    throw Error("implicit modeller: cap value and far value must not be NaN");
  }
  if (o.scale_to_maximum_distance && is_floating(type)) {
    throw Error("implicit modeller: scale_to_maximum_distance needs an integer output type, got " +
                std::string(scalar_type_name(type)));
  }
  const bool is_unsigned =
      visit_scalar_type(type, [](auto t) { return std::is_unsigned_v<decltype(t)>; });
  if (o.signed_distance && is_unsigned) {
    throw Error("implicit modeller: signed distances need a signed output type, got " +
                std::string(scalar_type_name(type)));
  }
  const ModellerGrid mg = implicit_modeller_grid(input.bounds(), o);
  // Clamped or integer output holds a Float64 field and its conversion at once.
  require_volume_memory("implicit modeller", mg.grid.dims, scalar_type_name(type),
                        static_cast<double>(scalar_size(type)) +
                            (is_floating(type) && !o.clamp ? 0 : 8) + (o.signed_distance ? 9 : 0));
  DistanceOptions d = modeller_distance_options(o, mg.max_distance);
  ImplicitModellerResult r;
  ImageData& img = r.output;
  if (is_floating(type) && !o.clamp) {
    visit_scalar_type(type, [&](auto t) { (void)fitting<decltype(t)>(far_value, type, "far value"); });
    d.type = type;
    img = distance_image_far(input, mg.grid, d, far_value, r.stats);
  } else {
    // Clamped or integer: the exact field in Float64 (±inf beyond the band), then converted.
    const double scale = o.scale_to_maximum_distance ? type_max / mg.max_distance : 1.0;
    d.type = ScalarType::Float64;
    img = distance_image_far(input, mg.grid, d, std::numeric_limits<double>::infinity(), r.stats);
    DataArray& field = *img.point_data.active(AttributeRole::Scalars);
    DataArray out = visit_scalar_type(type, [&](auto t) {
      return convert_field<decltype(t)>(field, scale, far_value, o.clamp, mg.max_distance, type);
    });
    img.point_data.clear();
    img.point_data.add(std::move(out), AttributeRole::Scalars);
  }
  if (o.capping) cap_boundary(img, cap_value);
  return r;
}

void cap_boundary(ImageData& image, double value) {
  if (std::isnan(value)) throw Error("cap: the cap value is NaN");
  DataArray* s = image.point_data.active(AttributeRole::Scalars);
  if (!s || s->components() != 1) throw Error("cap: the image has no 1-component active scalars");
  visit_scalar_type(s->type(), [&](auto t) {
    using T = decltype(t);
    const auto [lo, hi] = type_range<T>();
    if (value < lo || value > hi) {
      throw Error(fmt::format("cap: the cap value {:g} does not fit the active scalars '{}' ({})",
                              value, s->name(), scalar_type_name(s->type())));
    }
    cap(image, static_cast<T>(value));
  });
}

}  // namespace isoforge
