// The implicit modeller (model/implicit_modeller.hpp): vtkImplicitModeller's grid, bounds,
// maximum distance and capping conventions over isoforge's exact distance fields.
//
// Methods implemented: W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit*,
// "Implicit Modelling" (distance to generating primitives sampled on a volume, contoured at an
// offset; capping so that offset surfaces close at the volume boundary), with the distances of
// model/distance.hpp (Eberly's point-triangle distance, banded scan conversion or BVH gather).

#include "isoforge/model/implicit_modeller.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "distance_internal.hpp"

namespace isoforge {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

DistanceOptions distance_options(const ImplicitModellerOptions& o, double max_distance) {
  DistanceOptions d;
  d.max_distance = max_distance;
  d.signed_distance = o.signed_distance;
  d.radius_array = o.radius_array;
  d.strategy = o.strategy;
  d.name = o.name;
  d.progress = o.progress;
  return d;
}

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
    throw Error(
        "implicit modeller: maximum distance must be a fraction in (0, 1] of the largest "
        "side, got " +
        num(o.maximum_distance));
  }
  if (!(o.adjust_distance >= 0) || !std::isfinite(o.adjust_distance)) {
    throw Error("implicit modeller: adjust distance must be finite and >= 0, got " +
                num(o.adjust_distance));
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

ImageData implicit_modeller(const PolyData& input, const ImplicitModellerOptions& o,
                            DistanceStats* stats) {
  if (input.num_cells() == 0 || input.points.empty()) {
    throw Error("implicit modeller: the input is empty (no vertices, lines or polygons)");
  }
  if (input.points.first_non_finite() < input.points.size()) {
    throw Error("implicit modeller: point " + std::to_string(input.points.first_non_finite()) +
                " is not finite");
  }
  if (std::isnan(o.cap_value) || std::isnan(o.far_value)) {
    throw Error("implicit modeller: cap value and far value must not be NaN");
  }
  const ModellerGrid mg = implicit_modeller_grid(input.bounds(), o);
  const double far = o.clamp ? mg.max_distance : o.far_value;
  ImageData img = model_detail::distance_image(input, mg.grid, distance_options(o, mg.max_distance),
                                               o.output_type, far, stats);
  if (o.capping) cap_boundary(img, o.cap_value);
  return img;
}

void cap_boundary(ImageData& image, double value) {
  if (std::isnan(value)) throw Error("cap: the cap value is NaN");
  DataArray* s = image.point_data.active(AttributeRole::Scalars);
  if (!s || s->components() != 1) throw Error("cap: the image has no 1-component active scalars");
  if (s->type() == ScalarType::Float32) {
    cap(image, static_cast<float>(value));
  } else if (s->type() == ScalarType::Float64) {
    cap(image, value);
  } else {
    throw Error("cap: the active scalars '" + s->name() + "' are not float32 or float64");
  }
}

openvdb::FloatGrid::Ptr implicit_modeller_vdb(const PolyData& input,
                                              const ImplicitModellerOptions& o,
                                              DistanceStats* stats) {
  if (input.num_cells() == 0 || input.points.empty()) {
    throw Error("implicit modeller: the input is empty (no vertices, lines or polygons)");
  }
  if (input.points.first_non_finite() < input.points.size()) {
    throw Error("implicit modeller: point " + std::to_string(input.points.first_non_finite()) +
                " is not finite");
  }
  const ModellerGrid mg = implicit_modeller_grid(input.bounds(), o);
  return distance_grid(input, mg.grid, distance_options(o, mg.max_distance), stats);
}

}  // namespace isoforge
