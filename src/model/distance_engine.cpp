// The block engine of the exact distance fields (distance_engine.hpp): the Scatter and Gather
// strategies over blocks of samples, for dense images and OpenVDB narrow bands alike.
//
// Methods implemented:
// - D. Eberly, "Distance Between Point and Triangle in 3D" (Geometric Tools): the exact kernel
//   (closest_point.hpp), shared by every path so that their values agree bit for bit.
// - Banded scan conversion of primitives: the per-cell loop of vtkImplicitModeller (Schroeder,
//   Martin & Lorensen, *The Visualization Toolkit*, "Implicit Modelling"), with every row of a
//   primitive's box cut to the sphere / cylinder / slab that can lie within reach — a superset of
//   the characteristic regions of S. Mauch, "A fast algorithm for computing the closest point and
//   distance transform" (Caltech, 2000).
// - Branch-and-bound nearest-primitive queries in the spatial module's 4-wide bounding volume
//   hierarchy (spatial/primitive_locator.hpp), seeded with the previous sample's nearest
//   primitive.
// - J. A. Bærentzen, H. Aanæs, "Signed distance computation using the angle weighted
//   pseudonormal", IEEE TVCG 11(3), 2005: the sign at the closest feature (distance_signs.hpp).
//
// Work unit: blocks of 8 x 8 x kz samples (kz = 8: aligned like OpenVDB leaves; 64 for dense
// output). Scatter bins (block, primitive) pairs, sorts them, and processes each block's
// primitives nearest first, cutting later ones' rows to where they can still win; Gather finds
// blocks within reach by a two-level box test and queries the BVH per sample. Either way one task
// owns a block, so no writes are shared, and ties go to the smallest primitive id whatever the
// order: results do not depend on the thread count, the strategy or the block shape.

#include "distance_engine.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>

#include "isoforge/core/closest_point.hpp"
#include "isoforge/spatial/primitive_locator.hpp"

namespace isoforge::model_detail {

namespace {

constexpr u32 kNone = PrimitiveSet::kNone;

// ---------------------------------------------------------------------------------------------
// Row kernels of the Scatter strategy: plain loops the compiler vectorizes, cloned for AVX-512
// and AVX2 (ISOFORGE_SIMD_CLONES, src/CMakeLists.txt); every clone computes the same bits as the
// scalar kernels of core/closest_point.hpp.
// ---------------------------------------------------------------------------------------------

// A segment a + t u, t in [0, 1]; inv = 1 / |u|².
struct SegmentRow {
  double ax, ay, az, ux, uy, uz, inv;
};

// Squared distances from (x, y, z[m]) to c: exactly norm2(p - c).
ISOFORGE_SIMD_CLONES
void point_row(const Vec3& c, double x, double y, const double* __restrict z, int n,
               double* __restrict out) {
  const double dx = x - c.x, dy = y - c.y;
  const double dxy = dx * dx + dy * dy;
  for (int m = 0; m < n; ++m) {
    const double dz = z[m] - c.z;
    out[m] = dxy + dz * dz;
  }
}

// d = min(d, v) with ties to the smaller id (w follows); true if it changed. Written without
// short-circuits and with one integer width per lane, so that the loops using it vectorize.
[[gnu::always_inline]] inline bool keep_min_lane(double v, double& d, u32& w, u32 id) {
  const double cur = d;
  const std::uint64_t who = w;
  const bool win = (v < cur) | ((v == cur) & (id < who));
  d = win ? v : cur;
  w = win ? id : static_cast<u32>(who);
  return win;
}

// d2[m] = min(d2[m], v[m]) with ties to the smaller id (who[m] follows); true if any changed.
ISOFORGE_SIMD_CLONES
bool keep_min_row(const double* __restrict v, int n, double* __restrict d2, u32* __restrict who,
                  u32 id) {
  std::int64_t changed = 0;
  for (int m = 0; m < n; ++m) changed += keep_min_lane(v[m], d2[m], who[m], id);
  return changed != 0;
}

// Squared distances from (x, y, z[m]) to the segment a + t u, t in [0, 1], exactly as
// segment_distance2 (closest_on_segment) computes them, operation by operation, kept where
// smaller than d2 (as keep_min_row, in the same pass).
ISOFORGE_SIMD_CLONES
bool segment_min_row(const SegmentRow& s, double x, double y, const double* __restrict z, int n,
                     double* __restrict d2, u32* __restrict who, u32 id) {
  const double wx = x - s.ax, wy = y - s.ay;
  const double wxy = wx * s.ux + wy * s.uy;
  std::int64_t changed = 0;
  for (int m = 0; m < n; ++m) {
    double t = (wxy + (z[m] - s.az) * s.uz) * s.inv;
    t = t < 0.0 ? 0.0 : t;
    t = 1.0 < t ? 1.0 : t;
    const double dx = x - (s.ax + s.ux * t), dy = y - (s.ay + s.uy * t),
                 dz = z[m] - (s.az + s.uz * t);
    changed += keep_min_lane(dx * dx + dy * dy + dz * dz, d2[m], who[m], id);
  }
  return changed != 0;
}

// Unsigned values of a row without radii: value = sqrt(d2) where below maxd (active), else
// maxd. Returns the number of active samples.
ISOFORGE_SIMD_CLONES
int finish_row(const double* __restrict d2, int n, double maxd, double* __restrict value,
               std::uint8_t* __restrict active) {
  int count = 0;
  for (int k = 0; k < n; ++k) {
    const double v = std::sqrt(d2[k]);
    const bool in = v < maxd;
    value[k] = in ? v : maxd;
    active[k] = static_cast<std::uint8_t>(in);
    count += in;
  }
  return count;
}

// The largest of n >= 1 non-negative, non-NaN doubles (squared distances). For such values the
// order of the bit patterns as integers is the order of the values, and an integer maximum
// vectorizes (a floating-point one does not without -ffast-math).
ISOFORGE_SIMD_CLONES
double max_nonnegative(const double* __restrict v, int n) {
  std::uint64_t m = 0;
  for (int k = 0; k < n; ++k) {
    std::uint64_t b;
    std::memcpy(&b, v + k, sizeof b);
    m = b > m ? b : m;
  }
  double r;
  std::memcpy(&r, &m, sizeof r);
  return r;
}

constexpr double kInf = std::numeric_limits<double>::infinity();
// Relative slack of every conservative (culling) test: culling never decides a value.
constexpr double kSlack = 1e-9;

class Engine {
 public:
  Engine(const PrimitiveSet& P, const GridSpec& g, const DistanceOptions& o,
         const Pseudonormals* signs, int kz)
      : P_(P), g_(g), maxd_(o.max_distance), signs_(signs), kz_(kz) {
    for (int a = 0; a < 3; ++a) {
      coord_[a].resize(static_cast<std::size_t>(g.dims[a]));
      for (Index i = 0; i < g.dims[a]; ++i)
        coord_[a][static_cast<std::size_t>(i)] = g.coordinate(a, i);
      const Index depth = a == 2 ? kz : 8;
      nb_[a] = (g.dims[a] + depth - 1) / depth;
      inv_[a] = 1.0 / g.spacing[a];
    }
    if (static_cast<double>(nb_[0]) * static_cast<double>(nb_[1]) * static_cast<double>(nb_[2]) >
        9e18) {
      throw Error("distance: the grid has too many blocks");
    }
  }

  struct ReachEstimates {
    double scatter = 0;  ///< Scatter's kernel calls: every primitive's own reach, overlaps counted
    double samples = 0;  ///< samples within reach of some primitive (overlaps not counted)
  };

  // One pass over the primitives with reach R = max distance + radius. Scatter evaluates each
  // primitive in its whole reach: a ball per point, plus the swept tube of a segment, plus the
  // slab (2 R A), edge tubes and corner balls of a triangle. The samples within reach of some
  // primitive are estimated without the overlaps (2 R A per triangle, pi R² L per segment, a ball
  // per point), at most the samples of the grid within the primitives' bounds grown by the reach.
  [[nodiscard]] ReachEstimates reach_estimates() const {
    const double hv = g_.spacing.x * g_.spacing.y * g_.spacing.z;
    constexpr double pi = std::numbers::pi;
    ReachEstimates e;
    for (u32 id = 0; id < P_.size(); ++id) {
      const double R = maxd_ + P_.radius(id);
      const double ball = 4.0 / 3.0 * pi * R * R * R;
      if (id >= P_.triangle_begin()) {
        const auto& t = P_.triangles()[id - P_.triangle_begin()];
        const Vec3 a = P_.vertices()[t[0]], b = P_.vertices()[t[1]], c = P_.vertices()[t[2]];
        const double area = 0.5 * norm(cross(b - a, c - a));
        const double perim = norm(b - a) + norm(c - b) + norm(a - c);
        e.scatter += ball + (2 * area * R + 0.5 * pi * perim * R * R);
        e.samples += 2 * area * R;
      } else if (id >= P_.segment_begin()) {
        const auto& sg = P_.segments()[id - P_.segment_begin()];
        const double tube = pi * R * R * norm(P_.vertices()[sg[1]] - P_.vertices()[sg[0]]);
        e.scatter += ball + tube;
        e.samples += tube;
      } else {
        e.scatter += ball;
        e.samples += ball;
      }
    }
    e.scatter /= hv;
    e.samples = std::min(e.samples / hv, reach_box_samples());
    return e;
  }

  // Samples of the grid within the primitives' bounds grown by the reach.
  [[nodiscard]] double reach_box_samples() const {
    Bounds b;
    double extra = 0;
    for (u32 id = 0; id < P_.size(); ++id) extra = std::max(extra, P_.radius(id));
    for (const Vec3& p : P_.vertices()) b.extend(p);
    const double R = maxd_ + extra;
    double n = 1;
    for (int a = 0; a < 3; ++a) {
      Index i0, i1;
      if (!range(a, b.min[a] - R, b.max[a] + R, i0, i1)) return 0;
      n *= static_cast<double>(i1 - i0 + 1);
    }
    return n;
  }

  // ---- Scatter ----
  std::vector<Task> scatter_tasks(std::vector<Pair>& pairs) const {
    const u32 n = P_.size();
    std::vector<std::size_t> offset(static_cast<std::size_t>(n) + 1, 0);
    tbb::parallel_for(tbb::blocked_range<u32>(0, n, 256), [&](const tbb::blocked_range<u32>& r) {
      for (u32 id = r.begin(); id != r.end(); ++id) {
        std::size_t c = 0;
        for_each_reach_block(id, [&](u64) { ++c; });
        offset[id + 1] = c;
      }
    });
    for (std::size_t i = 0; i < n; ++i) offset[i + 1] += offset[i];
    pairs.resize(offset[n]);
    tbb::parallel_for(tbb::blocked_range<u32>(0, n, 256), [&](const tbb::blocked_range<u32>& r) {
      for (u32 id = r.begin(); id != r.end(); ++id) {
        std::size_t w = offset[id];
        for_each_reach_block(id, [&](u64 key) { pairs[w++] = {key, id}; });
      }
    });
    tbb::parallel_sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
      return a.key != b.key ? a.key < b.key : a.prim < b.prim;
    });
    std::vector<Task> tasks;
    for (std::size_t s = 0; s < pairs.size();) {
      std::size_t e = s + 1;
      while (e < pairs.size() && pairs[e].key == pairs[s].key) ++e;
      tasks.push_back({pairs[s].key, s, e});
      s = e;
    }
    return tasks;
  }

  void scatter_block(const Task& t, const std::vector<Pair>& pairs, BlockOut& out) const {
    setup(t.key, out);
    const int nv = 64 * kz_;
    double* d2 = out.d2;
    double* rv = out.rv;
    u32* who = out.who;
    std::fill(d2, d2 + nv, kInf);
    std::fill(who, who + nv, kNone);
    const bool radii = P_.has_radii();
    if (radii) std::fill(rv, rv + nv, kInf);
    std::fill(out.rowmax, out.rowmax + 64, kInf);
    // Nearest primitives first (by their distance to the block's center): the rows of the later
    // ones are then cut to where they can still beat the current minimum. Ties of values go to
    // the smallest id whatever the order (see keep_min), so the order changes no result.
    Vec3 blo, bhi;
    box_of(out.i0, out.j0, out.k0, 8, kz_, blo, bhi);
    const Vec3 c = (blo + bhi) * 0.5;
    std::vector<std::pair<double, u32>>& order = out.order;
    order.clear();
    for (std::size_t q = t.begin; q < t.end; ++q) {
      const u32 id = pairs[q].prim;
      order.emplace_back(std::sqrt(P_.dist2(id, c)) - P_.radius(id), id);
    }
    out.evals += order.size();
    std::sort(order.begin(), order.end());
    for (const auto& [dc, id] : order) {
      out.evals += rasterize(id, out, d2, radii ? rv : nullptr, who);
    }
    finish(out, d2, radii ? rv : nullptr, who);
  }

  // ---- Gather ----
  std::vector<Task> gather_tasks(const PrimitiveLocator& bvh) const {
    double extra = 0;
    for (u32 id = 0; id < P_.size(); ++id) extra = std::max(extra, P_.radius(id));
    const double R = maxd_ + extra;
    const double r2 = R * R * (1 + kSlack);
    Bounds all;
    for (const Vec3& p : P_.vertices()) all.extend(p);
    Index lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      if (!range(a, all.min[a] - R, all.max[a] + R, lo[a], hi[a])) return {};
    }
    // Super blocks of 64³ samples (8 x 8 x 64 / kz blocks), tested before their blocks.
    const Index szb = 64 / kz_;
    Index slo[3], shi[3];
    for (int a = 0; a < 3; ++a) slo[a] = lo[a] >> 6, shi[a] = hi[a] >> 6;
    std::vector<std::array<Index, 3>> supers;
    for (Index z = slo[2]; z <= shi[2]; ++z)
      for (Index y = slo[1]; y <= shi[1]; ++y)
        for (Index x = slo[0]; x <= shi[0]; ++x) supers.push_back({x, y, z});
    std::vector<std::vector<u64>> found(supers.size());
    tbb::parallel_for(std::size_t{0}, supers.size(), [&](std::size_t s) {
      const auto& sb = supers[s];
      Vec3 blo, bhi;
      if (!box_of(sb[0] * 64, sb[1] * 64, sb[2] * 64, 64, 64, blo, bhi)) return;
      if (!bvh.any_within(blo, bhi, r2)) return;
      for (Index z = sb[2] * szb; z < sb[2] * szb + szb && z < nb_[2]; ++z)
        for (Index y = sb[1] * 8; y < sb[1] * 8 + 8 && y < nb_[1]; ++y)
          for (Index x = sb[0] * 8; x < sb[0] * 8 + 8 && x < nb_[0]; ++x) {
            if (x * 8 > hi[0] || x * 8 + 7 < lo[0] || y * 8 > hi[1] || y * 8 + 7 < lo[1] ||
                z * kz_ > hi[2] || z * kz_ + kz_ - 1 < lo[2]) {
              continue;
            }
            if (!box_of(x * 8, y * 8, z * kz_, 8, kz_, blo, bhi)) continue;
            if (bvh.any_within(blo, bhi, r2)) found[s].push_back(key_of(x, y, z));
          }
    });
    std::vector<Task> tasks;
    for (auto& f : found) {
      for (u64 k : f) tasks.push_back({k, 0, 0});
    }
    std::sort(tasks.begin(), tasks.end(),
              [](const Task& a, const Task& b) { return a.key < b.key; });
    return tasks;
  }

  void gather_block(const Task& t, const PrimitiveLocator& bvh, BlockOut& out) const {
    setup(t.key, out);
    double* d2 = out.d2;
    u32* who = out.who;
    std::fill(d2, d2 + 64 * kz_, kInf);
    std::fill(who, who + 64 * kz_, kNone);
    const double limit2 = maxd_ * maxd_;
    u32 seed = kNone;
    for (int i = 0; i < out.ni; ++i)
      for (int j = 0; j < out.nj; ++j)
        for (int k = 0; k < out.nk; ++k) {
          const Vec3 p = position(out.i0 + i, out.j0 + j, out.k0 + k);
          ClosestPrimitive near;
          if (seed != kNone) {
            near.dist2 = P_.dist2(seed, p);
            near.id = seed;
            ++out.evals;
          }
          bvh.nearest(p, limit2, near);
          out.evals += near.evaluations;
          const double best2 = near.dist2;
          const u32 best = near.id;
          const int off = (i * 8 + j) * kz_ + k;
          d2[off] = best2;
          who[off] = best;
          if (best != kNone) seed = best;
        }
    finish(out, d2, nullptr, who);
  }

  // Block index coordinates of a key, and the key of block coordinates.
  [[nodiscard]] u64 key_of(Index x, Index y, Index z) const {
    return static_cast<u64>(x) +
           static_cast<u64>(nb_[0]) *
               (static_cast<u64>(y) + static_cast<u64>(nb_[1]) * static_cast<u64>(z));
  }
  void block_of(u64 key, Index& x, Index& y, Index& z) const {
    x = static_cast<Index>(key % static_cast<u64>(nb_[0]));
    key /= static_cast<u64>(nb_[0]);
    y = static_cast<Index>(key % static_cast<u64>(nb_[1]));
    z = static_cast<Index>(key / static_cast<u64>(nb_[1]));
  }

 private:
  [[nodiscard]] Vec3 position(Index i, Index j, Index k) const {
    return {coord_[0][static_cast<std::size_t>(i)], coord_[1][static_cast<std::size_t>(j)],
            coord_[2][static_cast<std::size_t>(k)]};
  }

  // Samples [i0, i1] along `axis` whose coordinates may lie in [lo, hi] (conservative).
  bool range(int axis, double lo, double hi, Index& i0, Index& i1) const {
    const double o = g_.origin[axis], inv = inv_[axis];
    const double n = static_cast<double>(g_.dims[axis]);
    // Callers pass intervals inflated by a relative 1e-9, which covers the rounding of the
    // reciprocal: no sample inside the true interval is missed.
    double t0 = std::floor((lo - o) * inv), t1 = std::ceil((hi - o) * inv);
    if (!(t0 <= t1)) return false;
    t0 = std::max(t0, 0.0);
    t1 = std::min(t1, n - 1);
    if (t0 > t1) return false;
    i0 = static_cast<Index>(t0);
    i1 = static_cast<Index>(t1);
    return true;
  }

  // World box of the samples of [x, x + size) x [y, y + size) x [z, z + zsize) clipped to the
  // grid.
  bool box_of(Index x, Index y, Index z, Index size, Index zsize, Vec3& lo, Vec3& hi) const {
    const Index o[3] = {x, y, z};
    for (int a = 0; a < 3; ++a) {
      if (o[a] >= g_.dims[a]) return false;
      const Index last = std::min(o[a] + (a == 2 ? zsize : size) - 1, g_.dims[a] - 1);
      lo[a] = coord_[a][static_cast<std::size_t>(o[a])];
      hi[a] = coord_[a][static_cast<std::size_t>(last)];
    }
    return true;
  }

  template <class F>
  void for_each_reach_block(u32 id, F&& f) const {
    const double R = (maxd_ + P_.radius(id)) * (1 + kSlack);
    const Bounds b = P_.bounds(id);
    Index lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      if (!range(a, b.min[a] - R, b.max[a] + R, lo[a], hi[a])) return;
    }
    for (Index z = lo[2] / kz_; z <= hi[2] / kz_; ++z)
      for (Index y = lo[1] >> 3; y <= hi[1] >> 3; ++y)
        for (Index x = lo[0] >> 3; x <= hi[0] >> 3; ++x) {
          Vec3 blo, bhi;
          if (!box_of(x * 8, y * 8, z * kz_, 8, kz_, blo, bhi)) continue;
          const Vec3 c = (blo + bhi) * 0.5;
          const double lim = R + 0.5 * norm(bhi - blo);
          if (P_.dist2(id, c) > lim * lim * (1 + kSlack)) continue;
          f(key_of(x, y, z));
        }
  }

  void setup(u64 key, BlockOut& out) const {
    Index x, y, z;
    block_of(key, x, y, z);
    out.i0 = x * 8, out.j0 = y * 8, out.k0 = z * kz_;
    out.kz = kz_;
    out.ni = static_cast<int>(std::min<Index>(8, g_.dims[0] - out.i0));
    out.nj = static_cast<int>(std::min<Index>(8, g_.dims[1] - out.j0));
    out.nk = static_cast<int>(std::min<Index>(kz_, g_.dims[2] - out.k0));
    out.n_active = 0;
    out.evals = 0;
  }

  // Values, band flags and signs of a block from its minimum squared distances.
  void finish(BlockOut& out, const double* d2, const double* rv, const u32* who) const {
    std::fill(out.active, out.active + 64 * kz_, std::uint8_t{0});
    if (!signs_ && !rv) {
      for (int i = 0; i < out.ni; ++i)
        for (int j = 0; j < out.nj; ++j) {
          const int off = (i * 8 + j) * kz_;
          out.n_active += static_cast<std::size_t>(
              finish_row(d2 + off, out.nk, maxd_, out.value + off, out.active + off));
        }
      return;
    }
    for (int i = 0; i < out.ni; ++i)
      for (int j = 0; j < out.nj; ++j)
        for (int k = 0; k < out.nk; ++k) {
          const int off = (i * 8 + j) * kz_ + k;
          double v = std::sqrt(d2[off]);
          if (rv && rv[off] < v) v = rv[off];
          if (v < maxd_) {
            if (signs_)
              v *= signs_->sign(P_, who[off], position(out.i0 + i, out.j0 + j, out.k0 + k));
            out.value[off] = v;
            out.active[off] = 1;
            ++out.n_active;
          } else {
            out.value[off] = maxd_;
          }
        }
  }

  // Visits the samples of block `out` within reach of primitive `id`; returns kernel calls.
  std::size_t rasterize(u32 id, BlockOut& out, double* d2, double* rv, u32* who) const {
    const double R = maxd_ + P_.radius(id);
    const double Rs = R * (1 + kSlack);
    const Bounds b = P_.bounds(id);
    Index lo[3], hi[3];
    const Index blo[3] = {out.i0, out.j0, out.k0};
    const int bn[3] = {out.ni, out.nj, out.nk};
    for (int a = 0; a < 3; ++a) {
      if (!range(a, b.min[a] - Rs, b.max[a] + Rs, lo[a], hi[a])) return 0;
      lo[a] = std::max(lo[a], blo[a]);
      hi[a] = std::min(hi[a], blo[a] + bn[a] - 1);
      if (lo[a] > hi[a]) return 0;
    }
    const double zmin_box = b.min.z - Rs, zmax_box = b.max.z + Rs;
    std::size_t evals = 0;
    // After a row changed, its largest d2 (over the whole row: an upper bound for any part).
    const auto refresh_row = [&](Index i, Index j) {
      if (!out.row_dirty) return;
      const int r = static_cast<int>((i - blo[0]) * 8 + (j - blo[1]));
      out.rowmax[r] = max_nonnegative(d2 + r * kz_, out.nk);
    };
    // Runs `kernel` over the samples k of row (i, j) whose z lies in [zlo, zhi].
    const auto row = [&](Index i, Index j, double zlo, double zhi, auto&& kernel) {
      Index k0, k1;
      if (!range(2, std::max(zlo, zmin_box), std::min(zhi, zmax_box), k0, k1)) return;
      k0 = std::max(k0, lo[2]);
      k1 = std::min(k1, hi[2]);
      const double x = coord_[0][static_cast<std::size_t>(i)];
      const double y = coord_[1][static_cast<std::size_t>(j)];
      const int base = static_cast<int>(((i - blo[0]) * 8 + (j - blo[1])) * kz_ - blo[2]);
      out.row_dirty = false;
      for (Index k = k0; k <= k1; ++k) {
        const Vec3 p{x, y, coord_[2][static_cast<std::size_t>(k)]};
        const int off = base + static_cast<int>(k);
        kernel(p, off);
      }
      if (k1 >= k0) evals += static_cast<std::size_t>(k1 - k0 + 1);
      refresh_row(i, j);
    };
    const auto keep_min = [&](double v, int off) {
      if (v < d2[off] || (v == d2[off] && id < who[off])) {
        d2[off] = v, who[off] = id;
        out.row_dirty = true;
      }
    };
    // The reach along row (i, j): R, or less where every sample of the row that the primitive
    // can touch already holds a smaller distance (it cannot win there).
    const auto row_reach = [&](Index i, Index j) {
      const int base = static_cast<int>(((i - blo[0]) * 8 + (j - blo[1])) * kz_ - blo[2]);
      double worst = 0;
      if (rv) {
        // With radii the value is min(sqrt(d2), rv): a ball wins where |p - c| - r < rv, a
        // plain primitive where its distance is below that minimum.
        if (id < P_.segment_begin()) {
          for (Index k = lo[2]; k <= hi[2]; ++k) worst = std::max(worst, rv[base + k]);
          return std::min(Rs, std::max(0.0, worst + P_.radius(id)) * (1 + kSlack));
        }
        for (Index k = lo[2]; k <= hi[2]; ++k) {
          worst = std::max(worst, std::min(std::sqrt(d2[base + k]), rv[base + k]));
        }
        return std::min(Rs, worst * (1 + kSlack));
      }
      (void)base;
      return std::min(Rs, std::sqrt(out.rowmax[(i - blo[0]) * 8 + (j - blo[1])]) * (1 + kSlack));
    };
    // The same for a kernel that updates a whole row at once (vectorizable loops):
    // batch(x, y, z of the first sample, count, d2 of the first, who of the first) -> changed.
    const auto row_batch = [&](Index i, Index j, double zlo, double zhi, auto&& batch) {
      Index k0, k1;
      if (!range(2, std::max(zlo, zmin_box), std::min(zhi, zmax_box), k0, k1)) return;
      k0 = std::max(k0, lo[2]);
      k1 = std::min(k1, hi[2]);
      if (k1 < k0) return;
      const int n = static_cast<int>(k1 - k0 + 1);
      const int base = static_cast<int>(((i - blo[0]) * 8 + (j - blo[1])) * kz_ + (k0 - blo[2]));
      out.row_dirty =
          batch(coord_[0][static_cast<std::size_t>(i)], coord_[1][static_cast<std::size_t>(j)],
                &coord_[2][static_cast<std::size_t>(k0)], n, d2 + base, who + base);
      evals += static_cast<std::size_t>(n);
      refresh_row(i, j);
    };
    // Squared distances to point c along a row (exactly norm2(p - c)), kept where smaller.
    const auto point_batch = [id](const Vec3& c) {
      return [c, id](double x, double y, const double* z, int n, double* d, u32* w) {
        double tmp[64];
        point_row(c, x, y, z, n, tmp);
        return keep_min_row(tmp, n, d, w, id);
      };
    };
    if (id >= P_.triangle_begin()) {
      const auto& t = P_.triangles()[id - P_.triangle_begin()];
      const Vec3 a = P_.vertices()[t[0]], bb = P_.vertices()[t[1]], c = P_.vertices()[t[2]];
      const Vec3 nrm = cross(bb - a, c - a);
      const double nl = norm(nrm);
      const Vec3 n = nl > 0 ? nrm / nl : Vec3{};
      // A cheap lower bound first: the distance to the slab-disc around the triangle (its plane,
      // within rho of the centroid). Samples where it already exceeds the current minimum skip
      // the exact kernel (with a relative slack, so ties still reach it).
      const Vec3 cen = (a + bb + c) / 3.0;
      double rho = 0;
      for (const Vec3& v : {a, bb, c}) rho = std::max(rho, norm(cross(v - cen, n)));
      rho = rho * (1 + 1e-6) + 1e-300;
      const auto kernel = [&](const Vec3& p, int off) {
        if (nl > 0 && d2[off] < kInf) {
          const Vec3 w = p - cen;
          const double h = dot(w, n);
          const double l = std::max(0.0, norm(cross(w, n)) - rho);
          if ((h * h + l * l) * (1 - 1e-6) > d2[off]) return;
        }
        keep_min(triangle_distance2(p, a, bb, c), off);
      };
      for (Index i = lo[0]; i <= hi[0]; ++i)
        for (Index j = lo[1]; j <= hi[1]; ++j) {
          if (nl == 0) {
            row(i, j, -kInf, kInf, kernel);
            continue;
          }
          // Slab |n . (p - a)| <= reach.
          const double Rr = row_reach(i, j);
          const double f = n.x * (coord_[0][static_cast<std::size_t>(i)] - a.x) +
                           n.y * (coord_[1][static_cast<std::size_t>(j)] - a.y);
          if (std::abs(n.z) < 1e-12) {
            if (std::abs(f) <= Rr) row(i, j, -kInf, kInf, kernel);
            continue;
          }
          const double z0 = a.z + (-Rr - f) / n.z, z1 = a.z + (Rr - f) / n.z;
          row(i, j, std::min(z0, z1), std::max(z0, z1), kernel);
        }
    } else if (id >= P_.segment_begin()) {
      const auto& s = P_.segments()[id - P_.segment_begin()];
      const Vec3 a = P_.vertices()[s[0]], bb = P_.vertices()[s[1]];
      const Vec3 u = bb - a;
      const double L2 = dot(u, u);
      const double inv = 1.0 / L2;
      const SegmentRow sr{a.x, a.y, a.z, u.x, u.y, u.z, inv};
      const auto pt = point_batch(a);  // a zero-length segment is its point
      const auto kernel = [&](double x, double y, const double* z, int n, double* d, u32* w) {
        return L2 > 0 ? segment_min_row(sr, x, y, z, n, d, w, id) : pt(x, y, z, n, d, w);
      };
      const double alpha = L2 > 0 ? (u.x * u.x + u.y * u.y) / L2 : 1.0;
      const double inv2a = 0.5 / alpha;
      for (Index i = lo[0]; i <= hi[0]; ++i)
        for (Index j = lo[1]; j <= hi[1]; ++j) {
          const double wx = coord_[0][static_cast<std::size_t>(i)] - a.x;
          const double wy = coord_[1][static_cast<std::size_t>(j)] - a.y;
          const double Rr = row_reach(i, j);
          if (L2 == 0 || alpha < 1e-9) {
            // A point, or a segment along z: the row is within reach iff its (x, y) is.
            if (wx * wx + wy * wy <= Rr * Rr) row_batch(i, j, -kInf, kInf, kernel);
            continue;
          }
          // Distance to the line through a, b along the row: alpha s² + beta s + gamma <= 0,
          // s = z - a.z.
          const double c0 = wx * u.x + wy * u.y;
          const double beta = -2 * c0 * u.z * inv;
          const double gamma = wx * wx + wy * wy - c0 * c0 * inv - Rr * Rr;
          const double disc = beta * beta - 4 * alpha * gamma;
          if (disc < 0) continue;
          const double sq = std::sqrt(disc);
          row_batch(i, j, a.z + (-beta - sq) * inv2a, a.z + (-beta + sq) * inv2a, kernel);
        }
    } else {
      const Vec3 c = P_.vertices()[P_.points()[id]];
      const double r = P_.radius(id);
      const auto batch = point_batch(c);
      const auto kernel = [&](const Vec3& p, int off) {
        const double v = norm2(p - c);
        if (rv) {
          const double w = std::sqrt(v) - r;
          if (w < rv[off]) rv[off] = w, who[off] = id;
        } else {
          keep_min(v, off);
        }
      };
      for (Index i = lo[0]; i <= hi[0]; ++i)
        for (Index j = lo[1]; j <= hi[1]; ++j) {
          const double dx = coord_[0][static_cast<std::size_t>(i)] - c.x;
          const double dy = coord_[1][static_cast<std::size_t>(j)] - c.y;
          const double Rr = row_reach(i, j);
          const double rem = Rr * Rr - dx * dx - dy * dy;
          if (rem < 0) continue;
          const double half = std::sqrt(rem);
          if (rv) {
            row(i, j, c.z - half, c.z + half, kernel);
          } else {
            row_batch(i, j, c.z - half, c.z + half, batch);
          }
        }
    }
    return evals;
  }

  const PrimitiveSet& P_;
  const GridSpec& g_;
  double maxd_;
  const Pseudonormals* signs_;
  int kz_;
  std::array<std::vector<double>, 3> coord_;
  Index nb_[3];
  double inv_[3];
};

}  // namespace

PrimitiveSet distance_primitives(const PolyData& input, const DistanceOptions& o) {
  PrimitiveSet p = primitives_of(input, "distance");
  if (!o.radius_array.empty()) {
    const DataArray* a = input.point_data.find(o.radius_array);
    if (!a) throw Error("distance: radius array '" + o.radius_array + "' is not in the point data");
    if (a->components() != 1) {
      throw Error(fmt::format("distance: radius array '{}' has {} components, needs 1",
                              o.radius_array, a->components()));
    }
    std::vector<double> radii(p.points().size());
    for (std::size_t i = 0; i < radii.size(); ++i) {
      const double r = a->get(p.points()[i]);
      if (!(r >= 0) || !std::isfinite(r)) {
        throw Error(fmt::format("distance: radius of point {} is {:g}, must be finite and >= 0",
                                p.points()[i], r));
      }
      radii[i] = r;
    }
    p.set_radii(std::move(radii));
  }
  return p;
}

void check_common(const GridSpec& g, const DistanceOptions& o) {
  g.validate("distance", true);
  for (int a = 0; a < 3; ++a) {
    if (g.dims[a] > (Index{1} << 30)) throw Error("distance: dims exceed 2^30 samples per axis");
  }
  if (!(o.max_distance > 0) || !std::isfinite(o.max_distance)) {
    throw Error(fmt::format("distance: max_distance must be positive and finite, got {:g}",
                            o.max_distance));
  }
}

// The strategy `o` asks for, or (Auto) Gather when Scatter's estimated kernel calls exceed
// `gather_ratio` times the samples within reach; fills the counts of `stats`.
DistanceStrategy choose_strategy(const PrimitiveSet& P, const GridSpec& g, const DistanceOptions& o,
                                 int kz, double gather_ratio, DistanceStats& stats) {
  const Engine engine(P, g, o, nullptr, kz);
  stats.points = P.points().size();
  stats.segments = P.segments().size();
  stats.triangles = P.triangles().size();
  const auto estimates = engine.reach_estimates();
  stats.scatter_estimate = estimates.scatter;
  DistanceStrategy s = o.strategy;
  if (s == DistanceStrategy::Gather && P.has_radii()) {
    throw Error("distance: the Gather strategy does not support radii (use Scatter or Auto)");
  }
  if (s == DistanceStrategy::Auto) {
    s = P.has_radii() || stats.scatter_estimate <= gather_ratio * estimates.samples
            ? DistanceStrategy::Scatter
            : DistanceStrategy::Gather;
  }
  stats.strategy = s;
  return s;
}

void run_blocks(const PrimitiveSet& P, const Pseudonormals* signs, const GridSpec& g,
                const DistanceOptions& o, int kz, DistanceStats& stats,
                const std::function<void(std::size_t)>& prepare,
                const std::function<void(std::size_t, const BlockOut&)>& sink) {
  const DistanceStrategy s = choose_strategy(P, g, o, kz, kGatherRatio, stats);
  Engine engine(P, g, o, signs, kz);
  report_progress(o.progress, 0.0, "distance");
  std::vector<Pair> pairs;
  std::vector<Task> tasks;
  std::unique_ptr<PrimitiveLocator> bvh;
  if (s == DistanceStrategy::Scatter) {
    tasks = engine.scatter_tasks(pairs);
  } else {
    bvh = std::make_unique<PrimitiveLocator>(P);
    tasks = engine.gather_tasks(*bvh);
  }
  report_progress(o.progress, 0.05, "distance");
  prepare(tasks.size());
  std::vector<std::size_t> evals(tasks.size(), 0), active(tasks.size(), 0);
  const std::size_t chunks = std::min<std::size_t>(64, std::max<std::size_t>(1, tasks.size() / 64));
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t b = tasks.size() * c / chunks, e = tasks.size() * (c + 1) / chunks;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(b, e, 1), [&](const tbb::blocked_range<std::size_t>& r) {
          std::unique_ptr<BlockOut> out(new BlockOut);  // default-init: no zeroing of the scratch
          for (std::size_t t = r.begin(); t != r.end(); ++t) {
            if (s == DistanceStrategy::Scatter) {
              engine.scatter_block(tasks[t], pairs, *out);
            } else {
              engine.gather_block(tasks[t], *bvh, *out);
            }
            evals[t] = out->evals;
            active[t] = out->n_active;
            sink(t, *out);
          }
        });
    report_progress(o.progress,
                    0.05 + 0.9 * static_cast<double>(c + 1) / static_cast<double>(chunks),
                    "distance");
  }
  stats.blocks = tasks.size();
  stats.evaluations = 0;
  stats.active_voxels = 0;
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    stats.evaluations += evals[t];
    stats.active_voxels += active[t];
  }
}

}  // namespace isoforge::model_detail
