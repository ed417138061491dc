// Trajectory densities and the Lorenz strange attractor (model/attractor.hpp).
//
// Methods implemented: E. N. Lorenz, "Deterministic nonperiodic flow", J. Atmos. Sci. 20(2), 1963
// (the system); the classical fourth-order Runge-Kutta method (core/ode.hpp); visit counting in a
// volume and marching cubes at a visit value as in the chapter's section 1.5.2.3 (VTK's Lorenz
// example).

#include "isoforge/model/attractor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "isoforge/core/memory.hpp"
#include "isoforge/core/ode.hpp"

namespace isoforge {

namespace {

/// Validates the options, allocates the counts and bins states.
class TrajectoryBinner {
 public:
  explicit TrajectoryBinner(const TrajectoryOptions& o) {
    if (!is_finite(o.start)) throw Error("trajectory density: the start point is not finite");
    if (!(o.step > 0) || !std::isfinite(o.step)) {
      throw Error(fmt::format("trajectory density: the step must be positive and finite, got {:g}",
                              o.step));
    }
    if (o.steps > std::numeric_limits<std::uint32_t>::max()) {
      // One voxel could then receive more visits than its UInt32 count holds.
      throw Error(
          fmt::format("trajectory density: {} steps exceed the UInt32 visit counts "
                      "(at most {})",
                      o.steps, std::numeric_limits<std::uint32_t>::max()));
    }
    for (int a = 0; a < 3; ++a) {
      if (o.dims[a] < 2) {
        throw Error(
            fmt::format("trajectory density: dims must be at least 2 along every axis, "
                        "got {} x {} x {}",
                        o.dims[0], o.dims[1], o.dims[2]));
      }
    }
    const std::size_t n = checked_point_count(o.dims, "trajectory density");
    require_volume_memory("trajectory density", o.dims, "UInt32", 4);
    const GridSpec g = GridSpec::from_bounds(o.bounds, o.dims);
    for (int a = 0; a < 3; ++a) {
      o_[a] = g.origin[a];
      inv_[a] = 1.0 / g.spacing[a];
      lim_[a] = static_cast<double>(o.dims[a] - 1);
    }
    nx_ = static_cast<std::uint64_t>(o.dims[0]);
    ny_ = static_cast<std::uint64_t>(o.dims[1]);
    array_ = DataArray(o.name, ScalarType::UInt32, 1, n);
    counts_ = array_.values<std::uint32_t>().data();
    grid_ = g;
  }

  /// Counts state s (or discards it).
  void add(const Vec3& s) {
    const double fx = (s.x - o_[0]) * inv_[0], fy = (s.y - o_[1]) * inv_[1],
                 fz = (s.z - o_[2]) * inv_[2];
    // Inside the box (NaN fails every comparison and is discarded).
    if (!(fx >= 0 && fx <= lim_[0] && fy >= 0 && fy <= lim_[1] && fz >= 0 && fz <= lim_[2])) {
      ++discarded_;
      return;
    }
    const auto i = static_cast<std::uint64_t>(fx + 0.5), j = static_cast<std::uint64_t>(fy + 0.5),
               k = static_cast<std::uint64_t>(fz + 0.5);
    ++counts_[i + nx_ * (j + ny_ * k)];
  }

  /// Builds the result (moves the counts out).
  TrajectoryResult finish(const Vec3& end) {
    TrajectoryResult r{grid_.image(), {}};
    std::uint64_t total = 0;
    for (std::uint32_t c : array_.values<std::uint32_t>()) {
      total += c;
      r.stats.max_visits = std::max(r.stats.max_visits, c);
    }
    r.stats.counted = total;
    r.stats.discarded = discarded_;
    r.stats.end = end;
    counts_ = nullptr;
    r.output.point_data.add(std::move(array_), AttributeRole::Scalars);
    return r;
  }

 private:
  double o_[3], inv_[3], lim_[3];
  std::uint64_t nx_, ny_;
  std::uint32_t* counts_ = nullptr;
  DataArray array_;
  GridSpec grid_;
  std::uint64_t discarded_ = 0;
};

/// Integrates y' = f(y) with RK4 and bins the states; f is inlined.
template <class F>
TrajectoryResult integrate(F&& f, const TrajectoryOptions& options) {
  TrajectoryBinner binner(options);
  Vec3 y = options.start;
  const double h = options.step;
  for (std::uint64_t s = 0; s < options.transient; ++s) y = rk4_step(f, y, h);
  constexpr std::uint64_t kChunk = 1 << 20;
  for (std::uint64_t done = 0; done < options.steps;) {
    const std::uint64_t end = std::min(options.steps, done + kChunk);
    for (; done < end; ++done) {
      y = rk4_step(f, y, h);
      binner.add(y);
    }
    report_progress(options.progress,
                    static_cast<double>(done) / static_cast<double>(options.steps),
                    "trajectory density");
  }
  return binner.finish(y);
}

}  // namespace

TrajectoryResult trajectory_density(const std::function<Vec3(const Vec3&)>& f,
                                    const TrajectoryOptions& options) {
  if (!f) throw Error("trajectory density: the right-hand side is empty");
  return integrate(f, options);
}

TrajectoryResult lorenz_density(const LorenzParameters& p, const TrajectoryOptions& options) {
  if (!std::isfinite(p.sigma) || !std::isfinite(p.rho) || !std::isfinite(p.beta)) {
    throw Error(
        fmt::format("lorenz: the parameters must be finite (sigma {:g}, rho {:g}, beta {:g})",
                    p.sigma, p.rho, p.beta));
  }
  return integrate([&p](const Vec3& s) { return lorenz(p, s); }, options);
}

AttractorResult lorenz_attractor(const AttractorOptions& options) {
  if (!std::isfinite(options.value))
    throw Error("lorenz attractor: the contour value is not finite");
  AttractorResult r;
  auto density = lorenz_density(options.lorenz, options.trajectory);
  r.stats.trajectory = density.stats;
  r.output.volume = std::move(density.output);
  ContourOptions c;
  c.values = {options.value};
  c.flip = true;  // counts are high inside: orient outward
  c.normals = options.normals;
  auto surface = contour_image(r.output.volume, c);
  r.output.surface = std::move(surface.output);
  r.stats.contour = surface.stats;
  return r;
}

}  // namespace isoforge
