#pragma once
// Private to filters/: point location in a 3D structured grid for the prober (probe.cpp).
// Walking from cell to cell by Newton's method on the trilinear map of each hexahedron, and an
// exact locator over blocks of 2 x 2 x 2 cells in uniform bins for the start of a walk and for
// the points a walk cannot reach. Method: docs/algorithms/probe.md.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge::probe_detail {

/// A point found in a hexahedron: its cell and the trilinear weights of its 8 points.
struct GridHit {
  Index cell = -1;
  std::array<std::size_t, 8> ids{};  // input point ids, corner (a, b, c) at a + 2 b + 4 c
  std::array<double, 8> weights{};
};

/// Per-thread state of consecutive queries: the walk starts where the last one ended.
struct GridCursor {
  bool valid = false;
  std::array<Index, 3> cell{};
  Vec3 pcoords{0.5, 0.5, 0.5};
  Index map_cell = -1;          // the cell whose trilinear map is in `map`
  std::array<Vec3, 8> map{};    // its coefficients (probe_grid.cpp, Trilinear)
};

class GridLocator {
 public:
  /// `cell_ok`: empty, or one flag per cell (0 = blanked, never found). The grid must be 3D
  /// (all dims > 1), with finite points, and outlive the locator.
  GridLocator(const StructuredGrid& grid, std::span<const std::uint8_t> cell_ok, double tolerance);
  ~GridLocator();
  GridLocator(GridLocator&&) noexcept;
  GridLocator& operator=(GridLocator&&) noexcept;

  /// The smallest-id non-blanked cell containing p (exact), or the cell a walk from `cursor`
  /// reaches first (equally containing p). False when no cell contains p. Updates `cursor`.
  bool find(const Vec3& p, GridCursor& cursor, GridHit& hit) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isoforge::probe_detail
