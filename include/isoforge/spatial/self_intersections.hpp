#pragma once
/// \file
/// Self-intersections of a triangle mesh with exact predicates (core/predicates.hpp), and
/// `TriangleGrid`, the dynamic hash grid of triangle boxes behind incremental checks during
/// decimation and mesh optimization. Method: docs/algorithms/predicates.md.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge {

struct SelfIntersectionOptions {
  /// Stop after this many pairs (0 = find all): the result is then the first `max_pairs` pairs
  /// of the complete answer, in its order.
  std::size_t max_pairs = 0;
  ProgressCallback progress;  ///< fraction done; false cancels
};

/// Every pair (i, j), i < j, of triangles of `mesh` that `faces_intersect` (exact; faces
/// sharing a vertex or an edge by id meet legitimately there), sorted. Triangles are numbered
/// as `triangulate_faces` numbers them (polygons fan-triangulated, then strips split); faces
/// with a repeated id or collinear corners (exact) have no interior and are skipped, as
/// verify's check does; verts and lines are ignored. Parallel; the result does not depend on
/// the thread count. \throw Error on an invalid cell, a non-finite point of a face, or 2^32 or
/// more triangles.
[[nodiscard]] std::vector<std::pair<Index, Index>> self_intersections(
    const PolyData& mesh, const SelfIntersectionOptions& options = {});

/// A cell size for a `TriangleGrid` over a mesh: twice the mean edge length of its triangles,
/// enlarged until the grid over `bounds` has at most 4 cells per face (and at least 1 cell).
/// \param mean_edge mean edge length (data units; ≤ 0 or not finite: a fraction of the
/// bounds' diagonal is used). \return a positive cell size (data units).
[[nodiscard]] double triangle_grid_cell_size(const Bounds& bounds, std::size_t faces,
                                             double mean_edge);

/// The same from the triangles of `mesh` (polygons fan-triangulated, strips split).
/// \throw Error on an invalid cell.
[[nodiscard]] double triangle_grid_cell_size(const PolyData& mesh);

/// A dynamic uniform hash grid of triangle bounding boxes: faces are inserted and removed
/// with their box, and a query box finds every face whose box overlaps it. Cells are hashed
/// (open addressing) so memory follows the occupied cells; insert, remove and query cost
/// O(cells touched + faces listed there), and a query allocates nothing. Boxes are kept as
/// floats rounded outward, so the overlap test is conservative (never misses a face whose
/// double box overlaps the query). Not thread-safe for writes; concurrent queries are safe.
class TriangleGrid {
 public:
  /// A grid over `bounds` (boxes outside it are clamped into its border cells, so any box
  /// works; only speed suffers) with cubic cells of `cell_size` (data units).
  /// \throw Error if `bounds` is empty or not finite, or `cell_size` is not positive and finite.
  TriangleGrid(const Bounds& bounds, double cell_size);

  /// Adds `face` with its box [lo, hi]. A face must not be inserted twice without a removal.
  /// \throw Error if the box is not finite.
  void insert(std::uint32_t face, const Vec3& lo, const Vec3& hi);
  /// Removes `face`, given the box it was inserted with (swap-erase in each of its cells).
  /// \throw Error if the face is not in those cells (a caller's bug: the grid is then left
  /// partly updated).
  void remove(std::uint32_t face, const Vec3& lo, const Vec3& hi);

  /// Calls f(face) exactly once for every face whose (outward-rounded) box overlaps the closed
  /// box [lo, hi]; a face is reported from one cell only (the cell of the lower corner of the
  /// two boxes' intersection), so no deduplication is needed. Order: by cell, then by the
  /// order of insertions and removals. f must not modify the grid.
  template <class F>
  void for_each_candidate(const Vec3& lo, const Vec3& hi, F&& f) const;

  [[nodiscard]] std::size_t size() const { return faces_; }  ///< faces inserted
  [[nodiscard]] double cell_size() const { return cell_size_; }

 private:
  struct Entry {
    std::uint32_t face;
    float lo[3], hi[3];
  };
  using Key = std::uint64_t;
  static constexpr Key kEmpty = ~Key{0};

  struct Box {
    float lo[3], hi[3];
    int c0[3], c1[3];  // cell ranges
  };

  [[nodiscard]] Box box_of(const Vec3& lo, const Vec3& hi) const;
  [[nodiscard]] int cell_of(float x, int axis) const {
    const double t = std::floor((double(x) - origin_[axis]) * inv_cell_);
    return t <= 0 ? 0 : (t >= double(dims_[axis] - 1) ? dims_[axis] - 1 : int(t));
  }
  [[nodiscard]] static Key key_of(int i, int j, int k) {
    return Key(i) | (Key(j) << 21) | (Key(k) << 42);
  }
  [[nodiscard]] std::size_t slot_of(Key key) const {
    return std::size_t((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  /// The list of a cell, or nullptr.
  [[nodiscard]] const std::vector<Entry>* find(Key key) const {
    for (std::size_t s = slot_of(key);; s = (s + 1) & mask_) {
      if (slots_[s].key == key) return &lists_[slots_[s].list];
      if (slots_[s].key == kEmpty) return nullptr;
    }
  }
  std::vector<Entry>& find_or_add(Key key);
  void grow();

  double origin_[3] = {0, 0, 0};
  double cell_size_ = 1, inv_cell_ = 1;
  int dims_[3] = {1, 1, 1};
  struct Slot {
    Key key = kEmpty;
    std::uint32_t list = 0;  // index in lists_
  };
  std::vector<Slot> slots_;                // open-addressing table of occupied cells
  std::vector<std::vector<Entry>> lists_;  // faces per cell
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t faces_ = 0;
};

template <class F>
void TriangleGrid::for_each_candidate(const Vec3& lo, const Vec3& hi, F&& f) const {
  const Box q = box_of(lo, hi);
  for (int k = q.c0[2]; k <= q.c1[2]; ++k) {
    for (int j = q.c0[1]; j <= q.c1[1]; ++j) {
      for (int i = q.c0[0]; i <= q.c1[0]; ++i) {
        const std::vector<Entry>* list = find(key_of(i, j, k));
        if (list == nullptr) continue;
        for (const Entry& e : *list) {
          if (e.lo[0] > q.hi[0] || e.hi[0] < q.lo[0] || e.lo[1] > q.hi[1] || e.hi[1] < q.lo[1] ||
              e.lo[2] > q.hi[2] || e.hi[2] < q.lo[2]) {
            continue;
          }
          // Report from the cell holding the lower corner of the boxes' intersection only: per
          // axis max(query's first cell, face's first cell), where the face's first cell is at
          // most this one.
          if ((i != q.c0[0] && cell_of(e.lo[0], 0) != i) ||
              (j != q.c0[1] && cell_of(e.lo[1], 1) != j) ||
              (k != q.c0[2] && cell_of(e.lo[2], 2) != k)) {
            continue;
          }
          f(e.face);
        }
      }
    }
  }
}

}  // namespace isoforge
