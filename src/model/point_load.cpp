// The Boussinesq point-load stress field (model/point_load.hpp).
//
// Method: J. Boussinesq (1885), the field VTK's vtkPointLoad samples. With P the downward
// force, z ≥ 0 the depth (z down), ρ = |(x, y, z)| and k = P / 2π, the compression-positive
// stresses are
//   σxx = k (3x²z/ρ⁵ + (1−2ν)(1/(ρ(ρ+z)) − z/ρ³ − x²(2ρ+z)/(ρ³(ρ+z)²)))   (σyy alike with y)
//   σzz = 3k z³/ρ⁵,  σxy = k (3xyz/ρ⁵ − (1−2ν) xy(2ρ+z)/(ρ³(ρ+z)²)),
//   σxz = 3k xz²/ρ⁵,  σyz = 3k yz²/ρ⁵
// (the cylindrical σr, σθ of Timoshenko & Goodier §138 rotated to x, y, with 1 − z/ρ written as
// r²/(ρ(ρ+z)) so that nothing cancels on the axis). They are returned tension positive with z up
// (out of the body), the frame of the sampled box: normal and xy terms negated, xz and yz not.

#include "isoforge/model/point_load.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "isoforge/core/grid_spec.hpp"
#include "isoforge/core/memory.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

std::array<double, 9> boussinesq_stress(double x, double y, double depth, double load,
                                        double poisson_ratio) {
  const double z = depth;
  const double rho2 = x * x + y * y + z * z, rho = std::sqrt(rho2);
  const double rho3 = rho2 * rho, rho5 = rho3 * rho2;
  const double rz = rho + z;
  const double a = 1 / (rho * rz);                     // (1 − z/ρ)/r², finite on the axis
  const double b = (2 * rho + z) / (rho3 * rz * rz);   // (σr − σθ)'s (1−2ν) part over r²
  const double k = load / (2 * std::numbers::pi);
  const double nu = 1 - 2 * poisson_ratio;
  // Compression positive, z down (the formulas above), then tension positive, z up: the normal
  // and xy terms change sign once, xz and yz twice.
  const double sxx = k * (3 * x * x * z / rho5 + nu * (a - z / rho3 - x * x * b));
  const double syy = k * (3 * y * y * z / rho5 + nu * (a - z / rho3 - y * y * b));
  const double szz = k * 3 * z * z * z / rho5;
  const double sxy = k * x * y * (3 * z / rho5 - nu * b);
  const double sxz = k * 3 * x * z * z / rho5, syz = k * 3 * y * z * z / rho5;
  return {-sxx, -sxy, sxz, -sxy, -syy, syz, sxz, syz, -szz};
}

Result<ImageData, PointLoadStats> point_load(const PointLoadOptions& o) {
  if (!(std::isfinite(o.load) && o.load >= 0)) {
    throw Error(fmt::format("point load: the load must be finite and >= 0, got {}", o.load));
  }
  if (!(o.poisson_ratio >= 0 && o.poisson_ratio <= 0.5)) {
    throw Error(fmt::format("point load: Poisson's ratio must be in [0, 0.5], got {}",
                            o.poisson_ratio));
  }
  if (o.tensors.empty()) throw Error("point load: the tensor array needs a name");
  if (o.tensors == o.scalars || o.tensors == "vtkValidPointMask" ||
      o.scalars == "vtkValidPointMask") {
    throw Error("point load: the tensor, scalar and vtkValidPointMask arrays need distinct names");
  }
  for (int a = 0; a < 3; ++a) {
    if (o.dims[a] < 2) {
      throw Error(fmt::format("point load: dims must be at least 2 along every axis, got {}",
                              format_dims(o.dims)));
    }
    if (!(o.bounds.max[a] > o.bounds.min[a])) {
      throw Error(fmt::format("point load: the box must have a positive extent along every axis "
                              "(axis {}: {} .. {})", "xyz"[a], o.bounds.min[a], o.bounds.max[a]));
    }
  }
  const GridSpec grid = GridSpec::from_bounds(o.bounds, o.dims);
  require_volume_memory("point load", o.dims, "Float32 tensor",
                        9 * 4 + (o.scalars.empty() ? 0 : 4) + 1);
  const std::size_t n = grid.num_points("point load");
  ImageData out = grid.image();
  DataArray tensors = DataArray::uninitialized(o.tensors, ScalarType::Float32, 9, n);
  DataArray scalars;
  if (!o.scalars.empty()) scalars = DataArray::uninitialized(o.scalars, ScalarType::Float32, 1, n);
  DataArray valid = DataArray::uninitialized("vtkValidPointMask", ScalarType::UInt8, 1, n);
  float* T = tensors.values<float>().data();
  float* S = o.scalars.empty() ? nullptr : scalars.values<float>().data();
  auto* V = valid.values<std::uint8_t>().data();

  const Vec3 at{(o.bounds.min.x + o.bounds.max.x) / 2, (o.bounds.min.y + o.bounds.max.y) / 2,
                o.bounds.max.z};
  const auto nx = static_cast<std::size_t>(o.dims[0]);
  const auto rows = n / nx;
  parallel_for_range(
      rows, 16,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t r = b; r < e; ++r) {
          const auto j = static_cast<Index>(r % static_cast<std::size_t>(o.dims[1]));
          const auto k = static_cast<Index>(r / static_cast<std::size_t>(o.dims[1]));
          const double y = grid.coordinate(1, j) - at.y;
          const double depth = std::max(0.0, at.z - grid.coordinate(2, k));
          for (std::size_t i = 0; i < nx; ++i) {
            const std::size_t p = r * nx + i;
            const double x = grid.coordinate(0, static_cast<Index>(i)) - at.x;
            // Only the load point itself is singular. Anywhere else a stress that is not finite
            // (a huge load, or a sample within a hair of the load point) is stored as it is and
            // reported below, rather than passed off as the singular sample.
            std::array<double, 9> s{};
            const bool regular = x * x + y * y + depth * depth > 0;
            if (regular) s = boussinesq_stress(x, y, depth, o.load, o.poisson_ratio);
            for (std::size_t c = 0; c < 9; ++c) T[9 * p + c] = static_cast<float>(s[c]);
            V[p] = regular ? 1 : 0;
            if (S) {
              const double dxy = s[0] - s[4], dyz = s[4] - s[8], dzx = s[8] - s[0];
              S[p] = static_cast<float>(std::sqrt(
                  0.5 * (dxy * dxy + dyz * dyz + dzx * dzx) +
                  3 * (s[1] * s[1] + s[5] * s[5] + s[2] * s[2])));
            }
          }
        }
      },
      o.progress, "point load");

  // A regular sample's stress is finite as a double; stored as Float32 it overflows to inf when
  // the load is huge or a sample lies very close to the load point (the stress grows as 1/ρ²).
  PointLoadStats stats;
  for (std::size_t p = 0; p < n; ++p) {
    bool stored = !S || std::isfinite(S[p]);
    for (std::size_t c = 0; c < 9; ++c) stored = stored && std::isfinite(T[9 * p + c]);
    if (!stored) {
      const std::size_t i = p % nx, j = (p / nx) % static_cast<std::size_t>(o.dims[1]),
                        k = p / nx / static_cast<std::size_t>(o.dims[1]);
      throw Error(fmt::format(
          "point load: the stress at sample ({}, {}, {}) = ({:g}, {:g}, {:g}) exceeds the Float32 "
          "range (3.4e38): lower the load ({:g}) or sample farther from the load point",
          i, j, k, grid.coordinate(0, static_cast<Index>(i)),
          grid.coordinate(1, static_cast<Index>(j)), grid.coordinate(2, static_cast<Index>(k)),
          o.load));
    }
    if (!V[p]) {
      ++stats.singular;
    } else if (S) {
      stats.max_effective_stress = std::max(stats.max_effective_stress, double(S[p]));
    }
  }
  out.point_data.add(std::move(tensors), AttributeRole::Tensors);
  if (S) out.point_data.add(std::move(scalars), AttributeRole::Scalars);
  out.point_data.add(std::move(valid));
  return {std::move(out), stats};
}

}  // namespace isoforge
