#pragma once
// Private to filters/: point location in a 3D structured grid for the prober (probe.cpp).
// Walking from cell to cell by Newton's method on the trilinear map of each hexahedron, and an
// exact locator over blocks of 2 x 2 x 2 cells in uniform bins for the start of a walk and for
// the points a walk cannot reach. Method: docs/algorithms/probe.md.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge::probe_detail {

/// A point found in a hexahedron: its cell, the id of its corner (0, 0, 0) and the point's
/// parametric coordinates there, in [0, 1]. Corner (a, b, c) is point base + offset[a + 2b +
/// 4c] (GridLocator::offsets), of trilinear weight (a ? r : 1 − r)(b ? s : 1 − s)(c ? t : 1 − t).
struct GridHit {
  Index cell = -1;
  std::size_t base = 0;
  double r = 0, s = 0, t = 0;
};

/// Per-thread state of consecutive queries: the walk starts where the last one ended, from
/// the coordinates predicted by the last point's inverse Jacobian (one Newton step saved).
struct GridCursor {
  bool valid = false;
  std::array<Index, 3> cell{};
  Vec3 pcoords{0.5, 0.5, 0.5};
  Index map_cell = -1;             // the cell whose trilinear map is in `map`
  std::array<double, 24> map{};    // its coefficients (probe_grid.cpp, make_map)
  bool predict = false;            // `last` and `jinv` hold: `cell` contained `last` at `pcoords`
  Vec3 last{};                     // the point last found
  std::array<double, 9> jinv{};    // the inverse Jacobian of `map` there, by rows
};

/// Where GridLocator::scan_image writes the points it finds: hit q (q < size) is point out[q],
/// found in cell[q] at hit[q]. When `size` reaches `capacity`, the scan calls `full()`, which
/// takes the hits and sets `size` to 0.
class GridHitSink {
 public:
  std::size_t size = 0, capacity = 0;
  std::size_t* out = nullptr;
  Index* cell = nullptr;
  GridHit* hit = nullptr;
  virtual void full() = 0;

 protected:
  ~GridHitSink() = default;
};

/// An image probe cut into slabs of consecutive layers (along its last axis of more than one
/// point), each listing, in increasing id order, the cells whose boxes meet the slab's points.
struct ImagePlan {
  Dims dims{};
  Vec3 origin{}, spacing{}, inverse{};      // inverse: 1 / spacing
  int axis = 2;                             // the slab axis
  Index layers = 1;                         // image layers per slab
  std::size_t stride = 1;                   // point ids per layer
  std::vector<std::uint32_t> start, cells;  // slab s: cells[start[s]] .. cells[start[s + 1] - 1]

  [[nodiscard]] std::size_t slabs() const { return start.empty() ? 0 : start.size() - 1; }
  /// The slab's point ids: [first, second).
  [[nodiscard]] std::pair<std::size_t, std::size_t> points(std::size_t slab) const;
};

/// Tests: makes `scan_image` use its portable Newton kernel (SSE) even where the processor has
/// AVX2 and FMA (true), or choose by the processor again (false).
void use_portable_kernel(bool portable);

class GridLocator {
 public:
  /// `cell_ok`: empty, or one flag per cell (0 = blanked, never found). The grid must be 3D
  /// (all dims > 1), with finite points, and outlive the locator.
  GridLocator(const StructuredGrid& grid, std::span<const std::uint8_t> cell_ok, double tolerance);
  ~GridLocator();
  GridLocator(GridLocator&&) noexcept;
  GridLocator& operator=(GridLocator&&) noexcept;

  /// Builds the exact locator that `find` uses, once (`find` calls it; call it before finding
  /// in parallel, so that no thread waits for another's build inside a task).
  void prepare() const;
  /// The smallest-id non-blanked cell containing p (exact), or the cell a walk from `cursor`
  /// reaches first (equally containing p). False when no cell contains p. Updates `cursor`.
  bool find(const Vec3& p, GridCursor& cursor, GridHit& hit) const;
  /// Prefetches the corners (points, and `values` tuples of `tuple_bytes` each when not null) of
  /// the cell predicted to hold p from the cursor's last find (its inverse Jacobian): a hint for
  /// a query to come, no search; nothing when the cursor has no prediction.
  void prefetch(const Vec3& p, const GridCursor& cursor, const std::byte* values,
                std::size_t tuple_bytes) const;
  /// Whether `scan_image` can locate the points of `image` (finite origin, finite non-zero
  /// spacing along its axes of more than one point, fewer than 2^32 cells).
  [[nodiscard]] bool can_scan(const ImageData& image) const;
  /// The slabs of `image` (can_scan), about `slabs` of them, and the cells meeting each.
  [[nodiscard]] ImagePlan plan_image(const ImageData& image, std::size_t slabs) const;
  /// Every point of slab `slab` in some non-blanked cell, found in the smallest-id such cell
  /// (as `find` without a cursor), given to `sink`, its `owned` flag (indexed by point id, 0 on
  /// entry for the slab's points) set to 1. Cell by cell: the image points in each cell's box
  /// whose coordinates, predicted from the trilinear map linearized at the cell's centre, can
  /// lie in it (a rigorous bound on the nonlinear terms) are solved by Newton's method.
  void scan_image(const ImagePlan& plan, std::size_t slab, std::uint8_t* owned,
                  GridHitSink& sink) const;
  /// The point ids of a cell's corners relative to its corner (0, 0, 0), corner (a, b, c) at
  /// a + 2b + 4c.
  [[nodiscard]] std::array<std::size_t, 8> offsets() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isoforge::probe_detail
