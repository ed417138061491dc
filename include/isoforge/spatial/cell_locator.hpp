#pragma once
/// \file
/// Point location in the cells of any dataset: which cell contains a point (with its
/// parametric coordinates and interpolation weights) and the closest point of the cells. A
/// one-shot function and a reusable `CellLocator` that keeps its bounding volume hierarchy.
/// Used by probing, streamlines and resampling. Method: docs/algorithms/spatial.md.

#include <limits>
#include <memory>

#include "isoforge/core/cell.hpp"
#include "isoforge/core/dataset.hpp"

namespace isoforge {

struct CellLocatorOptions {
  /// Parametric tolerance of the inside test (`locate_in_cell`), ≥ 0.
  double tolerance = kDefaultCellTolerance;
  /// Points within this world distance of a vertex, line or surface cell count as on it (≥ 0;
  /// negative: 1e-6 × the dataset's bounding-box diagonal). 3D cells need no distance.
  double distance_tolerance = -1;
};

/// Where a point was found.
struct CellHit {
  Index cell = -1;       ///< the cell, or −1 when none
  int sub_id = 0;        ///< sub-cell of a composite cell (polyline, strip, poly-vertex)
  Vec3 pcoords{};        ///< parametric coordinates in the (sub-)cell
  CellWeights weights;   ///< interpolation weights of the cell's points at `pcoords`
  Vec3 closest_point{};  ///< the point of the cell closest to the query
  double dist2 = std::numeric_limits<double>::infinity();  ///< squared distance to it
  [[nodiscard]] bool found() const { return cell >= 0; }
};

/// A hierarchy of the cells' bounding boxes over a dataset (kept by reference: it must outlive
/// the locator and not change). Queries are const and thread-safe, and exact in the sense of
/// `locate_in_cell`: a point inside a cell is always found (the boxes only prune, grown by the
/// tolerances); among several cells the smallest id is returned, so answers are deterministic.
class CellLocator {
 public:
  /// \throw Error if the dataset is invalid, has more than 2^31 − 1 cells, non-finite points, or
  /// the options are negative (tolerance) or not finite.
  explicit CellLocator(DatasetRef dataset, const CellLocatorOptions& options = {});
  ~CellLocator();
  CellLocator(CellLocator&&) noexcept;
  CellLocator& operator=(CellLocator&&) noexcept;

  /// The cell containing p: a 3D cell whose parametric domain holds it (within `tolerance`), or
  /// a lower-dimensional cell within `distance_tolerance` of it whose projection is inside it.
  /// `cell` is −1 when there is none.
  [[nodiscard]] CellHit find_cell(const Vec3& p) const;

  /// The closest point of all cells to p (`cell` −1 only for a dataset without cells).
  [[nodiscard]] CellHit closest_point(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot `CellLocator::find_cell` (builds a locator; keep one for many queries).
[[nodiscard]] CellHit find_cell(DatasetRef dataset, const Vec3& p,
                                const CellLocatorOptions& options = {});
/// One-shot `CellLocator::closest_point`.
[[nodiscard]] CellHit closest_cell_point(DatasetRef dataset, const Vec3& p,
                                         const CellLocatorOptions& options = {});

}  // namespace isoforge
