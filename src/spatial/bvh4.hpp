#pragma once
// Private: the 4-wide bounding volume hierarchy of the spatial module, over any set of items
// (primitives, cells) described by an `Items` policy:
//
//   std::uint32_t size() const;                      number of items, ids 0 .. size() - 1
//   Bounds bounds(std::uint32_t id) const;           the item's box
//   bool slab(std::uint32_t id, Vec3& c, Vec3& n) const;
//                                                    a slab-disc axis for the item alone
//                                                    (center c, unit normal n), or false
//   bool plane_normal(std::uint32_t id, Vec3& n) const;
//                                                    the (unnormalized) normal of a planar item
//                                                    (triangles), or false
//   template <class F> void for_each_vertex(std::uint32_t id, F&& f) const;
//   double dist2(std::uint32_t id, const Vec3& p) const;   (for `nearest` only)
//
// Each node holds the bounds of its four children in float SIMD lanes (GCC vector extensions;
// SSE on x86), so one step tests four children. Every child — subtree or single item — is
// bounded by a box and, where useful, a *slab-disc*: the points within `thick` of the plane
// through `c` with unit normal `n` and within `rho` of the axis through c along n. For a
// triangle that is its plane and circumscribing disc about the centroid, for a segment (n along
// it, thick = half its length, rho = 0) and a point (thick = rho = 0) it is the item itself;
// subtrees of nearly coplanar triangles get one too. Far from a flat patch a box is loose by its
// thickness, while the slab-disc bound grows with the lateral offset, so almost only the items
// under the query point survive to the exact kernel. Bounds are evaluated in float and compared
// with a tolerance `tol` (world units) that covers float rounding; pruning is therefore
// conservative: it never changes which item is nearest, only how many are evaluated.
//
// Built by median splits along the longest axis of the item centres (two levels per node), in
// parallel for large ranges; the tree depends only on the items, never on the thread count.

#if defined(__SSE__)
#include <immintrin.h>
#endif
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "isoforge/core/buffer.hpp"
#include "isoforge/core/error.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge::spatial_detail {

using u32 = std::uint32_t;
constexpr u32 kNone = std::numeric_limits<u32>::max();

using v4f = float __attribute__((vector_size(16)));

inline v4f vmax(v4f a, v4f b) {
  return a > b ? a : b;
}
inline v4f vsqrt(v4f x) {
#if defined(__SSE__)
  return _mm_sqrt_ps(x);
#else
  return v4f{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}
inline v4f splat(float x) {
  return v4f{x, x, x, x};
}

struct alignas(16) Node4 {
  v4f lo[3], hi[3];
  v4f c[3], n[3], thick, rho;
  std::int32_t child[4];  // >= 0: node index; < 0: item id -(child + 1); kEmpty: none
};
constexpr std::int32_t kEmpty = std::numeric_limits<std::int32_t>::min();

inline float round_down(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
inline float round_up(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

/// The tolerance of a tree over points whose coordinates are at most `max_abs` in magnitude and
/// span a box of diagonal `diagonal`: float rounding of coordinates (and of unit normals) is
/// ~6e-8 relative; 1e-6 covers the few operations of a bound with a wide margin.
inline double bvh_tolerance(double max_abs, double diagonal) {
  return 1e-6 * (max_abs + diagonal) + std::numeric_limits<double>::min();
}

template <class Items>
class Bvh4 {
 public:
  /// Builds the tree over `items` (kept by reference) with bound tolerance `tol`.
  Bvh4(const Items& items, double tol) : items_(items), tol_(tol) {
    const u32 n = items.size();
    if (n >= static_cast<u32>(std::numeric_limits<std::int32_t>::max())) {
      throw Error("bounding volume hierarchy: too many items");
    }
    if (n == 0) return;
    order_.resize(n);
    cent_.resize(n);
    for (u32 i = 0; i < n; ++i) {
      order_[i] = i;
      cent_[i] = items.bounds(i).center();
    }
    partition(0, n);
    cent_ = {};
    nodes_.resize(count_nodes(n), Node4{});
    build(0, n, 0);
    order_ = {};
  }

  [[nodiscard]] bool empty() const { return nodes_.empty(); }
  [[nodiscard]] double tolerance() const { return tol_; }

  /// Whether some item's box lies within sqrt(r2) of the box [blo, bhi] (conservative).
  [[nodiscard]] bool any_within(const Vec3& blo, const Vec3& bhi, double r2) const {
    if (nodes_.empty()) return false;
    const double r = std::sqrt(r2) + tol_;
    const v4f bl[3] = {splat(round_down(blo.x)), splat(round_down(blo.y)),
                       splat(round_down(blo.z))};
    const v4f bh[3] = {splat(round_up(bhi.x)), splat(round_up(bhi.y)), splat(round_up(bhi.z))};
    const v4f lim = splat(round_up(r * r * (1 + 1e-6)));
    const v4f zero = splat(0.0f);
    std::int32_t stack[256];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node4& nd = nodes_[static_cast<std::size_t>(stack[--top])];
      v4f d2 = zero;
      for (int a = 0; a < 3; ++a) {
        const v4f d = vmax(vmax(nd.lo[a] - bh[a], bl[a] - nd.hi[a]), zero);
        d2 += d * d;
      }
      for (int k = 0; k < 4; ++k) {
        if (nd.child[k] == kEmpty || !(d2[k] <= lim[k])) continue;
        if (nd.child[k] < 0) return true;
        stack[top++] = nd.child[k];
      }
    }
    return false;
  }

  /// Calls f(id) for every item whose box (grown by the tolerance and `grow`) contains p, in
  /// tree order; stops when f returns true. Returns whether it stopped.
  template <class F>
  bool for_each_containing(const Vec3& p, double grow, F&& f) const {
    if (nodes_.empty()) return false;
    const float g = round_up(grow);
    const v4f px = splat(round_down(p.x)), py = splat(round_down(p.y)), pz = splat(round_down(p.z));
    const v4f qx = splat(round_up(p.x)), qy = splat(round_up(p.y)), qz = splat(round_up(p.z));
    const v4f gg = splat(g);
    std::int32_t stack[256];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node4& nd = nodes_[static_cast<std::size_t>(stack[--top])];
      for (int k = 3; k >= 0; --k) {
        if (nd.child[k] == kEmpty) continue;
        const bool in = nd.lo[0][k] - gg[k] <= qx[k] && px[k] <= nd.hi[0][k] + gg[k] &&
                        nd.lo[1][k] - gg[k] <= qy[k] && py[k] <= nd.hi[1][k] + gg[k] &&
                        nd.lo[2][k] - gg[k] <= qz[k] && pz[k] <= nd.hi[2][k] + gg[k];
        if (!in) continue;
        if (nd.child[k] < 0) {
          if (f(static_cast<u32>(-(nd.child[k] + 1)))) return true;
        } else {
          stack[top++] = nd.child[k];
        }
      }
    }
    return false;
  }

  /// Nearest item to p among those with squared distance below limit2 (lexicographic on
  /// (d2, id), d2 from `items.dist2`): best2/best_id hold a candidate on entry (or +inf/kNone),
  /// the result on exit; `evals` counts the exact distances computed.
  void nearest(const Vec3& p, double limit2, double& best2, u32& best_id,
               std::size_t& evals) const {
    if (nodes_.empty()) return;
    const v4f px = splat(static_cast<float>(p.x)), py = splat(static_cast<float>(p.y)),
              pz = splat(static_cast<float>(p.z));
    const v4f zero = splat(0.0f);
    float bound = 0;
    const auto update_bound = [&] {
      const double b = std::sqrt(std::min(best2, limit2)) + tol_;
      bound = round_up(b * b * (1 + 1e-6));
    };
    update_bound();
    struct Item {
      std::int32_t node;
      float lb2;
    };
    Item stack[256];
    int top = 0;
    stack[top++] = {0, 0.0f};
    while (top > 0) {
      const Item it = stack[--top];
      if (it.lb2 > bound) continue;
      const Node4& nd = nodes_[static_cast<std::size_t>(it.node)];
      // Box bound.
      const v4f dx = vmax(vmax(nd.lo[0] - px, px - nd.hi[0]), zero);
      const v4f dy = vmax(vmax(nd.lo[1] - py, py - nd.hi[1]), zero);
      const v4f dz = vmax(vmax(nd.lo[2] - pz, pz - nd.hi[2]), zero);
      const v4f box = dx * dx + dy * dy + dz * dz;
      // Slab-disc bound.
      const v4f wx = px - nd.c[0], wy = py - nd.c[1], wz = pz - nd.c[2];
      const v4f h = wx * nd.n[0] + wy * nd.n[1] + wz * nd.n[2];
      const v4f dh = vmax(vmax(h, -h) - nd.thick, zero);
      const v4f lx = wy * nd.n[2] - wz * nd.n[1], ly = wz * nd.n[0] - wx * nd.n[2],
                lz = wx * nd.n[1] - wy * nd.n[0];
      const v4f dl = vmax(vsqrt(lx * lx + ly * ly + lz * lz) - nd.rho, zero);
      const v4f lb2 = vmax(box, dh * dh + dl * dl);
      // Children within the bound, nearest first: items are evaluated at once, subtrees pushed
      // in decreasing order of their bound. Empty lanes have an infinite box bound, which an
      // infinite `bound` (a reach beyond float's range) would not exclude: tested too.
      unsigned mask = 0;
      for (int k = 0; k < 4; ++k) {
        mask |= static_cast<unsigned>((lb2[k] <= bound) & (nd.child[k] != kEmpty)) << k;
      }
      if (mask == 0) continue;
      Item kids[4];
      int nk = 0;
      for (; mask; mask &= mask - 1) {
        const int k = __builtin_ctz(mask);
        Item item{nd.child[k], lb2[k]};
        int b = nk++;
        for (; b > 0 && item.lb2 < kids[b - 1].lb2; --b) kids[b] = kids[b - 1];
        kids[b] = item;
      }
      for (int k = 0; k < nk; ++k) {
        if (kids[k].node >= 0 || kids[k].lb2 > bound) continue;
        const u32 id = static_cast<u32>(-(kids[k].node + 1));
        const double d2 = items_.dist2(id, p);
        ++evals;
        if (d2 < best2 || (d2 == best2 && id < best_id)) {
          best2 = d2, best_id = id;
          update_bound();
        }
      }
      for (int k = nk - 1; k >= 0; --k) {
        if (kids[k].node >= 0 && kids[k].lb2 <= bound) stack[top++] = kids[k];
      }
    }
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();

  // A bound in double before it is stored in a lane.
  struct ChildBound {
    Bounds box;
    bool slab = false;
    Vec3 c, n;
    double thick = kInf, rho = kInf;
  };

  ChildBound leaf_bound(u32 id) const {
    ChildBound b;
    b.box = items_.bounds(id);
    b.slab = items_.slab(id, b.c, b.n);
    return b;
  }

  // Thickness and radius of the slab-disc (c, n) around the vertices of items [begin, end).
  void fit_slab(u32 begin, u32 end, ChildBound& b) const {
    // The float lanes hold float(c), float(n): measure the bound around exactly those.
    const Vec3 c{static_cast<float>(b.c.x), static_cast<float>(b.c.y), static_cast<float>(b.c.z)};
    const Vec3 n{static_cast<float>(b.n.x), static_cast<float>(b.n.y), static_cast<float>(b.n.z)};
    double thick = 0, rho = 0;
    const auto visit = [&](const Vec3& v) {
      const Vec3 w = v - c;
      thick = std::max(thick, std::abs(dot(w, n)));
      rho = std::max(rho, norm(cross(w, n)));
    };
    for (u32 k = begin; k < end; ++k) items_.for_each_vertex(order_[k], visit);
    b.c = c;
    b.n = n;
    b.thick = thick + tol_;
    b.rho = rho + tol_;
  }

  // Slab-disc of a subtree of nearly coplanar planar items (normals summed with consistent sign).
  void subtree_slab(u32 begin, u32 end, ChildBound& b) const {
    Vec3 sum{}, first{};
    double total = 0;
    for (u32 k = begin; k < end; ++k) {
      Vec3 nrm;
      if (!items_.plane_normal(order_[k], nrm)) return;
      if (k == begin) first = nrm;
      if (dot(nrm, first) < 0) nrm = -nrm;
      sum += nrm;
      total += norm(nrm);
    }
    const double len = norm(sum);
    // Normals spread over more than ~45 degrees: no useful slab.
    if (!(len > 0.7 * total)) return;
    b.c = b.box.center();
    b.n = sum / len;
    fit_slab(begin, end, b);
    // Keep it only if it is thinner than the box (else it only costs).
    const Vec3 size = b.box.size();
    b.slab = b.thick < 0.5 * std::min({size.x, size.y, size.z}) || b.thick < 0.25 * b.rho;
  }

  // Median splits of [begin, end) along the longest axis of the centres, recursively: the shape
  // of the tree (build() splits at the same places).
  void partition(u32 begin, u32 end) {
    if (end - begin <= 1) return;
    Bounds cb;
    for (u32 k = begin; k < end; ++k) cb.extend(cent_[order_[k]]);
    const Vec3 ext = cb.size();
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const u32 mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](u32 a, u32 c) {
                       const double ca = cent_[a][axis], cc = cent_[c][axis];
                       return ca != cc ? ca < cc : a < c;
                     });
    if (end - begin > 16384) {
      tbb::parallel_invoke([&] { partition(begin, mid); }, [&] { partition(mid, end); });
    } else {
      partition(begin, mid);
      partition(mid, end);
    }
  }

  // The (up to) four child ranges of a node over [begin, end): two levels of median splits.
  static int quarters(u32 begin, u32 end, u32 (&r)[5]) {
    const u32 mid = begin + (end - begin) / 2;
    int n = 0;
    r[n] = begin;
    for (const auto& [b, e] : {std::pair{begin, mid}, std::pair{mid, end}}) {
      if (e - b >= 2) {
        r[++n] = b + (e - b) / 2;
      }
      r[++n] = e;
    }
    return n;
  }

  // Nodes of the subtree over m >= 2 items (a range of one is an item child).
  static std::size_t count_nodes(u32 m) {
    if (m < 2) return m == 1 ? 1 : 0;  // the root of a single item is a node
    u32 r[5];
    const int n = quarters(0, m, r);
    std::size_t c = 1;
    for (int k = 0; k < n; ++k) {
      if (r[k + 1] - r[k] >= 2) c += count_nodes(r[k + 1] - r[k]);
    }
    return c;
  }

  // The bound of a child over items [begin, end).
  ChildBound child_bound(u32 begin, u32 end) const {
    if (end - begin == 1) {
      ChildBound b = leaf_bound(order_[begin]);
      if (b.slab) fit_slab(begin, end, b);
      return b;
    }
    ChildBound b;
    for (u32 k = begin; k < end; ++k) b.box.merge(items_.bounds(order_[k]));
    subtree_slab(begin, end, b);
    return b;
  }

  // Node over [begin, end) at nodes_[index]; child subtrees follow it in order.
  void build(u32 begin, u32 end, std::size_t index) {
    u32 r[5];
    int n = 1;
    r[0] = begin;
    r[1] = end;
    if (end - begin >= 2) n = quarters(begin, end, r);
    Node4& nd = nodes_[index];
    const float inf = std::numeric_limits<float>::infinity();
    std::size_t next = index + 1;
    struct Sub {
      u32 b, e;
      std::size_t at;
    };
    Sub subs[4];
    int nsub = 0;
    for (int k = 0; k < 4; ++k) {
      if (k >= n) {
        for (int a = 0; a < 3; ++a)
          nd.lo[a][k] = inf, nd.hi[a][k] = -inf, nd.c[a][k] = 0, nd.n[a][k] = 0;
        nd.thick[k] = inf, nd.rho[k] = inf;
        nd.child[k] = kEmpty;
        continue;
      }
      const ChildBound b = child_bound(r[k], r[k + 1]);
      for (int a = 0; a < 3; ++a) {
        nd.lo[a][k] = round_down(b.box.min[a] - tol_);
        nd.hi[a][k] = round_up(b.box.max[a] + tol_);
        nd.c[a][k] = b.slab ? static_cast<float>(b.c[a]) : 0.0f;
        nd.n[a][k] = b.slab ? static_cast<float>(b.n[a]) : 0.0f;
      }
      nd.thick[k] = b.slab ? round_up(b.thick) : inf;
      nd.rho[k] = b.slab ? round_up(b.rho) : inf;
      if (r[k + 1] - r[k] == 1) {
        nd.child[k] = -static_cast<std::int32_t>(order_[r[k]]) - 1;
      } else {
        nd.child[k] = static_cast<std::int32_t>(next);
        subs[nsub++] = {r[k], r[k + 1], next};
        next += count_nodes(r[k + 1] - r[k]);
      }
    }
    if (end - begin > 16384) {
      tbb::parallel_for(0, nsub, [&](int k) { build(subs[k].b, subs[k].e, subs[k].at); });
    } else {
      for (int k = 0; k < nsub; ++k) build(subs[k].b, subs[k].e, subs[k].at);
    }
  }

  const Items& items_;
  double tol_ = 0;
  // Buffer: large trees are first touched in huge pages (core/buffer.hpp).
  Buffer<Node4> nodes_;
  Buffer<u32> order_;  // item ids in tree order (during the build)
  Buffer<Vec3> cent_;
};

}  // namespace isoforge::spatial_detail
