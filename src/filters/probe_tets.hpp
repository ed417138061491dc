#pragma once
// Private to filters/: point location in a mesh of tetrahedra for the prober (probe.cpp) and the
// streamline tracer (streamline.cpp): a walk from tetrahedron to tetrahedron across the face
// opposite the most negative barycentric coordinate, started from a cell whose centroid lies in
// the query's bin. Face neighbours are matched once, when the walker is built, and stored beside
// each cell's points (one 32-byte record per cell: a step of the walk touches one cache line). A
// walk that fails hands over to the exact CellLocator.
// Method: docs/algorithms/probe.md.

#include <array>
#include <cmath>
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
  /// The gradients of the 3 components of `values` (float or double triples, one per point) in
  /// `cell`, where linear interpolation makes them constant; false for a degenerate cell.
  template <class T>
  bool gradient(Index cell, const T* values, std::array<Vec3, 3>& grad) const;
  /// The points of `cell` (its connectivity, as 32-bit ids).
  [[nodiscard]] const std::uint32_t* points_of(Index cell) const {
    return tets_[std::size_t(cell)].v;
  }
  /// Whether p is inside the mesh's bounds grown by the tolerance (outside them no cell holds p).
  [[nodiscard]] bool in_bounds(const Vec3& p) const;
  /// Walks from `cell` (updated) toward p. True when a non-blanked tetrahedron containing p was
  /// reached (its barycentric weights in `w`, in the cell's point order); false: ask the
  /// locator (p may be outside, beyond a boundary the walk met, or the walk cycled).
  bool walk(const Vec3& p, Index& cell, std::array<double, 4>& w) const;

 private:
  [[nodiscard]] Vec3 pt(std::uint32_t id) const;
  /// A cell's points and, opposite each point f, the other cell holding that face: its id, −1
  /// when there is none (a boundary face), −2 when several share it (an invalid mesh: the walk
  /// then scans the cells of the face's points).
  struct Tet {
    std::uint32_t v[4];
    std::int32_t n[4];
  };
  const float* pf_ = nullptr;
  const double* pd_ = nullptr;
  std::span<const std::uint8_t> cell_ok_;
  double tol_ = 0;
  Buffer<Tet> tets_;
  std::vector<std::uint32_t> point_start_;  // cells of each point (CSR)
  Buffer<std::uint32_t> point_cells_;
  Bounds bounds_;  // of the points, grown by the tolerance
  Vec3 bin_lo_{}, bin_inv_{};
  std::array<Index, 3> bins_{};
  std::vector<std::int32_t> bin_seed_;  // smallest cell id whose centroid is in the bin, or −1
};

inline Vec3 TetWalker::pt(std::uint32_t id) const {
  if (pf_) {
    const float* q = pf_ + 3 * std::size_t(id);
    return {q[0], q[1], q[2]};
  }
  const double* q = pd_ + 3 * std::size_t(id);
  return {q[0], q[1], q[2]};
}

template <class T>
bool TetWalker::gradient(Index cell, const T* values, std::array<Vec3, 3>& grad) const {
  const std::uint32_t* v = tets_[std::size_t(cell)].v;
  const Vec3 p0 = pt(v[0]);
  const Vec3 e1 = pt(v[1]) - p0, e2 = pt(v[2]) - p0, e3 = pt(v[3]) - p0;
  const Vec3 g1 = cross(e2, e3), g2 = cross(e3, e1), g3 = cross(e1, e2);
  const double det = dot(e1, g1);
  if (!(std::abs(det) > 1e-300)) return false;
  const double inv = 1.0 / det;
  const T* u0 = values + 3 * std::size_t(v[0]);
  const T* u1 = values + 3 * std::size_t(v[1]);
  const T* u2 = values + 3 * std::size_t(v[2]);
  const T* u3 = values + 3 * std::size_t(v[3]);
  for (std::size_t c = 0; c < 3; ++c) {
    const double d1 = double(u1[c]) - double(u0[c]), d2 = double(u2[c]) - double(u0[c]),
                 d3 = double(u3[c]) - double(u0[c]);
    grad[c] = (g1 * d1 + g2 * d2 + g3 * d3) * inv;
  }
  return true;
}

}  // namespace isoforge::probe_detail
