// Point location in a 3D structured grid (probe_grid.hpp).
//
// References implemented:
// - W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit* (4th ed.), 8.x: point
//   location in curvilinear grids by walking from cell to cell using the parametric coordinates
//   of the point in the current cell, found by Newton's method on the trilinear map.

#include "probe_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "isoforge/core/cell.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge::probe_detail {

namespace {

/// The walk gives up (and asks the exact locator) after this many cells.
constexpr int kMaxWalkSteps = 32;
/// Largest jump of the walk along one axis in one step, in cells.
constexpr double kMaxJump = 8;
/// Newton's method: iteration cap, and the step below which the iterate has converged (the
/// error after such a step is of the order of its square, 1e-12: far below the parametric
/// tolerance).
constexpr int kMaxNewton = 24;
constexpr double kNewtonStep = 1e-6;
/// Block edge in cells of the exact locator.
constexpr Index kBlock = 2;

/// The trilinear map X = a + b r + c s + d t + e rs + f rt + g st + h rst of a hexahedron with
/// corners x[ia + 2 ib + 4 ic], as its 8 coefficients.
void make_map(const std::array<Vec3, 8>& x, std::array<Vec3, 8>& m) {
  m[0] = x[0];
  m[1] = x[1] - x[0];
  m[2] = x[2] - x[0];
  m[3] = x[4] - x[0];
  m[4] = x[3] - x[1] - x[2] + x[0];
  m[5] = x[5] - x[1] - x[4] + x[0];
  m[6] = x[6] - x[2] - x[4] + x[0];
  m[7] = x[7] - x[3] - x[5] - x[6] + x[1] + x[2] + x[4] - x[0];
}

/// Parametric coordinates of p by Newton's method from `pc`; false if it did not converge.
bool solve(const std::array<Vec3, 8>& m, const Vec3& p, Vec3& pc) {
  double r = pc.x, s = pc.y, t = pc.z;
  const Vec3 &a = m[0], &b = m[1], &c = m[2], &d = m[3], &e = m[4], &f = m[5], &g = m[6],
             &h = m[7];
  for (int it = 0; it < kMaxNewton; ++it) {
    // X and its derivatives in nested form: u = e + t h, jr = dX/dr = b + s u + t f, ...
    const Vec3 u = e + h * t;
    const Vec3 cg = c + g * t;
    const Vec3 jr = b + u * s + f * t;
    const Vec3 js = cg + u * r;
    const Vec3 jt = d + (f + h * s) * r + g * s;
    const Vec3 F = a + jr * r + cg * s + d * t - p;
    const Vec3 c0 = cross(js, jt);
    const double det = dot(jr, c0);
    // A singular Jacobian; a nearly singular one (a degenerate cell) makes the iteration diverge
    // or stall, which is caught below and leaves the cell to locate_in_cell.
    if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
    const double inv = 1.0 / det;
    const double dr = dot(F, c0) * inv;
    const double ds = dot(jr, cross(F, jt)) * inv;
    const double dt = dot(jr, cross(js, F)) * inv;
    r -= dr;
    s -= ds;
    t -= dt;
    if (!(std::abs(r) < 1e6 && std::abs(s) < 1e6 && std::abs(t) < 1e6)) return false;
    if (std::max({std::abs(dr), std::abs(ds), std::abs(dt)}) < kNewtonStep) {
      pc = {r, s, t};
      return true;
    }
  }
  return false;
}

float down(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float up(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

struct Box {
  float lo[3], hi[3];
  [[nodiscard]] bool contains(const Vec3& p) const {
    return p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1] && p.z >= lo[2] &&
           p.z <= hi[2];
  }
};

}  // namespace

struct GridLocator::Impl {
  Index nx = 0, ny = 0, nz = 0, cx = 0, cy = 0, cz = 0, bx = 0, by = 0, bz = 0;
  double tol = 0;
  const float* pf = nullptr;
  const double* pd = nullptr;
  std::span<const std::uint8_t> cell_ok;
  std::vector<Box> cell_box, block_box;
  Box all{};
  Vec3 bin_lo{}, bin_inv{};
  std::array<Index, 3> bins{};
  std::vector<std::uint32_t> bin_start, bin_blocks;

  [[nodiscard]] Vec3 pt(Index id) const {
    if (pf) {
      const float* q = pf + 3 * id;
      return {q[0], q[1], q[2]};
    }
    const double* q = pd + 3 * id;
    return {q[0], q[1], q[2]};
  }
  [[nodiscard]] Index cell_id(Index i, Index j, Index k) const { return i + cx * (j + cy * k); }
  [[nodiscard]] Index point_id(Index i, Index j, Index k) const { return i + nx * (j + ny * k); }

  void corner_ids(Index i, Index j, Index k, std::array<std::size_t, 8>& ids) const {
    const auto base = std::size_t(point_id(i, j, k)), sj = std::size_t(nx),
               sk = std::size_t(nx * ny);
    ids = {base, base + 1, base + sj, base + sj + 1, base + sk, base + sk + 1, base + sk + sj,
           base + sk + sj + 1};
  }
  void corners(Index i, Index j, Index k, std::array<Vec3, 8>& x,
               std::array<std::size_t, 8>& ids) const {
    corner_ids(i, j, k, ids);
    for (int c = 0; c < 8; ++c) x[std::size_t(c)] = pt(Index(ids[std::size_t(c)]));
  }

  /// Whether cell (i, j, k) contains p; its parametric coordinates in `pc` (start: `pc`).
  /// Newton on the trilinear map; `locate_in_cell` when it does not converge.
  bool test(const std::array<std::size_t, 8>& ids, const std::array<Vec3, 8>& map,
            const Vec3& p, Vec3& pc, bool& inside) const {
    if (solve(map, p, pc)) {
      inside = pc.x >= -tol && pc.x <= 1 + tol && pc.y >= -tol && pc.y <= 1 + tol &&
               pc.z >= -tol && pc.z <= 1 + tol;
      return true;
    }
    std::array<Vec3, 8> vtk;  // VTK's hexahedron order
    const int order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    for (int c = 0; c < 8; ++c) vtk[std::size_t(c)] = pt(Index(ids[std::size_t(order[c])]));
    const CellPosition pos = locate_in_cell(CellType::Hexahedron, vtk, p, tol);
    inside = pos.inside;
    pc = pos.pcoords;
    return pos.converged;
  }

  void fill(Index i, Index j, Index k, const std::array<std::size_t, 8>& ids, const Vec3& pc,
            GridHit& hit) const {
    hit.cell = cell_id(i, j, k);
    hit.ids = ids;
    const double r = std::clamp(pc.x, 0.0, 1.0), s = std::clamp(pc.y, 0.0, 1.0),
                 t = std::clamp(pc.z, 0.0, 1.0);
    for (int c = 0; c < 8; ++c) {
      hit.weights[std::size_t(c)] = ((c & 1) ? r : 1 - r) * (((c >> 1) & 1) ? s : 1 - s) *
                                    (((c >> 2) & 1) ? t : 1 - t);
    }
  }

  [[nodiscard]] bool ok(Index cell) const {
    return cell_ok.empty() || cell_ok[std::size_t(cell)] != 0;
  }

  /// The walk from the cursor's cell; false: ask the exact locator.
  bool walk(const Vec3& p, GridCursor& cur, GridHit& hit) const {
    std::array<Vec3, 8> x;
    std::array<std::size_t, 8> ids;
    Vec3 pc = cur.pcoords;
    for (int step = 0; step < kMaxWalkSteps; ++step) {
      const auto [i, j, k] = cur.cell;
      const Index cell = cell_id(i, j, k);
      if (cur.map_cell != cell) {
        corners(i, j, k, x, ids);
        make_map(x, cur.map);
        cur.map_cell = cell;
      } else {
        corner_ids(i, j, k, ids);
      }
      bool inside = false;
      if (!test(ids, cur.map, p, pc, inside)) return false;
      if (inside) {
        if (!ok(cell)) return false;
        fill(i, j, k, ids, pc, hit);
        cur.pcoords = pc;
        return true;
      }
      const Index lim[3] = {cx, cy, cz};
      bool moved = false;
      for (int a = 0; a < 3; ++a) {
        const double v = pc[a];
        double jump = 0;
        if (v < -tol) jump = std::max(-kMaxJump, std::floor(v));
        if (v > 1 + tol) jump = std::min(kMaxJump, std::floor(v));
        const Index next = std::clamp(cur.cell[std::size_t(a)] + Index(jump), Index{0}, lim[a] - 1);
        pc[a] = std::clamp(v - double(next - cur.cell[std::size_t(a)]), 0.0, 1.0);  // next start
        moved = moved || next != cur.cell[std::size_t(a)];
        cur.cell[std::size_t(a)] = next;
      }
      if (!moved) return false;  // p beyond the grid's boundary here: maybe outside
    }
    return false;
  }

  /// Exact: the smallest-id non-blanked cell containing p.
  bool exact(const Vec3& p, GridCursor& cur, GridHit& hit) const {
    if (!all.contains(p)) return false;
    Index bin[3];
    for (int a = 0; a < 3; ++a) {
      bin[a] = std::clamp(Index((p[a] - bin_lo[a]) * bin_inv[a]), Index{0}, bins[std::size_t(a)] - 1);
    }
    const std::size_t b = std::size_t(bin[0] + bins[0] * (bin[1] + bins[1] * bin[2]));
    Index best = -1;
    Vec3 best_pc{};
    std::array<Vec3, 8> x, map;
    std::array<std::size_t, 8> ids;
    for (std::uint32_t e = bin_start[b]; e < bin_start[b + 1]; ++e) {
      const Index blk = bin_blocks[e];
      if (!block_box[std::size_t(blk)].contains(p)) continue;
      const Index bi = blk % bx, bj = (blk / bx) % by, bk = blk / (bx * by);
      for (Index k = bk * kBlock; k < std::min(cz, (bk + 1) * kBlock); ++k)
        for (Index j = bj * kBlock; j < std::min(cy, (bj + 1) * kBlock); ++j)
          for (Index i = bi * kBlock; i < std::min(cx, (bi + 1) * kBlock); ++i) {
            const Index cell = cell_id(i, j, k);
            if ((best >= 0 && cell > best) || !ok(cell) || !cell_box[std::size_t(cell)].contains(p)) continue;
            corners(i, j, k, x, ids);
            make_map(x, map);
            Vec3 pc{0.5, 0.5, 0.5};
            bool inside = false;
            (void)test(ids, map, p, pc, inside);
            if (inside) {
              best = cell;
              best_pc = pc;
            }
          }
    }
    if (best < 0) return false;
    const Index i = best % cx, j = (best / cx) % cy, k = best / (cx * cy);
    corners(i, j, k, x, ids);
    fill(i, j, k, ids, best_pc, hit);
    cur.valid = true;
    cur.cell = {i, j, k};
    cur.pcoords = best_pc;
    return true;
  }
};

GridLocator::GridLocator(const StructuredGrid& grid, std::span<const std::uint8_t> cell_ok,
                         double tolerance)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.nx = grid.dims[0];
  m.ny = grid.dims[1];
  m.nz = grid.dims[2];
  m.cx = m.nx - 1;
  m.cy = m.ny - 1;
  m.cz = m.nz - 1;
  m.tol = tolerance;
  m.cell_ok = cell_ok;
  if (grid.points.type() == ScalarType::Float32) {
    m.pf = grid.points.floats().data();
  } else {
    m.pd = grid.points.array().values<double>().data();
  }
  // Cell boxes, grown so that every point the parametric tolerance admits is in them.
  const std::size_t nc = std::size_t(m.cx * m.cy * m.cz);
  m.cell_box.resize(nc);
  parallel_for_range(nc, 4096, [&](std::size_t c0, std::size_t c1) {
    std::array<Vec3, 8> x;
    std::array<std::size_t, 8> ids;
    for (std::size_t c = c0; c < c1; ++c) {
      const Index cell = Index(c);
      m.corners(cell % m.cx, (cell / m.cx) % m.cy, cell / (m.cx * m.cy), x, ids);
      Bounds b;
      for (const Vec3& q : x) b.extend(q);
      const double grow = (1e-6 + 4 * tolerance) * b.diagonal() +
                          1e-12 * (std::abs(b.min.x) + std::abs(b.min.y) + std::abs(b.min.z) +
                                   std::abs(b.max.x) + std::abs(b.max.y) + std::abs(b.max.z));
      Box& box = m.cell_box[c];
      for (int a = 0; a < 3; ++a) {
        box.lo[a] = down(b.min[a] - grow);
        box.hi[a] = up(b.max[a] + grow);
      }
    }
  });
  // Blocks of cells and their boxes.
  m.bx = (m.cx + kBlock - 1) / kBlock;
  m.by = (m.cy + kBlock - 1) / kBlock;
  m.bz = (m.cz + kBlock - 1) / kBlock;
  const std::size_t nb = std::size_t(m.bx * m.by * m.bz);
  m.block_box.resize(nb);
  parallel_for_range(nb, 1024, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      const Index blk = Index(b);
      const Index bi = blk % m.bx, bj = (blk / m.bx) % m.by, bk = blk / (m.bx * m.by);
      Box box{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
      for (Index k = bk * kBlock; k < std::min(m.cz, (bk + 1) * kBlock); ++k)
        for (Index j = bj * kBlock; j < std::min(m.cy, (bj + 1) * kBlock); ++j)
          for (Index i = bi * kBlock; i < std::min(m.cx, (bi + 1) * kBlock); ++i) {
            const Box& c = m.cell_box[std::size_t(m.cell_id(i, j, k))];
            for (int a = 0; a < 3; ++a) {
              box.lo[a] = std::min(box.lo[a], c.lo[a]);
              box.hi[a] = std::max(box.hi[a], c.hi[a]);
            }
          }
      m.block_box[b] = box;
    }
  });
  m.all = m.block_box[0];
  for (const Box& b : m.block_box) {
    for (int a = 0; a < 3; ++a) {
      m.all.lo[a] = std::min(m.all.lo[a], b.lo[a]);
      m.all.hi[a] = std::max(m.all.hi[a], b.hi[a]);
    }
  }
  // Uniform bins, about one per block, each listing the blocks whose box overlaps it.
  double ext[3], vol = 1;
  for (int a = 0; a < 3; ++a) {
    ext[a] = std::max(double(m.all.hi[a]) - double(m.all.lo[a]), 1e-30);
    vol *= ext[a];
  }
  const double h = std::cbrt(vol / double(nb));
  std::size_t total_bins = 1;
  for (int a = 0; a < 3; ++a) {
    m.bins[std::size_t(a)] = std::clamp(Index(std::ceil(ext[a] / h)), Index{1}, Index{1024});
    m.bin_lo[a] = m.all.lo[a];
    m.bin_inv[a] = double(m.bins[std::size_t(a)]) / ext[a];
    total_bins *= std::size_t(m.bins[std::size_t(a)]);
  }
  auto range = [&](const Box& b, int a, Index& lo, Index& hi) {
    const Index n = m.bins[std::size_t(a)];
    lo = std::clamp(Index((b.lo[a] - m.bin_lo[a]) * m.bin_inv[a]), Index{0}, n - 1);
    hi = std::clamp(Index((b.hi[a] - m.bin_lo[a]) * m.bin_inv[a]), Index{0}, n - 1);
  };
  m.bin_start.assign(total_bins + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t i = 0; i < total_bins; ++i) m.bin_start[i + 1] += m.bin_start[i];
      m.bin_blocks.resize(m.bin_start[total_bins]);
      fill.assign(m.bin_start.begin(), m.bin_start.end() - 1);
    }
    for (std::size_t b = 0; b < nb; ++b) {
      Index lo[3], hi[3];
      for (int a = 0; a < 3; ++a) range(m.block_box[b], a, lo[a], hi[a]);
      for (Index k = lo[2]; k <= hi[2]; ++k)
        for (Index j = lo[1]; j <= hi[1]; ++j)
          for (Index i = lo[0]; i <= hi[0]; ++i) {
            const std::size_t bin = std::size_t(i + m.bins[0] * (j + m.bins[1] * k));
            if (pass == 0) {
              ++m.bin_start[bin + 1];
            } else {
              m.bin_blocks[fill[bin]++] = std::uint32_t(b);
            }
          }
    }
  }
}

GridLocator::~GridLocator() = default;
GridLocator::GridLocator(GridLocator&&) noexcept = default;
GridLocator& GridLocator::operator=(GridLocator&&) noexcept = default;

bool GridLocator::find(const Vec3& p, GridCursor& cursor, GridHit& hit) const {
  if (cursor.valid && impl_->walk(p, cursor, hit)) return true;
  if (impl_->exact(p, cursor, hit)) return true;
  cursor.valid = false;
  return false;
}

}  // namespace isoforge::probe_detail
