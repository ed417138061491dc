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
#include "isoforge/core/prefetch.hpp"

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
/// Chord steps after each Newton step (the residual re-evaluated, the Jacobian kept): at most
/// this many, and the iterate is accepted when the error bound of a contraction, q / (1 − q)
/// times the last step (q: the ratio of the last two steps), is below kChordError.
constexpr int kMaxChord = 3;
constexpr double kChordError = 1e-12;
/// A walk whose predicted coordinates lie this far outside the current cell moves on without
/// solving in it (the prediction's error is far smaller: the square of the step, in cells).
constexpr double kPredictMargin = 0.05;
/// Block edge in cells of the exact locator.
constexpr Index kBlock = 2;

/// The trilinear map X = a + b r + c s + d t + e rs + f rt + g st + h rst of a hexahedron, as
/// m[3 q + axis] for the coefficients q = a, b, ..., h.
using Map = std::array<double, 24>;

/// The map of the hexahedron with corners x[3 (ia + 2 ib + 4 ic) + axis].
void make_map(const double* x, double* m) {
  for (int a = 0; a < 3; ++a) {
    const double x0 = x[a], x1 = x[3 + a], x2 = x[6 + a], x3 = x[9 + a], x4 = x[12 + a],
                 x5 = x[15 + a], x6 = x[18 + a], x7 = x[21 + a];
    m[a] = x0;
    m[3 + a] = x1 - x0;
    m[6 + a] = x2 - x0;
    m[9 + a] = x4 - x0;
    m[12 + a] = x3 - x1 - x2 + x0;
    m[15 + a] = x5 - x1 - x4 + x0;
    m[18 + a] = x6 - x2 - x4 + x0;
    m[21 + a] = x7 - x3 - x5 - x6 + x1 + x2 + x4 - x0;
  }
}

bool bounded(double r, double s, double t) {
  return std::abs(r) < 1e6 && std::abs(s) < 1e6 && std::abs(t) < 1e6;
}

/// X(r, s, t) − p, in the nested form of `solve`.
inline void residual(const double* m, const double* p, double r, double s, double t, double* F) {
  for (int q = 0; q < 3; ++q) {
    const double jr = m[3 + q] + (m[12 + q] + m[21 + q] * t) * s + m[15 + q] * t;
    F[q] = m[q] + jr * r + (m[6 + q] + m[18 + q] * t) * s + m[9 + q] * t - p[q];
  }
}

/// Parametric coordinates (r, s, t) of p by Newton's method from (r, s, t), each Newton step
/// followed by chord steps (the residual re-evaluated, the Jacobian kept); false if they did
/// not converge. `jinv`: the inverse Jacobian (rows) of the last Newton step, near the
/// solution, for predicting the next point's coordinates.
bool solve(const double* m, const double* p, double& r_io, double& s_io, double& t_io,
           double* jinv) {
  const double *a = m, *b = m + 3, *c = m + 6, *d = m + 9, *e = m + 12, *f = m + 15,
               *g = m + 18, *h = m + 21;
  double r = r_io, s = s_io, t = t_io;
  for (int it = 0; it < kMaxNewton; ++it) {
    // X and its derivatives in nested form: u = e + t h, jr = dX/dr = b + s u + t f, ...
    double jr[3], js[3], jt[3], F[3];
    for (int q = 0; q < 3; ++q) {
      const double u = e[q] + h[q] * t;
      const double cg = c[q] + g[q] * t;
      jr[q] = b[q] + u * s + f[q] * t;
      js[q] = cg + u * r;
      jt[q] = d[q] + (f[q] + h[q] * s) * r + g[q] * s;
      F[q] = a[q] + jr[q] * r + cg * s + d[q] * t - p[q];
    }
    // The inverse Jacobian's rows: (js × jt, jt × jr, jr × js) / det.
    const double c0[3] = {js[1] * jt[2] - js[2] * jt[1], js[2] * jt[0] - js[0] * jt[2],
                          js[0] * jt[1] - js[1] * jt[0]};
    const double c1[3] = {jt[1] * jr[2] - jt[2] * jr[1], jt[2] * jr[0] - jt[0] * jr[2],
                          jt[0] * jr[1] - jt[1] * jr[0]};
    const double c2[3] = {jr[1] * js[2] - jr[2] * js[1], jr[2] * js[0] - jr[0] * js[2],
                          jr[0] * js[1] - jr[1] * js[0]};
    const double det = jr[0] * c0[0] + jr[1] * c0[1] + jr[2] * c0[2];
    // A singular Jacobian; a nearly singular one (a degenerate cell) makes the iteration diverge
    // or stall, which is caught below and leaves the cell to locate_in_cell.
    if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
    const double inv = 1.0 / det;
    double dr = (c0[0] * F[0] + c0[1] * F[1] + c0[2] * F[2]) * inv;
    double ds = (c1[0] * F[0] + c1[1] * F[1] + c1[2] * F[2]) * inv;
    double dt = (c2[0] * F[0] + c2[1] * F[1] + c2[2] * F[2]) * inv;
    r -= dr;
    s -= ds;
    t -= dt;
    if (!bounded(r, s, t)) return false;
    double prev = std::max({std::abs(dr), std::abs(ds), std::abs(dt)});
    bool done = prev < kNewtonStep;
    for (int k = 0; k < kMaxChord && !done; ++k) {
      double Fk[3];
      residual(m, p, r, s, t, Fk);
      dr = (c0[0] * Fk[0] + c0[1] * Fk[1] + c0[2] * Fk[2]) * inv;
      ds = (c1[0] * Fk[0] + c1[1] * Fk[1] + c1[2] * Fk[2]) * inv;
      dt = (c2[0] * Fk[0] + c2[1] * Fk[1] + c2[2] * Fk[2]) * inv;
      r -= dr;
      s -= ds;
      t -= dt;
      if (!bounded(r, s, t)) return false;
      const double step = std::max({std::abs(dr), std::abs(ds), std::abs(dt)});
      const double q = step / prev;
      if (!(q < 0.5)) break;  // not contracting fast: a Newton step again
      done = step * q <= kChordError * (1 - q);
      prev = step;
    }
    if (done) {
      r_io = r;
      s_io = s;
      t_io = t;
      for (int q = 0; q < 3; ++q) {
        jinv[q] = c0[q] * inv;
        jinv[3 + q] = c1[q] * inv;
        jinv[6 + q] = c2[q] * inv;
      }
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

}  // namespace

/// A float box around a block of cells. Outside the anonymous namespace because
/// GridLocator::Impl, which has external linkage, holds them.
struct BlockBox {
  float lo[3], hi[3];
  [[nodiscard]] bool contains(const Vec3& p) const {
    return p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1] && p.z >= lo[2] &&
           p.z <= hi[2];
  }
};

namespace {

/// The growth of a box with corners lo, hi so that it holds every point the parametric
/// tolerance admits in a cell inside it, plus rounding.
double growth(const Vec3& lo, const Vec3& hi, double tolerance) {
  double mag = 0;
  for (int a = 0; a < 3; ++a) mag += 2 * std::max(std::abs(lo[a]), std::abs(hi[a]));
  return (1e-6 + 4 * tolerance) * norm(hi - lo) + 1e-12 * mag;
}

}  // namespace

struct GridLocator::Impl {
  Index nx = 0, ny = 0, nz = 0, cx = 0, cy = 0, cz = 0, bx = 0, by = 0, bz = 0;
  double tol = 0;
  const float* pf = nullptr;
  const double* pd = nullptr;
  std::span<const std::uint8_t> cell_ok;
  std::vector<BlockBox> block_box;
  BlockBox all{};
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

  /// The corners of cell (i, j, k): x[3 (ia + 2 ib + 4 ic) + axis].
  void corners(Index i, Index j, Index k, double* x) const {
    const std::size_t base = std::size_t(point_id(i, j, k)), sj = std::size_t(nx),
                      sk = std::size_t(nx * ny);
    const std::size_t ids[8] = {base,      base + 1,      base + sj,      base + sj + 1,
                                base + sk, base + sk + 1, base + sk + sj, base + sk + sj + 1};
    if (pf) {
      for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) x[3 * c + a] = double(pf[3 * ids[c] + std::size_t(a)]);
    } else {
      for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) x[3 * c + a] = pd[3 * ids[c] + std::size_t(a)];
    }
  }

  /// Whether cell (i, j, k), of map `map`, contains p; its parametric coordinates in `pc`
  /// (start: `pc`). `solve` on the trilinear map (`newton` true, `jinv` set), or
  /// `locate_in_cell` when that does not converge. False if neither converged.
  bool test(Index i, Index j, Index k, const double* map, const Vec3& p, Vec3& pc, bool& inside,
            double* jinv, bool& newton) const {
    const double pp[3] = {p.x, p.y, p.z};
    newton = solve(map, pp, pc.x, pc.y, pc.z, jinv);
    if (newton) {
      inside = pc.x >= -tol && pc.x <= 1 + tol && pc.y >= -tol && pc.y <= 1 + tol &&
               pc.z >= -tol && pc.z <= 1 + tol;
      return true;
    }
    double x[24];
    corners(i, j, k, x);
    std::array<Vec3, 8> vtk;  // VTK's hexahedron order
    const int order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    for (int c = 0; c < 8; ++c) {
      const double* q = x + 3 * order[c];
      vtk[std::size_t(c)] = {q[0], q[1], q[2]};
    }
    const CellPosition pos = locate_in_cell(CellType::Hexahedron, vtk, p, tol);
    inside = pos.inside;
    pc = pos.pcoords;
    return pos.converged;
  }

  void fill(Index i, Index j, Index k, const Vec3& pc, GridHit& hit) const {
    hit.cell = cell_id(i, j, k);
    hit.base = std::size_t(point_id(i, j, k));
    hit.r = std::clamp(pc.x, 0.0, 1.0);
    hit.s = std::clamp(pc.y, 0.0, 1.0);
    hit.t = std::clamp(pc.z, 0.0, 1.0);
  }

  [[nodiscard]] bool ok(Index cell) const {
    return cell_ok.empty() || cell_ok[std::size_t(cell)] != 0;
  }

  /// The walk from the cursor's cell; false: ask the exact locator.
  bool walk(const Vec3& query, GridCursor& cur, GridHit& hit) const {
    const Vec3 p = query;  // a local: stores to `cur` cannot change it
    Vec3 pc = cur.pcoords;
    // The coordinates predicted from the last point: one Newton step from it, whose Jacobian
    // is known (exact for a parallelepiped; otherwise off by about the square of the step).
    bool predicted = false;
    if (cur.predict) {
      const Vec3 dp = p - cur.last;
      const double* J = cur.jinv.data();
      pc.x += J[0] * dp.x + J[1] * dp.y + J[2] * dp.z;
      pc.y += J[3] * dp.x + J[4] * dp.y + J[5] * dp.z;
      pc.z += J[6] * dp.x + J[7] * dp.y + J[8] * dp.z;
      predicted = bounded(pc.x, pc.y, pc.z);
      if (!predicted) pc = cur.pcoords;
      cur.predict = false;
    }
    for (int step = 0; step < kMaxWalkSteps; ++step) {
      const auto [i, j, k] = cur.cell;
      const Index cell = cell_id(i, j, k);
      if (step == 0 && predicted &&
          !(pc.x >= -kPredictMargin && pc.x <= 1 + kPredictMargin && pc.y >= -kPredictMargin &&
            pc.y <= 1 + kPredictMargin && pc.z >= -kPredictMargin && pc.z <= 1 + kPredictMargin)) {
        // Clearly in another cell: move on without solving here.
      } else {
        if (cur.map_cell != cell) {
          double x[24];
          corners(i, j, k, x);
          make_map(x, cur.map.data());
          cur.map_cell = cell;
        }
        bool inside = false, newton = false;
        if (!test(i, j, k, cur.map.data(), p, pc, inside, cur.jinv.data(), newton)) return false;
        if (inside) {
          if (!ok(cell)) return false;
          fill(i, j, k, pc, hit);
          cur.pcoords = pc;
          cur.predict = newton;
          cur.last = p;
          return true;
        }
      }
      const Index lim[3] = {cx, cy, cz};
      double v[3] = {pc.x, pc.y, pc.z};
      bool moved = false;
      for (int a = 0; a < 3; ++a) {
        double jump = 0;
        if (v[a] < -tol) jump = std::max(-kMaxJump, std::floor(v[a]));
        if (v[a] > 1 + tol) jump = std::min(kMaxJump, std::floor(v[a]));
        const Index now = cur.cell[std::size_t(a)];
        const Index next = std::clamp(now + Index(jump), Index{0}, lim[a] - 1);
        v[a] = std::clamp(v[a] - double(next - now), 0.0, 1.0);  // the next start
        moved = moved || next != now;
        cur.cell[std::size_t(a)] = next;
      }
      pc = {v[0], v[1], v[2]};
      if (!moved) return false;  // p beyond the grid's boundary here: maybe outside
    }
    return false;
  }

  /// Exact: the smallest-id non-blanked cell containing p.
  bool exact(const Vec3& p, GridCursor& cur, GridHit& hit) const {
    cur.predict = false;
    if (!all.contains(p)) return false;
    const double pp[3] = {p.x, p.y, p.z};
    Index bin[3];
    for (int a = 0; a < 3; ++a) {
      bin[a] =
          std::clamp(Index((pp[a] - bin_lo[a]) * bin_inv[a]), Index{0}, bins[std::size_t(a)] - 1);
    }
    const std::size_t b = std::size_t(bin[0] + bins[0] * (bin[1] + bins[1] * bin[2]));
    Index best = -1;
    Vec3 best_pc;
    double x[24], map[24], jinv[9];
    bool best_newton = false;
    for (std::uint32_t e = bin_start[b]; e < bin_start[b + 1]; ++e) {
      const Index blk = bin_blocks[e];
      if (!block_box[std::size_t(blk)].contains(p)) continue;
      const Index bi = blk % bx, bj = (blk / bx) % by, bk = blk / (bx * by);
      for (Index k = bk * kBlock; k < std::min(cz, (bk + 1) * kBlock); ++k)
        for (Index j = bj * kBlock; j < std::min(cy, (bj + 1) * kBlock); ++j)
          for (Index i = bi * kBlock; i < std::min(cx, (bi + 1) * kBlock); ++i) {
            const Index cell = cell_id(i, j, k);
            if ((best >= 0 && cell > best) || !ok(cell)) continue;
            corners(i, j, k, x);
            Vec3 lo{x[0], x[1], x[2]}, hi = lo;
            for (int c = 1; c < 8; ++c) {
              lo = {std::min(lo.x, x[3 * c]), std::min(lo.y, x[3 * c + 1]),
                    std::min(lo.z, x[3 * c + 2])};
              hi = {std::max(hi.x, x[3 * c]), std::max(hi.y, x[3 * c + 1]),
                    std::max(hi.z, x[3 * c + 2])};
            }
            const double grow = growth(lo, hi, tol);
            if (!(p.x >= lo.x - grow && p.x <= hi.x + grow && p.y >= lo.y - grow &&
                  p.y <= hi.y + grow && p.z >= lo.z - grow && p.z <= hi.z + grow)) {
              continue;
            }
            make_map(x, map);
            Vec3 pc{0.5, 0.5, 0.5};
            bool inside = false, newton = false;
            (void)test(i, j, k, map, p, pc, inside, jinv, newton);
            if (inside) {
              best = cell;
              best_pc = pc;
              best_newton = newton;
              if (newton) std::copy_n(jinv, 9, cur.jinv.data());
            }
          }
    }
    if (best < 0) return false;
    const Index i = best % cx, j = (best / cx) % cy, k = best / (cx * cy);
    fill(i, j, k, best_pc, hit);
    cur.valid = true;
    cur.cell = {i, j, k};
    cur.pcoords = best_pc;
    corners(i, j, k, x);
    make_map(x, cur.map.data());
    cur.map_cell = best;
    cur.predict = best_newton;
    cur.last = p;
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
  // Blocks of cells and their boxes (float, rounded outward), grown so that every point the
  // parametric tolerance admits in one of their cells is in them. The cells' own boxes are
  // made when a query needs them.
  m.bx = (m.cx + kBlock - 1) / kBlock;
  m.by = (m.cy + kBlock - 1) / kBlock;
  m.bz = (m.cz + kBlock - 1) / kBlock;
  const std::size_t nb = std::size_t(m.bx * m.by * m.bz);
  m.block_box.resize(nb);
  parallel_for_range(nb, 1024, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      const Index blk = Index(b);
      const Index bi = blk % m.bx, bj = (blk / m.bx) % m.by, bk = blk / (m.bx * m.by);
      double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
      const auto extend = [&](const auto* pts) {
        for (Index k = bk * kBlock; k <= std::min(m.cz, (bk + 1) * kBlock); ++k)
          for (Index j = bj * kBlock; j <= std::min(m.cy, (bj + 1) * kBlock); ++j) {
            const Index i0 = bi * kBlock, i1 = std::min(m.cx, (bi + 1) * kBlock);
            const auto* q = pts + 3 * m.point_id(i0, j, k);
            for (Index i = i0; i <= i1; ++i, q += 3) {
              for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], double(q[a]));
                hi[a] = std::max(hi[a], double(q[a]));
              }
            }
          }
      };
      if (m.pf) {
        extend(m.pf);
      } else {
        extend(m.pd);
      }
      const double grow = growth({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, tolerance);
      BlockBox& box = m.block_box[b];
      for (int a = 0; a < 3; ++a) {
        box.lo[a] = down(lo[a] - grow);
        box.hi[a] = up(hi[a] + grow);
      }
    }
  });
  m.all = m.block_box[0];
  for (const BlockBox& b : m.block_box) {
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
  auto range = [&](const BlockBox& b, int a, Index& lo, Index& hi) {
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

std::array<std::size_t, 8> GridLocator::offsets() const {
  const auto sj = std::size_t(impl_->nx), sk = std::size_t(impl_->nx * impl_->ny);
  return {0, 1, sj, sj + 1, sk, sk + 1, sk + sj, sk + sj + 1};
}

void GridLocator::prefetch(const Vec3& p, const GridCursor& cursor, const std::byte* values,
                           std::size_t tuple_bytes) const {
  if (!cursor.valid || !cursor.predict) return;
  const Impl& m = *impl_;
  const Vec3 d = p - cursor.last;
  const std::array<double, 9>& J = cursor.jinv;
  const double pc[3] = {cursor.pcoords.x + J[0] * d.x + J[1] * d.y + J[2] * d.z,
                        cursor.pcoords.y + J[3] * d.x + J[4] * d.y + J[5] * d.z,
                        cursor.pcoords.z + J[6] * d.x + J[7] * d.y + J[8] * d.z};
  const Index limit[3] = {m.cx - 1, m.cy - 1, m.cz - 1};
  Index ijk[3];
  for (int a = 0; a < 3; ++a) {
    const double step = std::floor(pc[a]);
    if (!(std::abs(step) < 4)) return;  // far (or not finite): no useful guess
    ijk[a] = std::clamp(cursor.cell[std::size_t(a)] + Index(step), Index{0}, limit[a]);
  }
  const std::size_t base = std::size_t(m.point_id(ijk[0], ijk[1], ijk[2])),
                    sj = std::size_t(m.nx), sk = std::size_t(m.nx * m.ny);
  const std::size_t point_bytes = m.pf ? 3 * sizeof(float) : 3 * sizeof(double);
  const auto* points = m.pf ? reinterpret_cast<const std::byte*>(m.pf)
                            : reinterpret_cast<const std::byte*>(m.pd);
  for (const std::size_t row : {base, base + sj, base + sk, base + sk + sj}) {
    isoforge::prefetch(points + row * point_bytes);
    isoforge::prefetch(points + (row + 1) * point_bytes + point_bytes - 1);
    if (values) {
      isoforge::prefetch(values + row * tuple_bytes);
      isoforge::prefetch(values + (row + 1) * tuple_bytes + tuple_bytes - 1);
    }
  }
}

bool GridLocator::find(const Vec3& p, GridCursor& cursor, GridHit& hit) const {
  if (cursor.valid && impl_->walk(p, cursor, hit)) return true;
  if (impl_->exact(p, cursor, hit)) return true;
  cursor.valid = false;
  return false;
}

}  // namespace isoforge::probe_detail
