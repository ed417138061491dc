#pragma once
/// \file
/// Trajectory densities and the Lorenz strange attractor (section 1.5.2.3, Fig. 1.25): an
/// autonomous ODE is integrated with RK4, every state after a step counts one visit at the
/// nearest sample of a volume (states outside the box are discarded, not an error), and the
/// counts are contoured. Deterministic (the trajectory is sequential). Defaults are Fig. 1.25's:
/// docs/algorithms/attractor.md.

#include <cstdint>
#include <functional>
#include <string>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

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
  std::uint64_t steps = 10'000'000;  ///< integration steps counted (after the transient), ≤ 2³²−1
  std::uint64_t transient = 0;       ///< steps integrated first and not counted
  Bounds bounds = lorenz_bounds();   ///< volume box, samples from corner to corner
  Dims dims{200, 200, 200};          ///< samples per axis (each ≥ 2)
  std::string name = "Visits";       ///< point array name (UInt32 counts)
  ProgressCallback progress;         ///< called with the fraction of steps done
};

/// What binning a trajectory counted.
struct TrajectoryStats {
  std::uint64_t counted = 0;     ///< states binned into the volume
  std::uint64_t discarded = 0;   ///< states outside the bounds
  std::uint32_t max_visits = 0;  ///< largest count of one sample
  Vec3 end{};                    ///< the state after the last step
};

/// The visit counts (UInt32 point array `name`, active scalars) and what was counted.
using TrajectoryResult = Result<ImageData, TrajectoryStats>;

/// Integrates y' = f(y) with RK4 (core/ode.hpp) and bins the states (see the file comment).
/// \throw Error on an empty f, a non-finite start or step, step ≤ 0, more than 2³²−1 steps,
/// dims < 2, empty/non-finite bounds or a volume larger than memory; `Cancelled` if `progress`
/// says so.
[[nodiscard]] TrajectoryResult trajectory_density(const std::function<Vec3(const Vec3&)>& f,
                                                  const TrajectoryOptions& options);

/// The visit counts of the Lorenz system. \throw Error as `trajectory_density`, or on
/// non-finite parameters.
[[nodiscard]] TrajectoryResult lorenz_density(const LorenzParameters& parameters = {},
                                              const TrajectoryOptions& options = {});

struct AttractorOptions {
  LorenzParameters lorenz;
  TrajectoryOptions trajectory;
  double value = 50;  ///< contour value, visits
  ContourNormals normals = ContourNormals::None;
};

/// The attractor surface and the visit-count volume it was contoured from.
struct AttractorOutput {
  PolyData surface;  ///< the contour, oriented outward (toward fewer visits)
  ImageData volume;  ///< the visit counts
};

struct AttractorStats {
  TrajectoryStats trajectory;
  ContourStats contour;
};

using AttractorResult = Result<AttractorOutput, AttractorStats>;

/// Fig. 1.25: the Lorenz density contoured at `value` (marching cubes, `contour_image` with
/// `flip` so that the surface is oriented outward). \throw Error as `lorenz_density`, or on a
/// non-finite value.
[[nodiscard]] AttractorResult lorenz_attractor(const AttractorOptions& options = {});

}  // namespace isoforge
