#pragma once
// Private to filters/: point location in a mesh of tetrahedra for the prober (probe.cpp): a walk
// from tetrahedron to tetrahedron across the face opposite the most negative barycentric
// coordinate, neighbours found through the cells of each point, started from a cell whose
// centroid lies in the query's bin. A walk that fails hands over to the exact CellLocator.
// Method: docs/algorithms/probe.md.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "isoforge/core/buffer.hpp"
#include "isoforge/core/dataset.hpp"

namespace isoforge::probe_detail {

class TetWalker {
 public:
  /// Whether `ug` is made of tetrahedra only (at least one).
  static bool applicable(const UnstructuredGrid& ug);
  /// `cell_ok`: empty, or one flag per cell (0 = blanked, never found). The mesh must outlive
  /// the walker and have finite points.
  TetWalker(const UnstructuredGrid& ug, std::span<const std::uint8_t> cell_ok, double tolerance);

  /// A start for a walk toward p: a cell whose centroid is in p's bin, or −1.
  [[nodiscard]] Index seed(const Vec3& p) const;
  /// Walks from `cell` (updated) toward p. True when a non-blanked tetrahedron containing p was
  /// reached (its barycentric weights in `w`, in the cell's point order); false: ask the
  /// locator (p may be outside, beyond a boundary the walk met, or the walk cycled).
  bool walk(const Vec3& p, Index& cell, std::array<double, 4>& w) const;

 private:
  [[nodiscard]] Vec3 pt(Index id) const;
  /// The cell other than `cell` holding the face opposite its point `f`: 0..n−1, or −1 when
  /// there is none; −2 when several cells share the face (an invalid mesh: the walk then scans).
  [[nodiscard]] Index neighbour(Index cell, int f) const;
  const Index* conn_ = nullptr;
  const float* pf_ = nullptr;
  const double* pd_ = nullptr;
  std::span<const std::uint8_t> cell_ok_;
  double tol_ = 0;
  std::vector<std::uint32_t> point_start_;  // cells of each point (CSR)
  Buffer<std::uint32_t> point_cells_;
  // Face neighbours, found on first need (0: not yet; else neighbour() + 1 as −1, −2 or n + 1,
  // written once by whichever thread finds it first: every thread finds the same).
  mutable Buffer<std::int32_t> neighbours_;
  Vec3 bin_lo_{}, bin_inv_{};
  std::array<Index, 3> bins_{};
  std::vector<std::int32_t> bin_seed_;  // smallest cell id whose centroid is in the bin, or −1
};

}  // namespace isoforge::probe_detail
