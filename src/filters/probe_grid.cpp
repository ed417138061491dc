// Point location in a 3D structured grid (probe_grid.hpp).
//
// References implemented:
// - W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit* (4th ed.), 8.x: point
//   location in curvilinear grids by walking from cell to cell using the parametric coordinates
//   of the point in the current cell, found by Newton's method on the trilinear map.

#include "probe_grid.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>

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

/// The rows of the adjugate of the matrix with columns jr, js, jt — (js × jt, jt × jr, jr × js),
/// the inverse's rows times the determinant — and the determinant.
inline double adjugate_rows(const double* jr, const double* js, const double* jt, double* c0,
                            double* c1, double* c2) {
  c0[0] = js[1] * jt[2] - js[2] * jt[1];
  c0[1] = js[2] * jt[0] - js[0] * jt[2];
  c0[2] = js[0] * jt[1] - js[1] * jt[0];
  c1[0] = jt[1] * jr[2] - jt[2] * jr[1];
  c1[1] = jt[2] * jr[0] - jt[0] * jr[2];
  c1[2] = jt[0] * jr[1] - jt[1] * jr[0];
  c2[0] = jr[1] * js[2] - jr[2] * js[1];
  c2[1] = jr[2] * js[0] - jr[0] * js[2];
  c2[2] = jr[0] * js[1] - jr[1] * js[0];
  return jr[0] * c0[0] + jr[1] * c0[1] + jr[2] * c0[2];
}

/// Whether parametric coordinates lie in the unit cube grown by `tol`.
inline bool in_unit_cube(const Vec3& pc, double tol) {
  return pc.x >= -tol && pc.x <= 1 + tol && pc.y >= -tol && pc.y <= 1 + tol && pc.z >= -tol &&
         pc.z <= 1 + tol;
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
    double c0[3], c1[3], c2[3];
    const double det = adjugate_rows(jr, js, jt, c0, c1, c2);
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
  std::once_flag exact_built;  // the exact locator (block boxes, bins) is built on first use

  /// Builds the exact locator: the blocks' boxes, the bins listing them.
  void build_exact();

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
      inside = in_unit_cube(pc, tol);
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
    fill(cell_id(i, j, k), std::size_t(point_id(i, j, k)), pc, hit);
  }
  static void fill(Index cell, std::size_t base, const Vec3& pc, GridHit& hit) {
    hit.cell = cell;
    hit.base = base;
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

namespace {

/// The image indices along axis `a` of the points that can lie in the box [lo, hi] (grown by
/// `grow`, which holds far more than the rounding of the product): [first, last], empty when
/// first > last.
[[gnu::always_inline]] inline void index_range(const ImagePlan& plan, int a, double lo, double hi,
                                               double grow, Index& first, Index& last) {
  const Index n = plan.dims[std::size_t(a)];
  if (n == 1) {
    const double o = plan.origin[a];
    first = 0;
    last = o >= lo - grow && o <= hi + grow ? 0 : -1;
    return;
  }
  const double top = double(n - 1);
  double v0 = (lo - grow - plan.origin[a]) * plan.inverse[a];
  double v1 = (hi + grow - plan.origin[a]) * plan.inverse[a];
  if (v0 > v1) std::swap(v0, v1);  // a negative spacing
  const double u0 = std::ceil(v0), u1 = std::floor(v1);
  if (!(u0 <= top) || !(u1 >= 0)) {
    first = 0;
    last = -1;
    return;
  }
  first = Index(std::max(u0, 0.0));
  last = Index(std::min(u1, top));
}

/// The box [lo, hi] of a cell's corners x[3 c + axis], and a growth at least `growth`'s.
[[gnu::always_inline]] inline double cell_box(const double* x, double tol, double* lo, double* hi) {
  for (int a = 0; a < 3; ++a) {
    double l = x[a], h = x[a];
    for (int c = 1; c < 8; ++c) {
      l = std::min(l, x[3 * c + a]);
      h = std::max(h, x[3 * c + a]);
    }
    lo[a] = l;
    hi[a] = h;
  }
  // The box's diagonal bounded by the sum of its sides (no square root; a larger growth only
  // admits more candidates).
  const double sides = (hi[0] - lo[0]) + (hi[1] - lo[1]) + (hi[2] - lo[2]);
  double mag = 0;
  for (int a = 0; a < 3; ++a) mag += 2 * std::max(std::abs(lo[a]), std::abs(hi[a]));
  return (1e-6 + 4 * tol) * sides + 1e-12 * mag;
}

/// Points of one cell solved together: their ids, coordinates, parametric coordinates (the
/// start, then after one Newton step) and whether that step converged (ok).
struct Lanes {
  static constexpr std::size_t kSize = 32;
  std::size_t n = 0;
  std::size_t id[kSize];
  alignas(32) double px[kSize], py[kSize], pz[kSize];
  alignas(32) double r[kSize], s[kSize], t[kSize];
  alignas(32) std::int64_t ok[kSize];
};

// Four doubles (GCC's vector extension, also in Clang): AVX registers in the AVX2 build of the
// kernel, pairs of SSE registers otherwise. No function takes or returns one (their calling
// convention would depend on AVX): loads are copies, |v| clears the sign bits in place.
using V4 = double __attribute__((vector_size(32)));
using M4 = std::int64_t __attribute__((vector_size(32)));

/// One Newton step of `solve` on the map m for every lane, four at a time (the same formulas,
/// in vector form); ok: the step was below kNewtonStep and the coordinates are bounded.
[[gnu::always_inline]] inline void newton_lanes_body(const double* m, Lanes& L) {
  for (std::size_t l = L.n; l % 4 != 0; ++l) {  // pad with copies of the last lane
    L.px[l] = L.px[l - 1];
    L.py[l] = L.py[l - 1];
    L.pz[l] = L.pz[l - 1];
    L.r[l] = L.r[l - 1];
    L.s[l] = L.s[l - 1];
    L.t[l] = L.t[l - 1];
  }
  for (std::size_t l = 0; l < L.n; l += 4) {
    V4 R, S, T, P[3];
    std::memcpy(&R, L.r + l, sizeof R);
    std::memcpy(&S, L.s + l, sizeof S);
    std::memcpy(&T, L.t + l, sizeof T);
    std::memcpy(&P[0], L.px + l, sizeof R);
    std::memcpy(&P[1], L.py + l, sizeof R);
    std::memcpy(&P[2], L.pz + l, sizeof R);
    V4 jr[3], js[3], jt[3], F[3];
    for (int q = 0; q < 3; ++q) {
      const double a = m[q], b = m[3 + q], c = m[6 + q], d = m[9 + q], e = m[12 + q], f = m[15 + q],
                   g = m[18 + q], h = m[21 + q];
      const V4 u = e + h * T;
      const V4 cg = c + g * T;
      jr[q] = b + u * S + f * T;
      js[q] = cg + u * R;
      jt[q] = d + (f + h * S) * R + g * S;
      F[q] = a + jr[q] * R + cg * S + d * T - P[q];
    }
    const V4 c0[3] = {js[1] * jt[2] - js[2] * jt[1], js[2] * jt[0] - js[0] * jt[2],
                      js[0] * jt[1] - js[1] * jt[0]};
    const V4 c1[3] = {jt[1] * jr[2] - jt[2] * jr[1], jt[2] * jr[0] - jt[0] * jr[2],
                      jt[0] * jr[1] - jt[1] * jr[0]};
    const V4 c2[3] = {jr[1] * js[2] - jr[2] * js[1], jr[2] * js[0] - jr[0] * js[2],
                      jr[0] * js[1] - jr[1] * js[0]};
    const V4 det = jr[0] * c0[0] + jr[1] * c0[1] + jr[2] * c0[2];
    const V4 inv = 1.0 / det;
    const V4 dr = (c0[0] * F[0] + c0[1] * F[1] + c0[2] * F[2]) * inv;
    const V4 ds = (c1[0] * F[0] + c1[1] * F[1] + c1[2] * F[2]) * inv;
    const V4 dt = (c2[0] * F[0] + c2[1] * F[1] + c2[2] * F[2]) * inv;
    const V4 r = R - dr, s = S - ds, t = T - dt;
    // NaN (a singular Jacobian) compares false: not ok.
    constexpr std::int64_t kNoSign = std::numeric_limits<std::int64_t>::max();
    const V4 adr = (V4)((M4)dr & kNoSign), ads = (V4)((M4)ds & kNoSign),
             adt = (V4)((M4)dt & kNoSign);
    const V4 ar = (V4)((M4)r & kNoSign), as = (V4)((M4)s & kNoSign), at = (V4)((M4)t & kNoSign);
    const M4 ok = (adr < kNewtonStep) & (ads < kNewtonStep) & (adt < kNewtonStep) & (ar < 1e6) &
                  (as < 1e6) & (at < 1e6);
    std::memcpy(L.r + l, &r, sizeof r);
    std::memcpy(L.s + l, &s, sizeof s);
    std::memcpy(L.t + l, &t, sizeof t);
    std::memcpy(L.ok + l, &ok, sizeof ok);
  }
}

[[gnu::target("avx2,fma")]] void newton_lanes_avx2(const double* m, Lanes& L) {
  newton_lanes_body(m, L);
}
void newton_lanes_base(const double* m, Lanes& L) {
  newton_lanes_body(m, L);
}

std::atomic<bool> g_portable_kernel{false};  // tests: the portable kernel even with AVX2

/// The lanes' Newton step, with AVX2 and FMA where the processor has them.
void newton_lanes(const double* m, Lanes& L) {
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2 && !g_portable_kernel.load(std::memory_order_relaxed)) {
    newton_lanes_avx2(m, L);
  } else {
    newton_lanes_base(m, L);
  }
}

}  // namespace

void use_portable_kernel(bool portable) {
  g_portable_kernel.store(portable, std::memory_order_relaxed);
}

std::pair<std::size_t, std::size_t> ImagePlan::points(std::size_t slab) const {
  const auto n = std::size_t(dims[std::size_t(axis)]), l = std::size_t(layers);
  return {slab * l * stride, std::min(n, (slab + 1) * l) * stride};
}

bool GridLocator::can_scan(const ImageData& image) const {
  const Impl& m = *impl_;
  if (std::size_t(m.cx) * std::size_t(m.cy) * std::size_t(m.cz) >= (std::size_t{1} << 32)) {
    return false;
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(image.origin[a])) return false;
    if (image.dims[std::size_t(a)] > 1 &&
        !(image.spacing[a] != 0 && std::isfinite(image.spacing[a]))) {
      return false;
    }
  }
  return image.num_points() > 0;
}

ImagePlan GridLocator::plan_image(const ImageData& image, std::size_t slabs) const {
  const Impl& m = *impl_;
  ImagePlan plan;
  plan.dims = image.dims;
  plan.origin = image.origin;
  plan.spacing = image.spacing;
  for (int a = 0; a < 3; ++a) plan.inverse[a] = 1 / image.spacing[a];
  plan.axis = image.dims[2] > 1 ? 2 : image.dims[1] > 1 ? 1 : 0;
  plan.stride = plan.axis == 2   ? std::size_t(image.dims[0] * image.dims[1])
                : plan.axis == 1 ? std::size_t(image.dims[0])
                                 : 1;
  const Index n = image.dims[std::size_t(plan.axis)];
  plan.layers = std::max<Index>(
      1, (n + Index(std::max<std::size_t>(slabs, 1)) - 1) / Index(std::max<std::size_t>(slabs, 1)));
  const std::size_t count = std::size_t((n + plan.layers - 1) / plan.layers);
  // Per cell, its first and last slab (none: first > last), counted per chunk of cell layers;
  // then each chunk lists its cells at its offsets, so every slab lists its cells in id order.
  const std::size_t nc = std::size_t(m.cx * m.cy * m.cz);
  const std::size_t chunks = std::min<std::size_t>(std::size_t(m.cz), 64);
  const auto chunk_cells = [&](std::size_t c) {
    const auto layer = [&](std::size_t q) { return std::size_t(m.cz) * q / chunks; };
    const std::size_t per_layer = std::size_t(m.cx * m.cy);
    return std::pair{layer(c) * per_layer, layer(c + 1) * per_layer};
  };
  std::vector<std::array<std::uint32_t, 2>> range(nc);
  std::vector<std::uint32_t> counts(chunks * count, 0);
  parallel_for_range(chunks, 1, [&](std::size_t c0, std::size_t c1) {
    double x[24];
    for (std::size_t ch = c0; ch < c1; ++ch) {
      std::uint32_t* cnt = counts.data() + ch * count;
      const auto [first_cell, last_cell] = chunk_cells(ch);
      // The chunk's cells in order, (i, j, k) counted along (no division per cell).
      Index ci = 0, cj = 0, ck = Index(first_cell) / (m.cx * m.cy);
      for (std::size_t id = first_cell; id < last_cell; ++id) {
        const Index cell = Index(id), i = ci, j = cj, k = ck;
        if (++ci == m.cx) {
          ci = 0;
          if (++cj == m.cy) {
            cj = 0;
            ++ck;
          }
        }
        auto& rg = range[id];
        rg = {1, 0};
        if (!m.ok(cell)) continue;
        m.corners(i, j, k, x);
        double lo[3], hi[3];
        const double grow = cell_box(x, m.tol, lo, hi);
        Index first[3], last[3];
        bool empty = false;
        for (int a = 0; a < 3; ++a) {
          index_range(plan, a, lo[a], hi[a], grow, first[a], last[a]);
          empty = empty || first[a] > last[a];
        }
        if (empty) continue;
        rg = {std::uint32_t(first[plan.axis] / plan.layers),
              std::uint32_t(last[plan.axis] / plan.layers)};
        for (std::uint32_t sl = rg[0]; sl <= rg[1]; ++sl) ++cnt[sl];
      }
    }
  });
  // Offsets: slab by slab, chunk by chunk within a slab.
  plan.start.assign(count + 1, 0);
  std::uint32_t total = 0;
  for (std::size_t sl = 0; sl < count; ++sl) {
    plan.start[sl] = total;
    for (std::size_t ch = 0; ch < chunks; ++ch) {
      const std::uint32_t c = counts[ch * count + sl];
      counts[ch * count + sl] = total;
      total += c;
    }
  }
  plan.start[count] = total;
  plan.cells.resize(total);
  parallel_for_range(chunks, 1, [&](std::size_t c0, std::size_t c1) {
    for (std::size_t ch = c0; ch < c1; ++ch) {
      std::uint32_t* at = counts.data() + ch * count;
      const auto [first_cell, last_cell] = chunk_cells(ch);
      for (std::size_t id = first_cell; id < last_cell; ++id)
        for (std::uint32_t sl = range[id][0]; sl <= range[id][1]; ++sl) {
          plan.cells[at[sl]++] = std::uint32_t(id);
        }
    }
  });
  return plan;
}

void GridLocator::scan_image(const ImagePlan& plan, std::size_t slab, std::uint8_t* owned,
                             GridHitSink& sink) const {
  const Impl& m = *impl_;
  const double tol = m.tol;
  const Index slab_first = Index(slab) * plan.layers;
  const Index slab_last = std::min(plan.dims[std::size_t(plan.axis)], slab_first + plan.layers) - 1;
  const auto sy = std::size_t(plan.dims[0]), sz = std::size_t(plan.dims[0] * plan.dims[1]);
  // The nonlinear terms of a map in centred coordinates (u = r − ½, ...) over the cell grown by
  // the tolerance: |uv| <= mm, |uvw| <= mmm.
  const double mm = (0.5 + tol) * (0.5 + tol), mmm = mm * (0.5 + tol);
  double x[24], map[24], jinv[9];
  Lanes lanes;
  Index cell = -2, i = 0, j = 0, k = 0;
  for (std::uint32_t e = plan.start[slab]; e < plan.start[slab + 1]; ++e) {
    // The listed cells mostly follow each other along i: no division then.
    const Index next = Index(plan.cells[e]);
    if (next == cell + 1 && i + 1 < m.cx) {
      ++i;
    } else {
      i = next % m.cx;
      j = (next / m.cx) % m.cy;
      k = next / (m.cx * m.cy);
    }
    cell = next;
    m.corners(i, j, k, x);
    double lo[3], hi[3];
    const double grow = cell_box(x, tol, lo, hi);
    Index first[3], last[3];
    for (int a = 0; a < 3; ++a) index_range(plan, a, lo[a], hi[a], grow, first[a], last[a]);
    first[plan.axis] = std::max(first[plan.axis], slab_first);
    last[plan.axis] = std::min(last[plan.axis], slab_last);
    if (first[0] > last[0] || first[1] > last[1] || first[2] > last[2]) continue;
    make_map(x, map);
    const double *a = map, *b = map + 3, *c = map + 6, *d = map + 9, *ee = map + 12, *f = map + 15,
                 *g = map + 18, *h = map + 21;
    // The map linearized at the centre: X ≈ A + J (r − ½, s − ½, t − ½), J = [jr js jt]; the rest
    // is E uv + F uw + G vw + H uvw with E = e + h/2, F = f + h/2, G = g + h/2, H = h.
    double A[3], jr[3], js[3], jt[3], N[3];  // the Jacobian's columns jr, js, jt
    for (int q = 0; q < 3; ++q) {
      A[q] = a[q] + 0.5 * (b[q] + c[q] + d[q]) + 0.25 * (ee[q] + f[q] + g[q]) + 0.125 * h[q];
      jr[q] = b[q] + 0.5 * (ee[q] + f[q]) + 0.25 * h[q];
      js[q] = c[q] + 0.5 * (ee[q] + g[q]) + 0.25 * h[q];
      jt[q] = d[q] + 0.5 * (f[q] + g[q]) + 0.25 * h[q];
      N[q] = (std::abs(ee[q] + 0.5 * h[q]) + std::abs(f[q] + 0.5 * h[q]) +
              std::abs(g[q] + 0.5 * h[q])) *
                 mm +
             std::abs(h[q]) * mmm;
    }
    // Its inverse (rows), and per coordinate the bound on how far the linearized prediction
    // can be from the coordinates of a point of the cell: |J⁻¹| N, plus rounding, generously.
    double Ji[3][3] = {}, reach[3] = {};
    bool filter = false;
    {
      const double det = adjugate_rows(jr, js, jt, Ji[0], Ji[1], Ji[2]);
      if (std::abs(det) > 0 && std::isfinite(det)) {
        const double inv = 1 / det;
        for (auto& row : Ji)
          for (double& v : row) v *= inv;
        double mag = 0;
        for (int q = 0; q < 3; ++q) mag += std::abs(lo[q]) + std::abs(hi[q]) + grow;
        filter = true;
        for (int r = 0; r < 3; ++r) {
          double bound = 0, row = 0;
          for (int q = 0; q < 3; ++q) {
            bound += std::abs(Ji[r][q]) * N[q];
            row += std::abs(Ji[r][q]);
          }
          reach[r] = 0.5 + tol + bound + 1e-6 + 1e-12 * row * mag;
          filter = filter && std::isfinite(reach[r]);
        }
      }
    }
    // The candidates the bound keeps are solved in batches: one Newton step for all of them at
    // once (lanes), then each point whose step was below kNewtonStep is decided; the others
    // (rare: a strongly curved cell, a degenerate one) go through `test`.
    lanes.n = 0;
    const std::size_t base = std::size_t(m.point_id(i, j, k));
    const auto flush = [&] {
      newton_lanes(map, lanes);
      for (std::size_t l = 0; l < lanes.n; ++l) {
        Vec3 pc{lanes.r[l], lanes.s[l], lanes.t[l]};
        bool inside = false;
        if (lanes.ok[l]) {
          inside = in_unit_cube(pc, tol);
        } else {  // on from the step taken, or from the centre (as the exact locator)
          const Vec3 p{lanes.px[l], lanes.py[l], lanes.pz[l]};
          if (!bounded(pc.x, pc.y, pc.z)) pc = {0.5, 0.5, 0.5};
          bool newton = false;
          if (!m.test(i, j, k, map, p, pc, inside, jinv, newton)) inside = false;
        }
        if (!inside) continue;
        owned[lanes.id[l]] = 1;
        if (sink.size == sink.capacity) sink.full();
        const std::size_t q = sink.size++;
        sink.out[q] = lanes.id[l];
        sink.cell[q] = cell;
        Impl::fill(cell, base, pc, sink.hit[q]);
      }
      lanes.n = 0;
    };
    for (Index z = first[2]; z <= last[2]; ++z) {
      const double pz = plan.origin.z + double(z) * plan.spacing.z;
      for (Index y = first[1]; y <= last[1]; ++y) {
        const double py = plan.origin.y + double(y) * plan.spacing.y;
        const std::size_t row = std::size_t(z) * sz + std::size_t(y) * sy;
        for (Index xi = first[0]; xi <= last[0]; ++xi) {
          if (owned[row + std::size_t(xi)]) continue;
          const double px = plan.origin.x + double(xi) * plan.spacing.x;
          double u[3] = {0, 0, 0};
          if (filter) {
            const double dp[3] = {px - A[0], py - A[1], pz - A[2]};
            bool out = false;
            for (int r = 0; r < 3; ++r) {
              u[r] = Ji[r][0] * dp[0] + Ji[r][1] * dp[1] + Ji[r][2] * dp[2];
              out = out || !(std::abs(u[r]) <= reach[r]);
            }
            if (out) continue;  // provably in no point of the cell
          }
          const std::size_t l = lanes.n++;
          lanes.id[l] = row + std::size_t(xi);
          lanes.px[l] = px;
          lanes.py[l] = py;
          lanes.pz[l] = pz;
          lanes.r[l] = 0.5 + u[0];
          lanes.s[l] = 0.5 + u[1];
          lanes.t[l] = 0.5 + u[2];
          if (lanes.n == Lanes::kSize) flush();
        }
      }
    }
    if (lanes.n > 0) flush();
  }
}

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
}

void GridLocator::Impl::build_exact() {
  Impl& m = *this;
  const double tolerance = tol;
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

void GridLocator::prepare() const {
  std::call_once(impl_->exact_built, [&] { impl_->build_exact(); });
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
  prepare();
  if (impl_->exact(p, cursor, hit)) return true;
  cursor.valid = false;
  return false;
}

}  // namespace isoforge::probe_detail
