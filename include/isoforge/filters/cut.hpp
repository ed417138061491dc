#pragma once
/// \file
/// Cutting (section 1.5.3 of the chapter; VTK's vtkCutter / vtkPlaneCutter): the surfaces
/// F(x) = c of an implicit function through any dataset. 3D cells give polygons, 2D cells
/// line segments (joined into polylines), 1D cells points. Method, conventions and measurements:
/// docs/algorithms/cut.md.
///
/// Conventions: a point counts as *above* when F ≥ c. One output point per crossed edge (and one
/// per input point where F = c exactly, shared by every edge meeting there), so neighbouring cells
/// share their cut points. Every input point array is interpolated along the edge at the crossing,
/// every cell array copied to what its cell produced. Polygons are oriented with their normal
/// toward increasing F. A plane through image data or a structured grid takes a fast path (no
/// function call per point; image data: only the cells the plane crosses are visited).

#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/implicit/function.hpp"

namespace isoforge {

struct CutOptions {
  std::vector<double> values{0.0};     ///< cut values c (at least one, finite), units of F
  bool interpolate_attributes = true;  ///< interpolate point data, copy cell data
  bool triangulate = false;            ///< triangles (fans of the polygons) instead of polygons
  /// Place each cut point on F = c by root finding along its edge (bracketed, to the precision
  /// of double) instead of linear interpolation of the values at the edge's ends. Changes only
  /// non-linear functions (a plane's linear interpolation is already exact).
  bool refine = true;
  ProgressCallback progress;  ///< fraction done; false cancels
};

struct CutStats {
  std::size_t points = 0;         ///< output points
  std::size_t polygons = 0;       ///< polygons (or triangles) from 3D cells
  std::size_t lines = 0;          ///< polylines from 2D cells
  std::size_t vertices = 0;       ///< vertices from 1D cells
  std::size_t cells_cut = 0;      ///< input cells with points on both sides, counted once per value (general path; 0 on the fast path)
  bool fast_path = false;         ///< the plane fast path was taken
};

using CutResult = Result<PolyData, CutStats>;

/// Cuts any dataset with `f` at every value of `options.values`. The output carries the
/// interpolated point arrays, the copied cell arrays and the Int32 point array "CutValueIndex"
/// (which value each point belongs to). \throw Error if the values are empty or not finite, or
/// the dataset is invalid.
[[nodiscard]] CutResult cut(DatasetRef input, const ImplicitFunction& f,
                            const CutOptions& options = {});

/// `n` values evenly spaced from `min` to `max` inclusive (VTK's GenerateValues); n = 1 gives
/// {min} and needs min = max. \throw Error naming the problem if n < 1, a bound is not finite,
/// min > max, or n = 1 with min ≠ max.
[[nodiscard]] std::vector<double> generate_values(int n, double min, double max);

}  // namespace isoforge
