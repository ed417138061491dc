#pragma once
/// \file
/// Fitting a geometric primitive — plane, sphere, cylinder, cone or general quadric — to the
/// points of any dataset: a closed-form or algebraic initialisation, then a robust nonlinear
/// least-squares refinement of the geometric distances. The result is an `ImplicitFunction`
/// (and its expression in the `-f` language of docs/implicit.md), so a fitted shape can be
/// sampled, contoured or combined like any other. Method and measurements:
/// docs/algorithms/fitting.md.

#include <cstddef>
#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/implicit/function.hpp"

namespace isoforge {

/// The shapes `fit_primitive` fits.
enum class PrimitiveKind { Plane, Sphere, Cylinder, Cone, Quadric };

/// Loss applied to each residual r (a distance) with scale a: None r², Huber (quadratic up to a,
/// linear beyond), Cauchy a² log(1 + r²/a²) (outliers far beyond a barely count).
enum class RobustLoss { None, Huber, Cauchy };

struct FitOptions {
  PrimitiveKind kind = PrimitiveKind::Plane;
  RobustLoss loss = RobustLoss::Huber;
  /// Scale a of the robust loss, data units (≥ 0). 0 = automatic: σ = 1.4826 × the median
  /// |residual| of the initial fit, a = 1.345 σ (Huber) or 2.385 σ (Cauchy); σ is re-estimated
  /// from each robust fit and the fit repeated until σ settles (at most 8 solves).
  double loss_scale = 0;
  /// Use a 3-component point array "Normals" (or the active normals) when present to initialise
  /// the plane's orientation, the cylinder's axis and the cone's apex.
  bool use_normals = true;
  int max_iterations = 100;   ///< Levenberg–Marquardt iterations per solve (≥ 1)
  ProgressCallback progress;  ///< fraction done; false cancels
};

/// A fitted primitive. `parameters` by kind (distances in data units, directions unit length):
/// - Plane: nx, ny, nz, d — the plane n·x = d, signed distance n·x − d;
/// - Sphere: cx, cy, cz, r;
/// - Cylinder: px, py, pz, ax, ay, az, r — p the point of the axis nearest the points' centroid;
/// - Cone: apex xyz, axis xyz, half angle in degrees (0, 90) — a double cone, as implicit/;
/// - Quadric: a0..a9 in the order of `ImplicitFunction::quadric`, scaled so that the mean
///   gradient norm over the points is 1 (the value approximates a distance near the points).
struct FittedPrimitive {
  PrimitiveKind kind = PrimitiveKind::Plane;
  std::vector<double> parameters;
  std::string expression;    ///< `function` in the expression language (parse_implicit reads it)
  ImplicitFunction function  ///< signed distance (algebraic for the quadric), negative inside
      = ImplicitFunction::sphere({0, 0, 0}, 1);
};

struct FitStats {
  std::size_t points = 0;  ///< points fitted
  /// Residuals of the final fit over all points: geometric distance (the quadric: the first-order
  /// distance |Q| / |∇Q|), data units.
  double rms = 0, max_abs = 0, median_abs = 0;
  /// Points with |r| ≤ 2.5 σ, σ = 1.4826 × median |r| (the robust scale of the final residuals).
  std::size_t inliers = 0;
  int iterations = 0;      ///< solver iterations over all solves
  bool converged = false;  ///< the last solve met its tolerances (not stopped by max_iterations)
};

using FitResult = Result<FittedPrimitive, FitStats>;

/// Fits `options.kind` to the points of `points` (cells are ignored).
/// \throw Error naming the problem: too few points for the kind (plane 3, sphere 4, cylinder, cone
/// and quadric 9), a non-finite point (its id), an option out of range, or a degenerate
/// configuration (collinear points for a plane, coplanar ones for a sphere, points that do not
/// determine a quadric, ...).
[[nodiscard]] FitResult fit_primitive(DatasetRef points, const FitOptions& options);

/// "plane", "sphere", "cylinder", "cone", "quadric"; "none", "huber", "cauchy".
[[nodiscard]] const char* to_string(PrimitiveKind kind);
[[nodiscard]] const char* to_string(RobustLoss loss);

}  // namespace isoforge
