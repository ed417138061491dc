#pragma once
/// \file
/// Probing (the chapter's Fig. 1.35; VTK's vtkProbeFilter): the input dataset sampled at the
/// points of a probe dataset. A one-shot `probe` and a reusable `Prober` that keeps its point
/// locator for repeated probes, plus generators of line, plane and volume probes.
/// Method and measurements: docs/algorithms/probe.md.

#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include "isoforge/core/cell.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

struct ProbeOptions {
  /// Parametric tolerance of the inside test (≥ 0): a point counts as inside a cell when its
  /// parametric coordinates are within this of the cell's domain (`locate_in_cell`).
  double tolerance = kDefaultCellTolerance;
  /// World distance within which a point counts as on a vertex, line or surface cell (≥ 0;
  /// negative: 1e-6 × the input's bounding-box diagonal). 3D cells need none.
  double distance_tolerance = -1;
  /// Value of floating-point arrays at points not found (any value; NaN by default). Integer
  /// arrays get it rounded and clamped to their type, or 0 when it is NaN.
  double nil_value = std::numeric_limits<double>::quiet_NaN();
  /// Name of the output's UInt8 validity array: 1 where the point was found in a cell, else 0.
  std::string mask_name = "vtkValidPointMask";
  /// Input point array (any type, one component) whose zero entries blank their points: a cell
  /// with a blanked point is never found (PLOT3D "IBlank"). Ignored when the input lacks it.
  std::string point_blanking = "IBlank";
  /// Input cell array (any type, one component) whose zero entries blank their cells (the
  /// PLOT3D reader's "Valid"). Ignored when the input lacks it.
  std::string cell_validity = "Valid";
  ProgressCallback progress;  ///< fraction done; false cancels
};

struct ProbeStats {
  std::size_t points = 0;   ///< probe points
  std::size_t found = 0;    ///< points found in a (non-blanked) cell of the input
  std::size_t blanked = 0;  ///< input cells skipped as blanked
};

/// The probe's structure and type (its points, cells and dims; none of its arrays) with the
/// input's point arrays interpolated and its cell arrays copied as point arrays (a cell array
/// named like a point array is renamed "NAME (cell)"), and the mask array.
using ProbeResult = Result<Dataset, ProbeStats>;

/// The input of repeated probes with its point locator, built once: arithmetic for image data;
/// for a 3D structured grid a walk through its hexahedra (Newton's method) completed by an exact
/// locator over blocks of cells; for a mesh of tetrahedra a walk completed by a `CellLocator`
/// (built on first need); a `CellLocator` for every other dataset. Every point inside a
/// non-blanked cell is found. Keeps a reference to the input: it must outlive the prober and
/// not change. `probe` is const and thread-safe; its output does not depend on the thread count.
class Prober {
 public:
  /// \throw Error if the input is invalid, has non-finite points, or the options are out of
  /// range (negative or non-finite tolerances, an empty mask name, a blanking array with more
  /// than one component).
  explicit Prober(DatasetRef input, const ProbeOptions& options = {});
  ~Prober();
  Prober(Prober&&) noexcept;
  Prober& operator=(Prober&&) noexcept;

  /// Samples the input at the points of `probe` (any dataset). \throw Error if the probe is
  /// invalid, `Cancelled` through the progress callback.
  [[nodiscard]] ProbeResult probe(DatasetRef probe) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot `Prober(input, options).probe(probe)`.
[[nodiscard]] ProbeResult probe(DatasetRef input, DatasetRef probe,
                                const ProbeOptions& options = {});

/// A line probe: n ≥ 1 points evenly spaced from p0 to p1 (p0 alone when n is 1) joined by
/// one polyline. \throw Error if n < 1 or a point is not finite.
[[nodiscard]] PolyData probe_line(const Vec3& p0, const Vec3& p1, Index n);

/// A plane probe (vtkPlaneSource's convention): nu × nv points spanning the parallelogram
/// origin + u (p1 − origin) + v (p2 − origin), u, v in [0, 1], point (a, b) at id a + nu b,
/// joined by (nu − 1)(nv − 1) quads. \throw Error if nu or nv < 2, a point is not finite or the
/// two axes are parallel or of zero length.
[[nodiscard]] PolyData probe_plane(const Vec3& origin, const Vec3& p1, const Vec3& p2, Index nu,
                                   Index nv);

/// A volume probe: image data of `dims` points spanning `box` (an axis of zero extent gets
/// spacing 1). \throw Error if the box is empty or not finite or a dimension is < 1.
[[nodiscard]] ImageData probe_volume(const Bounds& box, const Dims& dims);

}  // namespace isoforge
