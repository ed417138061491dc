#pragma once
/// \file
/// Visualizing mathematical descriptions (section 1.5.2.3, Fig. 1.25): the Lorenz strange
/// attractor as a surface. The Lorenz system
///
///     dx/dt = σ (y − x),   dy/dt = ρ x − y − x z,   dz/dt = x y − β z
///
/// is integrated with the classical fourth-order Runge–Kutta method from a start point for N
/// steps of size h; every state after a step is binned into the nearest sample of a volume
/// (counting visits), and the volume is contoured at a visit count. The same is available for any
/// autonomous ODE right-hand side (`trajectory_density`).
///
/// **Defaults** (Fig. 1.25; VTK's Lorenz example, Examples/Visualization/Lorenz): σ = 10,
/// ρ = 28, β = 8/3; 10 million steps of h = 0.01 from (0.1, 0.1, 0.1); 200³ samples spanning
/// x, y ∈ [−30, 30], z ∈ [−10, 60] corner to corner; contour at 50 visits. VTK's example uses
/// forward Euler (here RK4: same trajectory shape, correct to O(h⁴) per unit time), β = 2.667
/// and a random start; it bins by truncation into the sample at a cell's lower corner, here into
/// the nearest sample.
///
/// **Binning.** A state inside the bounds counts one visit at the sample nearest to it
/// (round((x − x0) / spacing) per axis); a state outside the bounds is *discarded* (counted in
/// `TrajectoryDensity::discarded`, not an error). `transient` initial steps are integrated but
/// not counted. Deterministic (one thread: the trajectory is sequential).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge {

/// Parameters of the Lorenz system.
struct LorenzParameters {
  double sigma = 10.0;      ///< σ, the Prandtl number
  double rho = 28.0;        ///< ρ, the Rayleigh number
  double beta = 8.0 / 3.0;  ///< β, the geometric factor
};

/// The Lorenz right-hand side at state s.
[[nodiscard]] inline Vec3 lorenz(const LorenzParameters& p, const Vec3& s) {
  return {p.sigma * (s.y - s.x), s.x * (p.rho - s.z) - s.y, s.x * s.y - p.beta * s.z};
}

/// One classical Runge–Kutta (RK4) step of size h of the autonomous system y' = f(y).
template <class F>
[[nodiscard]] inline Vec3 rk4_step(F&& f, const Vec3& y, double h) {
  const Vec3 k1 = f(y);
  const Vec3 k2 = f(y + k1 * (0.5 * h));
  const Vec3 k3 = f(y + k2 * (0.5 * h));
  const Vec3 k4 = f(y + k3 * h);
  return y + (k1 + 2.0 * k2 + 2.0 * k3 + k4) * (h / 6.0);
}

/// The Lorenz example's box: x, y ∈ [−30, 30], z ∈ [−10, 60].
[[nodiscard]] inline Bounds lorenz_bounds() {
  Bounds b;
  b.min = {-30, -30, -10};
  b.max = {30, 30, 60};
  return b;
}

struct TrajectoryOptions {
  Vec3 start{0.1, 0.1, 0.1};         ///< initial state
  double step = 0.01;                ///< h, time units
  std::uint64_t steps = 10'000'000;  ///< integration steps counted (after the transient)
  std::uint64_t transient = 0;       ///< steps integrated first and not counted
  Bounds bounds = lorenz_bounds();   ///< volume box, samples from corner to corner
  Dims dims{200, 200, 200};          ///< samples per axis (each ≥ 2)
  std::string name = "Visits";       ///< point array name (UInt32 counts)
  ProgressCallback progress;         ///< called with the fraction of steps done
};

/// Result of binning a trajectory.
struct TrajectoryDensity {
  ImageData volume;              ///< visit counts (UInt32 point array, active scalars)
  std::uint64_t counted = 0;     ///< states binned into the volume
  std::uint64_t discarded = 0;   ///< states outside the bounds
  std::uint32_t max_visits = 0;  ///< largest count of one sample
  Vec3 end{};                    ///< the state after the last step
};

namespace model_detail {

/// Validates the options, allocates the counts and bins states (the non-template part of
/// `trajectory_density`).
class TrajectoryBinner {
 public:
  explicit TrajectoryBinner(const TrajectoryOptions& options);
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
  [[nodiscard]] TrajectoryDensity finish(const Vec3& end);

 private:
  double o_[3], inv_[3], lim_[3];
  std::uint64_t nx_, ny_;
  std::uint32_t* counts_ = nullptr;
  DataArray array_;
  GridSpec grid_;
  std::uint64_t discarded_ = 0;
};

void check_trajectory_start(const TrajectoryOptions& options);

}  // namespace model_detail

/// Integrates y' = f(y) (f: `Vec3 f(const Vec3&)`, any callable) with RK4 and bins the states
/// (see the file comment). \throw Error on a non-finite start or step, step ≤ 0, dims < 2, or
/// empty/non-finite bounds; `Cancelled` if `progress` says so.
template <class F>
[[nodiscard]] TrajectoryDensity trajectory_density(F&& f, const TrajectoryOptions& options) {
  model_detail::check_trajectory_start(options);
  model_detail::TrajectoryBinner binner(options);
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

/// `trajectory_density` for a right-hand side given as a std::function.
[[nodiscard]] TrajectoryDensity trajectory_density_fn(const std::function<Vec3(const Vec3&)>& f,
                                                      const TrajectoryOptions& options);

/// The visit counts of the Lorenz system. \throw Error as `trajectory_density`, or on
/// non-finite parameters.
[[nodiscard]] TrajectoryDensity lorenz_density(const LorenzParameters& parameters = {},
                                               const TrajectoryOptions& options = {});

struct AttractorOptions {
  LorenzParameters lorenz;
  TrajectoryOptions trajectory;
  double value = 50;  ///< contour value, visits
  ContourNormals normals = ContourNormals::None;
};

struct AttractorResult {
  PolyData surface;           ///< the contour, oriented outward (toward fewer visits)
  TrajectoryDensity density;  ///< the counts and trajectory statistics
  ContourStats contour;
};

/// Fig. 1.25: the Lorenz density contoured at `value` (marching cubes, `contour_image` with
/// `flip` so that the surface is oriented outward). \throw Error as `lorenz_density`, or on a
/// non-finite value.
[[nodiscard]] AttractorResult lorenz_attractor(const AttractorOptions& options = {});

}  // namespace isoforge
