// Trajectory densities and the Lorenz strange attractor (model/attractor.hpp).
//
// Methods implemented: E. N. Lorenz, "Deterministic nonperiodic flow", J. Atmos. Sci. 20(2), 1963
// (the system); the classical fourth-order Runge-Kutta method (Kutta 1901; e.g. Hairer, Nørsett &
// Wanner, *Solving ODEs I*, II.1); visit counting in a volume and marching cubes at a visit value
// as in the chapter's section 1.5.2.3 (VTK's Lorenz example).

#include "isoforge/model/attractor.hpp"

#include <cmath>
#include <string>

#include "isoforge/core/memory.hpp"

namespace isoforge {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

namespace model_detail {

void check_trajectory_start(const TrajectoryOptions& o) {
  if (!is_finite(o.start)) throw Error("trajectory density: the start point is not finite");
  if (!(o.step > 0) || !std::isfinite(o.step)) {
    throw Error("trajectory density: the step must be positive and finite, got " + num(o.step));
  }
}

TrajectoryBinner::TrajectoryBinner(const TrajectoryOptions& o) {
  for (int a = 0; a < 3; ++a) {
    if (o.dims[a] < 2) {
      throw Error("trajectory density: dims must be at least 2 along every axis, got " +
                  std::to_string(o.dims[0]) + " x " + std::to_string(o.dims[1]) + " x " +
                  std::to_string(o.dims[2]));
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

TrajectoryDensity TrajectoryBinner::finish(const Vec3& end) {
  TrajectoryDensity r;
  r.volume.dims = grid_.dims;
  r.volume.origin = grid_.origin;
  r.volume.spacing = grid_.spacing;
  std::uint64_t total = 0;
  for (std::uint32_t c : array_.values<std::uint32_t>()) {
    total += c;
    r.max_visits = std::max(r.max_visits, c);
  }
  r.counted = total;
  r.discarded = discarded_;
  r.end = end;
  counts_ = nullptr;
  r.volume.point_data.add(std::move(array_), AttributeRole::Scalars);
  return r;
}

}  // namespace model_detail

TrajectoryDensity trajectory_density_fn(const std::function<Vec3(const Vec3&)>& f,
                                        const TrajectoryOptions& options) {
  if (!f) throw Error("trajectory density: the right-hand side is empty");
  return trajectory_density(f, options);
}

TrajectoryDensity lorenz_density(const LorenzParameters& p, const TrajectoryOptions& options) {
  if (!std::isfinite(p.sigma) || !std::isfinite(p.rho) || !std::isfinite(p.beta)) {
    throw Error("lorenz: the parameters must be finite (sigma " + num(p.sigma) + ", rho " +
                num(p.rho) + ", beta " + num(p.beta) + ")");
  }
  return trajectory_density([&p](const Vec3& s) { return lorenz(p, s); }, options);
}

AttractorResult lorenz_attractor(const AttractorOptions& options) {
  if (!std::isfinite(options.value))
    throw Error("lorenz attractor: the contour value is not finite");
  AttractorResult r;
  r.density = lorenz_density(options.lorenz, options.trajectory);
  ContourOptions c;
  c.values = {options.value};
  c.flip = true;  // counts are high inside: orient outward
  c.normals = options.normals;
  r.surface = contour_image(r.density.volume, c, &r.contour);
  return r;
}

}  // namespace isoforge
