// Dense distance fields of points and segments by rows along x (model/distance_internal.hpp).
//
// The image is computed one z-plane at a time. Each primitive that can reach the plane visits
// the rows (j) it can reach, and on each row the samples it can reach, in up to three pieces:
//
//   [ low end cap ]  [ middle: the full segment kernel ]  [ high end cap ]
//
// Along a row the projection parameter t of a sample onto the segment a + t u is monotone in x,
// so the samples whose (rounded) t clamps to 0 form a prefix or a suffix of the row, and so do
// those whose t clamps to 1. There the segment kernel of closest_point.hpp reduces, operation by
// operation, to the point kernel |p − a|² (t = 0) or |p − (a + u)|² (t = 1): 4 operations per
// sample instead of 18, with the same bits. The caps are the samples of the row inside the end
// balls whose t lies certainly (by a margin far above rounding) beyond 0 or 1; the middle is the
// row inside the infinite cylinder, between the caps. A sample within reach of the segment lies
// in one of the three, so every sample gets the minimum over the primitives that can reach it,
// computed with the very operations of the other paths: the result equals theirs bit for bit.
//
// Segments along the rows (uy = uz = 0) or across them (ux = 0) are simpler still: their kernel
// is (q(x) + dy²) + dz² with q the same on every row of the plane, so each row is one piece
// (axis_segment_plane).
//
// Pieces are rounded to chunks of 8 samples (rows are padded): caps shrink toward their ends and
// the middle grows to cover what they gave up, so the kernels run on whole vectors. The rows of
// a plane are set up in one vectorized loop per primitive, and one call per plane enters the
// AVX-512 / AVX2 / baseline clone (ISOFORGE_SIMD_CLONES, src/CMakeLists.txt), so that per-row
// work stays small.
//
// Methods: banded scan conversion of the primitives (vtkImplicitModeller's per-cell loop, cut
// to the characteristic regions of S. Mauch, "A fast algorithm for computing the closest point
// and distance transform", Caltech 2000: the cylinder of a segment, the balls of its ends).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <type_traits>
#include <vector>

#include "distance_internal.hpp"

namespace isoforge::model_detail {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int kChunk = 8;  // samples per kernel step (one AVX-512 vector of doubles)

// Every kernel must be inlined into the cloned plane functions (a kernel left out of line is
// compiled for the baseline only): lambdas get it explicitly.
#if defined(__GNUC__)
#define ISOFORGE_INLINE __attribute__((always_inline))
#else
#define ISOFORGE_INLINE
#endif

// A segment a + t u, t in [0, 1], as the kernels use it; b = a + u as the kernel rounds it when
// t clamps to 1 (not the input's second point, which may differ in the last bit).
struct Seg {
  double ax, ay, az, ux, uy, uz;
  double inv;   // 1 / |u|²
  double bx, by, bz;
  double len2;  // |u|²
  double yz2;   // uy² + uz²
  double len;   // |u|
  bool regular; // |u|² is a normal number with a finite reciprocal: the caps apply
  bool across;  // ux = 0: t is the same all along a row
  bool along;   // uy = uz = 0: the segment lies along the rows
};

// What one plane needs.
struct Plane {
  const double* X;  // sample x coordinates, padded to nxp (the padding continues the formula)
  const double* Y;  // sample y coordinates
  double Z;
  int nx, nxp, ny;
  double ox, hx, inv_hx, oy, inv_hy;
  double Rs, Rs2;   // the reach with its slack (relative, and absolute for the coordinates)
  double* d2;       // ny rows of nxp squared distances
  int* scratch;     // 6 * ny ints (the pieces of each row)
  double* sq;       // 2 * nxp doubles: the row-independent parts of a primitive's kernels
  double* rowc;     // 2 * ny doubles: per-row constants
};

// Constants of a segment's row set-up on one plane (passed by value: no aliasing with the
// outputs, so the loop vectorizes).
struct RowSetup {
  double ax, ay, bx, by, ux, uy, uz, inv, len2;
  double wz, wz2, wzb2;  // Z − az, its square, (Z − bz)²
  double ox, inv_hx, n;
  double Rs2, row_slack;
  bool parallel;  // along x
  double inv_yz2; // 1 / (uy² + uz²) (1 when parallel)
  double tau, inv_tau, delta, t_base;
};

// Sample index interval [lo, hi] of x in [x0, x1] on a row of n samples at ox + i / inv_hx,
// rounded outward, clamped to [0, n − 1], as doubles; (1, 0) when `valid` < 0, the interval
// misses the row or is NaN. Branch-free, for vectorization.
[[gnu::always_inline]] inline void x_span(double ox, double inv_hx, double n, double x0,
                                          double x1, double valid, double& lo, double& hi) {
  const double f0 = std::floor((x0 - ox) * inv_hx);
  const double f1 = std::ceil((x1 - ox) * inv_hx);
  const double last = n - 1.0;
  const bool ok = (valid >= 0.0) & (f0 <= f1) & (f1 >= 0.0) & (f0 <= last);
  lo = ok ? (f0 > 0.0 ? f0 : 0.0) : 1.0;
  hi = ok ? (f1 < last ? f1 : last) : 0.0;
}
[[gnu::always_inline]] inline void x_span(const RowSetup& c, double x0, double x1, double valid,
                                          double& lo, double& hi) {
  x_span(c.ox, c.inv_hx, c.n, x0, x1, valid, lo, hi);
}

// The same as ints.
[[gnu::always_inline]] inline void x_range(const Plane& p, double x0, double x1, bool valid,
                                           int& lo, int& hi) {
  double l, h;
  x_span(p.ox, p.inv_hx, p.nx, x0, x1, valid ? 0.0 : -1.0, l, h);
  lo = static_cast<int>(l);
  hi = static_cast<int>(h);
}

// Eight doubles: a chunk. GCC's generic vectors (one AVX-512 register, two AVX2 ones or four
// SSE ones, by clone); written as plain arithmetic, so every clone rounds the same.
using Chunk = double __attribute__((vector_size(kChunk * sizeof(double))));
using FloatChunk = float __attribute__((vector_size(kChunk * sizeof(float))));

// d2 = min(d2, v) with kernel(x, v) on the whole chunks of [m0, m1) of x = X; returns the
// samples visited.
template <class Kernel>
[[gnu::always_inline]] inline std::size_t min_chunks(const double* __restrict X, int m0, int m1,
                                                     double* __restrict d2, Kernel&& kernel) {
  for (int m = m0; m < m1; m += kChunk) {
    Chunk x, d;
    std::memcpy(&x, X + m, sizeof x);
    std::memcpy(&d, d2 + m, sizeof d);
    Chunk v;
    kernel(x, v);
    d = v < d ? v : d;
    std::memcpy(d2 + m, &d, sizeof d);
  }
  return static_cast<std::size_t>(m1 > m0 ? m1 - m0 : 0);
}

// sq = kernel(x) on the whole chunks of [m0, m1) of x = X.
template <class Kernel>
[[gnu::always_inline]] inline void map_chunks(const double* __restrict X, int m0, int m1,
                                              double* __restrict sq, Kernel&& kernel) {
  for (int m = m0; m < m1; m += kChunk) {
    Chunk x, v;
    std::memcpy(&x, X + m, sizeof x);
    kernel(x, v);
    std::memcpy(sq + m, &v, sizeof v);
  }
}

// Point kernels split in two: |(x, y, z) − c|² is exactly norm2(p − c) = ((dx² + dy²) + dz²), and
// dx² does not depend on the row, so it is computed once per plane (squares) and each row only
// adds its dy², dz² (offset_chunks): 2 additions a sample.
[[gnu::always_inline]] inline void squares(const double* __restrict X, int m0, int m1, double cx,
                                           double* __restrict sq) {
  const Chunk cxv = Chunk{} + cx;
  map_chunks(X, m0, m1, sq, [&](const Chunk& x, Chunk& v) ISOFORGE_INLINE {
    const Chunk dx = x - cxv;
    v = dx * dx;
  });
}

[[gnu::always_inline]] inline std::size_t offset_chunks(const double* __restrict sq, int m0, int m1,
                                                        double dy2, double dz2,
                                                        double* __restrict d2) {
  const Chunk dy2v = Chunk{} + dy2, dz2v = Chunk{} + dz2;
  return min_chunks(sq, m0, m1, d2,
                    [&](const Chunk& dx2, Chunk& v) ISOFORGE_INLINE { v = (dx2 + dy2v) + dz2v; });
}

// The segment's constants as chunks, made once per plane rather than per row.
struct SegChunks {
  Chunk ax, ay, az, ux, uy, uz, inv, z, cz, zero, one;
  SegChunks(const Seg& s, double z_, double cz_)
      : ax(Chunk{} + s.ax), ay(Chunk{} + s.ay), az(Chunk{} + s.az), ux(Chunk{} + s.ux),
        uy(Chunk{} + s.uy), uz(Chunk{} + s.uz), inv(Chunk{} + s.inv), z(Chunk{} + z_),
        cz(Chunk{} + cz_), zero(Chunk{}), one(Chunk{} + 1.0) {}
};

// segment_distance2((x, y, z), a, b), operation by operation as closest_on_segment:
// t = clamp(((wx ux + wy uy) + wz uz) · inv, 0, 1), q = a + u t, ((px − qx)² + (py − qy)²) +
// (pz − qz)². (On chunks rather than a loop over samples: as a loop, GCC moves the products u t
// into the clamp's selects, a third more work.)
[[gnu::always_inline]] inline std::size_t segment_chunks(const double* __restrict X, int m0, int m1,
                                                         const SegChunks& s, double y, double cy,
                                                         double* __restrict d2) {
  const Chunk yv = Chunk{} + y, cyv = Chunk{} + cy;
  return min_chunks(X, m0, m1, d2, [&](const Chunk& x, Chunk& v) ISOFORGE_INLINE {
    Chunk t = (((x - s.ax) * s.ux + cyv) + s.cz) * s.inv;
    t = t < s.zero ? s.zero : t;
    t = s.one < t ? s.one : t;
    const Chunk dx = x - (s.ax + s.ux * t), dy = yv - (s.ay + s.uy * t),
                dz = s.z - (s.az + s.uz * t);
    v = (dx * dx + dy * dy) + dz * dz;
  });
}

// For a segment along the rows (uy = uz = 0) the products uy t, uz t are zeros, so the kernel is
// ((x − (ax + ux t))² + dy²) + dz² with dy, dz the row's offsets from a, and t = ((x − ax) ux) ·
// inv (the kernel's added wy uy, wz uz are zeros too: same values). The first square does not
// depend on the row: computed once per plane, then offset_chunks.
[[gnu::always_inline]] inline void along_squares(const double* __restrict X, int m0, int m1,
                                                 const SegChunks& s, double* __restrict sq) {
  map_chunks(X, m0, m1, sq, [&](const Chunk& x, Chunk& v) ISOFORGE_INLINE {
    Chunk t = ((x - s.ax) * s.ux) * s.inv;
    t = t < s.zero ? s.zero : t;
    t = s.one < t ? s.one : t;
    const Chunk dx = x - (s.ax + s.ux * t);
    v = dx * dx;
  });
}

// The aligned hull [m0, m1) of the non-empty intervals [lo_q[j], hi_q[j]] of the three pieces q,
// j in [j0, j1], within [0, nxp); false if all are empty.
[[gnu::always_inline]] inline bool hull(const std::array<const int*, 3>& lo,
                                        const std::array<const int*, 3>& hi, int j0, int j1,
                                        int nxp, int& m0, int& m1) {
  int a = nxp, b = -1;
  for (int j = j0; j <= j1; ++j) {
    for (int q = 0; q < 3; ++q) {
      const bool e = lo[q][j] <= hi[q][j];
      a = std::min(a, e ? lo[q][j] : nxp);
      b = std::max(b, e ? hi[q][j] : -1);
    }
  }
  if (a > b) return false;
  m0 = std::max(a, 0) & ~(kChunk - 1);
  m1 = std::min((b | (kChunk - 1)) + 1, nxp);
  return true;
}

// Row index range [j0, j1] of y in [y0, y1] (outward), clamped; false if empty.
[[gnu::always_inline]] inline bool y_range(const Plane& p, double y0, double y1, int& j0, int& j1) {
  double f0 = std::floor((y0 - p.oy) * p.inv_hy), f1 = std::ceil((y1 - p.oy) * p.inv_hy);
  f0 = std::max(f0, 0.0);
  f1 = std::min(f1, p.ny - 1.0);
  if (!(f0 <= f1)) return false;
  j0 = static_cast<int>(f0);
  j1 = static_cast<int>(f1);
  return true;
}

// For each row j in [j0, j1]: the low cap [lo_a, hi_a], the middle [lo_f, hi_f], the high cap
// [lo_b, hi_b] (see the file comment). One pass of arithmetic and selects over the rows.
[[gnu::always_inline]] inline void setup_rows(const RowSetup c, const double* __restrict Y, int j0,
                                              int j1, int* __restrict lo_a, int* __restrict hi_a,
                                              int* __restrict lo_f, int* __restrict hi_f,
                                              int* __restrict lo_b, int* __restrict hi_b) {
  const bool rising = c.tau >= 0.0;
  for (int j = j0; j <= j1; ++j) {
    const double wy = Y[j] - c.ay;
    const double wyb = Y[j] - c.by;
    // The end balls on this row.
    const double ha2 = c.Rs2 - wy * wy - c.wz2;
    const double hb2 = c.Rs2 - wyb * wyb - c.wzb2;
    const double ha = std::sqrt(ha2 < 0.0 ? 0.0 : ha2), hb = std::sqrt(hb2 < 0.0 ? 0.0 : hb2);
    double la0, la1, lb0, lb1;
    x_span(c, c.ax - ha, c.ax + ha, ha2, la0, la1);
    x_span(c, c.bx - hb, c.bx + hb, hb2, lb0, lb1);
    // The infinite cylinder on this row: |w × u|² ≤ Rs² |u|², w = (x − ax, wy, wz), a quadratic
    // in s = x − ax with minimum mmin at s*, evaluated as a sum of squares (no cancellation).
    // Parallel to x, the row is within the cylinder everywhere or nowhere.
    const double c0 = wy * c.uy + c.wz * c.uz;
    const double sstar = c0 * c.ux * c.inv_yz2;
    const double P = wy * c.uz - c.wz * c.uy;
    const double q1 = c.wz * c.ux - sstar * c.uz, q2 = sstar * c.uy - wy * c.ux;
    const double mmin = P * P + q1 * q1 + q2 * q2;
    const double hc2 = (c.Rs2 * c.len2 - mmin) * c.inv_yz2;
    const double hc = std::sqrt(hc2 < 0.0 ? 0.0 : hc2);
    const double par_in = c.row_slack * c.row_slack - (wy * wy + c.wz2);
    double lc0, lc1;
    x_span(c, c.parallel ? -kInfinity : c.ax + sstar - hc, c.parallel ? kInfinity : c.ax + sstar + hc,
           c.parallel ? par_in : hc2, lc0, lc1);
    // Where t = −δ and t = 1 + δ (sample indices); t at sample m is t_row + m · tau. With
    // tau = 0, t is the same all along the row: everything is one cap or the middle.
    const double t_row = c.t_base + c0 * c.inv;
    // (inv_tau = +inf then: ±inf by the side of t, NaN on a tie, which leaves the caps empty.)
    const double qa = (-c.delta - t_row) * c.inv_tau;
    const double qb = (1.0 + c.delta - t_row) * c.inv_tau;
    // The low end of the row is cap a when t rises along x, else cap b. A NaN bound (from an
    // overflowing input) leaves the caps empty.
    double low_end = std::floor(rising ? qa : qb);  // + 1 past the last index of the low cap
    double high_start = std::ceil(rising ? qb : qa);  // − 1 before the first of the high cap
    low_end = low_end >= -1.0 ? (low_end < c.n ? low_end : c.n) : -1.0;
    high_start = high_start <= c.n ? (high_start > -1.0 ? high_start : -1.0) : c.n;
    low_end -= 1.0;
    high_start += 1.0;
    const double cl0 = rising ? la0 : lb0, cl1 = rising ? la1 : lb1;
    const double ch0 = rising ? lb0 : la0, ch1 = rising ? lb1 : la1;
    lo_a[j] = static_cast<int>(cl0);
    hi_a[j] = static_cast<int>(cl1 < low_end ? cl1 : low_end);
    lo_b[j] = static_cast<int>(ch0 > high_start ? ch0 : high_start);
    hi_b[j] = static_cast<int>(ch1);
    lo_f[j] = static_cast<int>(lc0 > low_end + 1.0 ? lc0 : low_end + 1.0);
    hi_f[j] = static_cast<int>(lc1 < high_start - 1.0 ? lc1 : high_start - 1.0);
  }
}

// A segment along the rows (uy = uz = 0) or across them (ux = 0), or a point (a segment of
// length 0 across them): its kernel is, operation by operation, (q(x) + dy²) + dz² with q
// independent of the row — along: q = (x − (ax + ux t))² and dy, dz the row's offsets from a
// (the products uy t, uz t are zeros); across: q = (x − ax)² and dy, dz those of the closest point
// a + u t, whose t is the same all along the row (0 for a point). So every row is one piece: the
// samples within Rs, |x − [x extent]| ≤ sqrt(Rs² − dy² − dz²). cz is the kernel's wz · uz.
[[gnu::always_inline]] inline std::size_t axis_segment_plane(const Plane& p, const Seg& s, int j0,
                                                             int j1, double cz) {
  const double x0 = std::min(s.ax, s.bx), x1 = std::max(s.ax, s.bx);
  int a, b;
  x_range(p, x0 - p.Rs, x1 + p.Rs, true, a, b);
  if (a > b) return 0;
  const int h0 = a & ~(kChunk - 1), h1 = (b | (kChunk - 1)) + 1;
  if (s.along) {
    along_squares(p.X, h0, h1, SegChunks(s, p.Z, cz), p.sq);
  } else {
    squares(p.X, h0, h1, s.ax, p.sq);
  }
  int* lo = p.scratch;
  int* hi = p.scratch + p.ny;
  double* dy2 = p.rowc;
  double* dz2 = p.rowc + p.ny;
  // The rows' constants and pieces, in one vectorized pass.
  const double t_shift = (p.X[0] - s.ax) * s.ux;  // ±0 across the rows: the kernel's first term
  for (int j = j0; j <= j1; ++j) {
    const double y = p.Y[j];
    double t = ((t_shift + (y - s.ay) * s.uy) + cz) * s.inv;  // across: the row's t
    t = t < 0.0 ? 0.0 : t;
    t = 1.0 < t ? 1.0 : t;
    t = s.along ? 0.0 : t;  // along: uy t and uz t are zeros whatever t
    const double dy = y - (s.ay + s.uy * t), dz = p.Z - (s.az + s.uz * t);
    dy2[j] = dy * dy;
    dz2[j] = dz * dz;
    const double rem = p.Rs2 - (dy2[j] + dz2[j]);
    const double h = std::sqrt(rem < 0.0 ? 0.0 : rem);
    double l, u;
    x_span(p.ox, p.inv_hx, p.nx, x0 - h, x1 + h, rem, l, u);
    lo[j] = static_cast<int>(l);
    hi[j] = static_cast<int>(u);
  }
  std::size_t evals = 0;
  for (int j = j0; j <= j1; ++j) {
    if (lo[j] > hi[j]) continue;
    evals += offset_chunks(p.sq, lo[j] & ~(kChunk - 1), (hi[j] | (kChunk - 1)) + 1, dy2[j], dz2[j],
                           p.d2 + static_cast<std::size_t>(j) * p.nxp);
  }
  return evals;
}

// A point: the sphere's rows, then the zero-length segment across the rows.
[[gnu::always_inline]] inline std::size_t point_plane(const Plane& p, double cx, double cy,
                                                      double cz) {
  const double dz = p.Z - cz;
  const double rem = p.Rs2 - dz * dz;
  if (rem < 0) return 0;
  const double r = std::sqrt(rem);
  int j0, j1;
  if (!y_range(p, cy - r, cy + r, j0, j1)) return 0;
  Seg s{};
  s.ax = s.bx = cx, s.ay = s.by = cy, s.az = s.bz = cz;
  s.across = true;
  return axis_segment_plane(p, s, j0, j1, 0.0);
}

[[gnu::always_inline]] inline std::size_t segment_plane(const Plane& p, const Seg& s) {
  const double Z = p.Z;
  const double wz = Z - s.az;
  // Rows: the points of the segment within Rs of the plane, grown by Rs in y.
  double t0 = 0, t1 = 1;
  if (s.uz != 0) {
    double a = (Z - p.Rs - s.az) / s.uz, b = (Z + p.Rs - s.az) / s.uz;
    if (a > b) std::swap(a, b);
    // A culling test: err on the wide side, by more than the rounding of a and b.
    const double eps = 1e-9 + 4e-16 * (std::abs(Z) + p.Rs + std::abs(s.az)) / std::abs(s.uz);
    t0 = std::max(0.0, a - eps);
    t1 = std::min(1.0, b + eps);
    if (t0 > t1) return 0;
  } else if (std::abs(wz) > p.Rs) {
    return 0;
  }
  const double ya = s.ay + s.uy * t0, yb = s.ay + s.uy * t1;
  int j0, j1;
  if (!y_range(p, std::min(ya, yb) - p.Rs, std::max(ya, yb) + p.Rs, j0, j1)) return 0;

  const double cz = wz * s.uz;  // the kernel's wz · uz
  const SegChunks sc(s, Z, cz);
  std::size_t evals = 0;
  if (!s.regular) {  // a segment too short for the caps' arithmetic: the full kernel on its box
    int m0, m1;
    x_range(p, std::min(s.ax, s.bx) - p.Rs, std::max(s.ax, s.bx) + p.Rs, true, m0, m1);
    if (m0 > m1) return 0;
    for (int j = j0; j <= j1; ++j) {
      evals += segment_chunks(p.X, m0 & ~(kChunk - 1), (m1 | (kChunk - 1)) + 1, sc, p.Y[j],
                              (p.Y[j] - s.ay) * s.uy, p.d2 + static_cast<std::size_t>(j) * p.nxp);
    }
    return evals;
  }
  if (s.along || s.across) return axis_segment_plane(p, s, j0, j1, cz);

  // Row constants shared by all rows of the plane.
  const double wzb = Z - s.bz;
  const double wz2 = wz * wz, wzb2 = wzb * wzb;
  const double tau = p.hx * s.ux * s.inv;  // dt per sample along the row
  const bool parallel = s.yz2 <= 1e-20 * s.len2;  // along x (or a point)
  // The uncertainty margin of t: rounding of the kernel's t and of this set-up is below
  // 1e-15 (1 + |w| / |u|) for |w| the distance of the samples from a; 1e-9 of it is far above.
  const double extent = std::abs(p.X[0] - s.ax) + std::abs(p.X[p.nx - 1] - s.ax) +
                        std::abs(p.Y[j0] - s.ay) + std::abs(p.Y[j1] - s.ay) + std::abs(wz) +
                        std::abs(s.ax) + std::abs(p.ox);
  const double delta = 1e-9 * (1.0 + extent / s.len);
  const double t_base = (p.ox - s.ax) * s.ux * s.inv;  // t at sample 0 minus the row's c0 · inv

  RowSetup c;
  c.ax = s.ax, c.ay = s.ay, c.bx = s.bx, c.by = s.by, c.ux = s.ux, c.uy = s.uy, c.uz = s.uz;
  c.inv = s.inv, c.len2 = s.len2;
  c.wz = wz, c.wz2 = wz2, c.wzb2 = wzb2;
  c.ox = p.ox, c.inv_hx = p.inv_hx, c.n = p.nx;
  c.Rs2 = p.Rs2;
  c.row_slack = p.Rs + 1e-10 * extent;
  c.parallel = parallel;
  c.inv_yz2 = parallel ? 1.0 : 1.0 / s.yz2;
  c.tau = tau;
  c.inv_tau = tau != 0.0 ? 1.0 / tau : kInfinity;
  c.delta = delta;
  c.t_base = t_base;
  int* lo_a = p.scratch;  // the cap at the low-x end of the row
  int* hi_a = p.scratch + p.ny;
  int* lo_f = p.scratch + 2 * p.ny;  // the middle
  int* hi_f = p.scratch + 3 * p.ny;
  int* lo_b = p.scratch + 4 * p.ny;  // the cap at the high-x end
  int* hi_b = p.scratch + 5 * p.ny;
  setup_rows(c, p.Y, j0, j1, lo_a, hi_a, lo_f, hi_f, lo_b, hi_b);
  const bool rising = tau >= 0.0;
  // The row-independent squares of the caps' kernels over the hull of the rows' pieces:
  // (x − ax)² and (x − bx)².
  int h0, h1;
  if (!hull({lo_a, lo_f, lo_b}, {hi_a, hi_f, hi_b}, j0, j1, p.nxp, h0, h1)) return evals;
  double* sq_a = p.sq;
  double* sq_b = p.sq + p.nxp;
  squares(p.X, h0, h1, s.ax, sq_a);
  squares(p.X, h0, h1, s.bx, sq_b);
  const double* sq_lo = rising ? sq_a : sq_b;  // the squares of the low and the high cap
  const double* sq_hi = rising ? sq_b : sq_a;
  for (int j = j0; j <= j1; ++j) {
    double* row = p.d2 + static_cast<std::size_t>(j) * p.nxp;
    const double y = p.Y[j];
    const double wy = y - s.ay, wyb = y - s.by;
    int f0 = lo_f[j], f1 = hi_f[j];
    // The middle also takes what the caps give up to run on whole chunks.
    const auto cover = [&](int lo, int hi) {
      if (f0 > f1) {
        f0 = lo, f1 = hi;
      } else {
        f0 = std::min(f0, lo), f1 = std::max(f1, hi);
      }
    };
    if (lo_a[j] <= hi_a[j]) {  // the low cap, its last chunk dropped if partial
      const int m0 = lo_a[j] & ~(kChunk - 1), m1 = (hi_a[j] + 1) & ~(kChunk - 1);
      if (m1 <= hi_a[j]) cover(m1, hi_a[j]);
      evals += rising ? offset_chunks(sq_lo, m0, m1, wy * wy, wz2, row)
                      : offset_chunks(sq_lo, m0, m1, wyb * wyb, wzb2, row);
    }
    if (lo_b[j] <= hi_b[j]) {  // the high cap, its first chunk dropped if partial
      const int m0 = (lo_b[j] + kChunk - 1) & ~(kChunk - 1), m1 = (hi_b[j] | (kChunk - 1)) + 1;
      if (m0 > lo_b[j]) cover(lo_b[j], m0 - 1);
      evals += rising ? offset_chunks(sq_hi, m0, m1, wyb * wyb, wzb2, row)
                      : offset_chunks(sq_hi, m0, m1, wy * wy, wz2, row);
    }
    if (f0 <= f1) {
      evals += segment_chunks(p.X, f0 & ~(kChunk - 1), (f1 | (kChunk - 1)) + 1, sc, y,
                              wy * s.uy, row);
    }
  }
  return evals;
}

struct PlaneWork {
  const std::vector<Vec3>* centers;
  const std::vector<Seg>* segs;
  const std::uint32_t* ids;  // the plane's primitives: points first ([0, centers)), then segments
  std::size_t count;
};

// Everything one plane does, in one clone: the primitives, then the values.
ISOFORGE_SIMD_CLONES
std::size_t plane_pass(const Plane& p, const PlaneWork& w) {
  std::fill(p.d2, p.d2 + static_cast<std::size_t>(p.ny) * p.nxp, kInfinity);
  const std::uint32_t npts = static_cast<std::uint32_t>(w.centers->size());
  std::size_t evals = 0;
  for (std::size_t q = 0; q < w.count; ++q) {
    const std::uint32_t id = w.ids[q];
    if (id < npts) {
      const Vec3& c = (*w.centers)[id];
      evals += point_plane(p, c.x, c.y, c.z);
    } else {
      const Seg& s = (*w.segs)[id - npts];
      evals += s.len2 > 0 ? segment_plane(p, s) : point_plane(p, s.ax, s.ay, s.az);
    }
  }
  return evals;
}

// value = sqrt(d2) where below maxd, else far; returns the samples in the band. On chunks: the
// padded rows let the last, partial chunk of a row be computed whole and stored in part.
template <class T>
[[gnu::always_inline]] inline std::size_t finish_body(const Plane& p, double maxd, double far,
                                                      T* out) {
  using Out = std::conditional_t<std::is_same_v<T, float>, FloatChunk, Chunk>;
  using Mask = std::int64_t __attribute__((vector_size(kChunk * sizeof(std::int64_t))));
  const Chunk maxd_v = Chunk{} + maxd, far_v = Chunk{} + far;
  Mask count = {};
  Mask lane;
  for (int l = 0; l < kChunk; ++l) lane[l] = l;
  for (int j = 0; j < p.ny; ++j) {
    const double* row = p.d2 + static_cast<std::size_t>(j) * p.nxp;
    T* o = out + static_cast<std::size_t>(j) * p.nx;
    for (int m = 0; m < p.nx; m += kChunk) {
      Chunk d, v;
      std::memcpy(&d, row + m, sizeof d);
      for (int l = 0; l < kChunk; ++l) v[l] = std::sqrt(d[l]);
      const Mask in = v < maxd_v;
      const Out w = __builtin_convertvector(in ? v : far_v, Out);
      if (m + kChunk <= p.nx) {
        count -= in;
        std::memcpy(o + m, &w, sizeof w);
      } else {  // the last chunk of the row, in part
        const int valid = p.nx - m;
        count -= in & (lane < valid);
        std::memcpy(o + m, &w, sizeof(T) * static_cast<std::size_t>(valid));
      }
    }
  }
  std::int64_t c = 0;
  for (int l = 0; l < kChunk; ++l) c += count[l];
  return static_cast<std::size_t>(c);
}

ISOFORGE_SIMD_CLONES
std::size_t plane_finish(const Plane& p, double maxd, double far, float* out) {
  return finish_body(p, maxd, far, out);
}

ISOFORGE_SIMD_CLONES
std::size_t plane_finish(const Plane& p, double maxd, double far, double* out) {
  return finish_body(p, maxd, far, out);
}

}  // namespace

template <class T>
RowStats distance_rows(const std::vector<Vec3>& centers,
                       const std::vector<std::array<Vec3, 2>>& segments, const GridSpec& g,
                       double max_distance, double far, T* out, const ProgressCallback& progress) {
  const int nx = static_cast<int>(g.dims[0]), ny = static_cast<int>(g.dims[1]);
  const Index nz = g.dims[2];
  const int nxp = (nx + kChunk - 1) / kChunk * kChunk;
  std::vector<double> X(static_cast<std::size_t>(nxp)), Y(static_cast<std::size_t>(ny));
  for (int i = 0; i < nxp; ++i) X[static_cast<std::size_t>(i)] = g.coordinate(0, i);
  for (int j = 0; j < ny; ++j) Y[static_cast<std::size_t>(j)] = g.coordinate(1, j);

  // Slack of every culling test: relative to the reach, and absolute for the rounding of
  // coordinates of magnitude M.
  double M = 0;
  for (int a = 0; a < 3; ++a) {
    M = std::max({M, std::abs(g.origin[a]), std::abs(g.coordinate(a, g.dims[a] - 1))});
  }
  for (const Vec3& c : centers) M = std::max({M, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
  std::vector<Seg> segs(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Vec3 a = segments[i][0], e = segments[i][1] - a;
    Seg& s = segs[i];
    s.ax = a.x, s.ay = a.y, s.az = a.z;
    s.ux = e.x, s.uy = e.y, s.uz = e.z;
    s.len2 = dot(e, e);
    s.inv = s.len2 > 0 ? 1.0 / s.len2 : 0.0;
    s.bx = a.x + e.x * 1.0, s.by = a.y + e.y * 1.0, s.bz = a.z + e.z * 1.0;
    s.yz2 = e.y * e.y + e.z * e.z;
    s.len = std::sqrt(s.len2);
    s.regular = s.len2 >= std::numeric_limits<double>::min() && std::isfinite(s.inv) &&
                std::isfinite(s.len2);
    s.across = e.x == 0;
    s.along = e.y == 0 && e.z == 0;
    for (const Vec3& v : segments[i]) M = std::max({M, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  }
  const double slack = 1e-12 * M;
  const double Rs = max_distance * (1 + 1e-9) + slack;

  // Primitives by plane (CSR): the planes whose z lies within Rs of the primitive's z extent.
  const std::size_t np = centers.size() + segs.size();
  std::vector<std::uint64_t> start(static_cast<std::size_t>(nz) + 1, 0);
  std::vector<std::array<Index, 2>> kr(np);
  const double oz = g.origin.z, inv_hz = 1.0 / g.spacing.z;
  for (std::size_t id = 0; id < np; ++id) {
    double z0, z1;
    if (id < centers.size()) {
      z0 = z1 = centers[id].z;
    } else {
      const Seg& s = segs[id - centers.size()];
      z0 = std::min(s.az, s.bz);
      z1 = std::max(s.az, s.bz);
    }
    double f0 = std::floor((z0 - Rs - oz) * inv_hz), f1 = std::ceil((z1 + Rs - oz) * inv_hz);
    f0 = std::max(f0, 0.0);
    f1 = std::min(f1, static_cast<double>(nz - 1));
    kr[id] = f0 <= f1 ? std::array<Index, 2>{static_cast<Index>(f0), static_cast<Index>(f1)}
                      : std::array<Index, 2>{1, 0};
    for (Index k = kr[id][0]; k <= kr[id][1]; ++k) ++start[static_cast<std::size_t>(k) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::uint32_t> ids(start.back());
  {
    std::vector<std::uint64_t> fill(start.begin(), start.end() - 1);
    for (std::size_t id = 0; id < np; ++id) {
      for (Index k = kr[id][0]; k <= kr[id][1]; ++k) {
        ids[fill[static_cast<std::size_t>(k)]++] = static_cast<std::uint32_t>(id);
      }
    }
  }

  std::atomic<std::size_t> evals{0}, active{0};
  const std::size_t plane_size = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  const auto planes = [&](Index k0, Index k1) {
    tbb::parallel_for(tbb::blocked_range<Index>(k0, k1, 1), [&](const tbb::blocked_range<Index>& r) {
      std::unique_ptr<double[]> d2(new double[static_cast<std::size_t>(ny) * nxp]);
      std::unique_ptr<int[]> scratch(new int[6 * static_cast<std::size_t>(ny)]);
      std::unique_ptr<double[]> sq(new double[2 * static_cast<std::size_t>(nxp)]);
      std::unique_ptr<double[]> rowc(new double[2 * static_cast<std::size_t>(ny)]);
      Plane p{X.data(), Y.data(), 0, nx, nxp, ny, g.origin.x, g.spacing.x, 1.0 / g.spacing.x,
              g.origin.y, 1.0 / g.spacing.y, Rs, Rs * Rs, d2.get(), scratch.get(),
              sq.get(), rowc.get()};
      std::size_t e = 0, a = 0;
      for (Index k = r.begin(); k != r.end(); ++k) {
        p.Z = g.coordinate(2, k);
        const std::size_t b = start[static_cast<std::size_t>(k)];
        const PlaneWork w{&centers, &segs, ids.data() + b, start[static_cast<std::size_t>(k) + 1] - b};
        e += plane_pass(p, w);
        a += plane_finish(p, max_distance, far, out + plane_size * static_cast<std::size_t>(k));
      }
      evals += e;
      active += a;
    });
  };
  // In chunks of planes when progress is reported (the callback runs on this thread).
  const Index chunks = progress ? std::clamp<Index>(nz / 8, 1, 64) : 1;
  for (Index c = 0; c < chunks; ++c) {
    planes(nz * c / chunks, nz * (c + 1) / chunks);
    if (progress) {
      report_progress(progress, 0.05 + 0.9 * static_cast<double>(c + 1) / static_cast<double>(chunks),
                      "distance");
    }
  }
  return {evals.load(), active.load(), static_cast<std::size_t>(nz)};
}

template RowStats distance_rows<float>(const std::vector<Vec3>&,
                                       const std::vector<std::array<Vec3, 2>>&, const GridSpec&,
                                       double, double, float*, const ProgressCallback&);
template RowStats distance_rows<double>(const std::vector<Vec3>&,
                                        const std::vector<std::array<Vec3, 2>>&, const GridSpec&,
                                        double, double, double*, const ProgressCallback&);

}  // namespace isoforge::model_detail
