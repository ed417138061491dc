// Exact Euclidean distance fields of points, segments and triangles, dense and in OpenVDB narrow
// bands (model/distance.hpp).
//
// Methods implemented:
// - D. Eberly, "Distance Between Point and Triangle in 3D" (Geometric Tools): the exact kernel
//   (closest_point.hpp), shared by every path so that their values agree bit for bit.
// - Banded scan conversion of primitives: the per-cell loop of vtkImplicitModeller (Schroeder,
//   Martin & Lorensen, *The Visualization Toolkit*, "Implicit Modelling"), with every row of a
//   primitive's box cut to the sphere / cylinder / slab that can lie within reach — a superset of
//   the characteristic regions of S. Mauch, "A fast algorithm for computing the closest point and
//   distance transform" (Caltech, 2000).
// - Branch-and-bound nearest-primitive queries in a 4-wide bounding volume hierarchy (median
//   splits; boxes and slab-discs as child bounds, evaluated in float SIMD lanes with a
//   conservative tolerance), seeded with the previous sample's nearest primitive.
// - J. A. Bærentzen, H. Aanæs, "Signed distance computation using the angle weighted
//   pseudonormal", IEEE TVCG 11(3), 2005: the sign at the closest feature.
// - K. Museth, "VDB: High-resolution sparse volumes with dynamic topology", ACM TOG 32(3), 2013:
//   the sparse tree, and OpenVDB's signedFloodFill for signs beyond the band.
//
// Work unit: blocks of 8 x 8 x kz samples (kz = 8: aligned like OpenVDB leaves; 64 for dense
// output). Scatter bins (block, primitive) pairs, sorts them, and processes each block's
// primitives nearest first, cutting later ones' rows to where they can still win; Gather finds
// blocks within reach by a two-level box test and queries the BVH per sample. Either way one task
// owns a block, so no writes are shared, and ties go to the smallest primitive id whatever the
// order: results do not depend on the thread count, the strategy or the block shape.

#include "isoforge/model/distance.hpp"

#include <openvdb/tools/MeshToVolume.h>
#if defined(__SSE__)
#include <immintrin.h>
#endif
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "core/simd_clones.hpp"
#include "distance_internal.hpp"
#include "isoforge/core/memory.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/io/vdb.hpp"
#include "isoforge/model/closest_point.hpp"

namespace isoforge {

namespace {

using u32 = std::uint32_t;
using u64 = std::uint64_t;
constexpr u32 kNone = std::numeric_limits<u32>::max();

// ---------------------------------------------------------------------------------------------
// Row kernels of the Scatter strategy: plain loops the compiler vectorizes, cloned for AVX-512
// and AVX2 (core/simd_clones.hpp); every clone computes the same bits as the scalar kernels in
// closest_point.hpp.
// ---------------------------------------------------------------------------------------------

// A segment a + t u, t in [0, 1]; inv = 1 / |u|².
struct SegmentRow {
  double ax, ay, az, ux, uy, uz, inv;
};

// Squared distances from (x, y, z[m]) to c: exactly norm2(p - c).
ISOFORGE_SIMD_CLONES
void point_row(const Vec3& c, double x, double y, const double* __restrict z, int n, double* __restrict out) {
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
bool keep_min_row(const double* __restrict v, int n, double* __restrict d2, u32* __restrict who, u32 id) {
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
    const double dx = x - (s.ax + s.ux * t), dy = y - (s.ay + s.uy * t), dz = z[m] - (s.az + s.uz * t);
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
// Auto picks Gather when the primitives' reach volumes add up to more than this many times the
// volume they cover together (measured: one Gather sample costs about as much as 20 Scatter
// kernel calls, counting the rows' setup).
constexpr double kGatherRatio = 20;
// The same for points and segments on the dense path, whose row kernels cost less per call
// (bench_model's crossover: a helix of 1k .. 1M segments at 128³, the rows win up to a ratio of
// about 600).
constexpr double kRowGatherRatio = 500;

std::string fmt_double(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// ---------------------------------------------------------------------------------------------
// Primitives
// ---------------------------------------------------------------------------------------------

// Ids: [0, seg_begin) points, [seg_begin, tri_begin) segments, [tri_begin, count) triangles.
struct Primitives {
  std::vector<Vec3> pts;
  std::vector<u32> point_ids;
  std::vector<double> radius;  // per point primitive; empty without radii
  std::vector<std::array<u32, 2>> segs;
  std::vector<std::array<u32, 3>> tris;
  u32 seg_begin = 0, tri_begin = 0, count = 0;

  [[nodiscard]] bool has_radius() const { return !radius.empty(); }
  [[nodiscard]] double extra(u32 id) const {
    return id < seg_begin && has_radius() ? radius[id] : 0.0;
  }
  [[nodiscard]] ISOFORGE_KERNEL double dist2(u32 id, const Vec3& x) const {
    if (id >= tri_begin) {
      const auto& t = tris[id - tri_begin];
      return triangle_distance2(x, pts[t[0]], pts[t[1]], pts[t[2]]);
    }
    if (id >= seg_begin) {
      const auto& s = segs[id - seg_begin];
      return segment_distance2(x, pts[s[0]], pts[s[1]]);
    }
    return norm2(x - pts[point_ids[id]]);
  }
  [[nodiscard]] Bounds bounds(u32 id) const {
    Bounds b;
    if (id >= tri_begin) {
      for (u32 v : tris[id - tri_begin]) b.extend(pts[v]);
    } else if (id >= seg_begin) {
      for (u32 v : segs[id - seg_begin]) b.extend(pts[v]);
    } else {
      b.extend(pts[point_ids[id]]);
    }
    return b;
  }
};

Primitives build_primitives(const PolyData& in, const DistanceOptions& o) {
  in.validate();
  if (in.num_cells() == 0 || in.points.empty()) {
    throw Error("distance: the input is empty (no vertices, lines or polygons to measure from)");
  }
  const std::size_t bad = in.points.first_non_finite();
  if (bad < in.points.size()) {
    throw Error("distance: point " + std::to_string(bad) + " is not finite");
  }
  if (in.points.size() >= kNone) throw Error("distance: more than 2^32 - 1 points");
  Primitives p;
  p.pts.resize(in.points.size());
  for (std::size_t i = 0; i < in.points.size(); ++i) p.pts[i] = in.points[i];
  for (std::size_t c = 0; c < in.verts.size(); ++c) {
    for (Index id : in.verts.cell(c)) p.point_ids.push_back(static_cast<u32>(id));
  }
  if (!o.radius_array.empty()) {
    const DataArray* a = in.point_data.find(o.radius_array);
    if (!a) throw Error("distance: radius array '" + o.radius_array + "' is not in the point data");
    if (a->components() != 1) {
      throw Error("distance: radius array '" + o.radius_array + "' has " +
                  std::to_string(a->components()) + " components, needs 1");
    }
    p.radius.resize(p.point_ids.size());
    for (std::size_t i = 0; i < p.point_ids.size(); ++i) {
      const double r = a->get(p.point_ids[i]);
      if (!(r >= 0) || !std::isfinite(r)) {
        throw Error("distance: radius of point " + std::to_string(p.point_ids[i]) + " is " +
                    fmt_double(r) + ", must be finite and >= 0");
      }
      p.radius[i] = r;
    }
  }
  for (std::size_t c = 0; c < in.lines.size(); ++c) {
    const auto ids = in.lines.cell(c);
    for (std::size_t k = 0; k + 1 < ids.size(); ++k) {
      p.segs.push_back({static_cast<u32>(ids[k]), static_cast<u32>(ids[k + 1])});
    }
  }
  for (const auto& t : triangulate_faces(in)) {
    p.tris.push_back({static_cast<u32>(t[0]), static_cast<u32>(t[1]), static_cast<u32>(t[2])});
  }
  const std::size_t total = p.point_ids.size() + p.segs.size() + p.tris.size();
  if (total >= kNone) throw Error("distance: more than 2^32 - 1 primitives");
  if (total == 0) throw Error("distance: the input is empty (its cells have no primitives)");
  p.seg_begin = static_cast<u32>(p.point_ids.size());
  p.tri_begin = static_cast<u32>(p.seg_begin + p.segs.size());
  p.count = static_cast<u32>(total);
  return p;
}

// ---------------------------------------------------------------------------------------------
// Signs: angle-weighted pseudonormals of a closed triangle mesh
// ---------------------------------------------------------------------------------------------

struct Pseudonormals {
  std::vector<Vec3> face, vertex, edge;
  std::vector<std::array<u32, 3>> tri_edges;  // edges 01, 12, 20 of each triangle

  [[nodiscard]] double sign(const Primitives& P, u32 id, const Vec3& x) const {
    const u32 t = id - P.tri_begin;
    const auto& v = P.tris[t];
    const TriangleClosest c = closest_on_triangle(x, P.pts[v[0]], P.pts[v[1]], P.pts[v[2]]);
    const Vec3* n = nullptr;
    switch (c.feature) {
      case TriangleFeature::Face:
        n = &face[t];
        break;
      case TriangleFeature::Edge01:
        n = &edge[tri_edges[t][0]];
        break;
      case TriangleFeature::Edge12:
        n = &edge[tri_edges[t][1]];
        break;
      case TriangleFeature::Edge20:
        n = &edge[tri_edges[t][2]];
        break;
      case TriangleFeature::Vertex0:
        n = &vertex[v[0]];
        break;
      case TriangleFeature::Vertex1:
        n = &vertex[v[1]];
        break;
      case TriangleFeature::Vertex2:
        n = &vertex[v[2]];
        break;
    }
    return dot(x - c.point, *n) < 0 ? -1.0 : 1.0;
  }
};

Pseudonormals build_pseudonormals(const PolyData& in, const Primitives& P, bool require_closed) {
  if (!P.point_ids.empty() || !P.segs.empty()) {
    throw Error("distance: signed distance needs a closed triangle mesh, but the input has " +
                std::to_string(in.verts.size()) + " vertex and " + std::to_string(in.lines.size()) +
                " line cells");
  }
  const SurfaceTopology topo = analyze_topology(in);
  if (require_closed) {
    if (!topo.manifold()) {
      throw Error("distance: signed distance needs a manifold mesh, but it has " +
                  std::to_string(topo.non_manifold_edges) + " non-manifold edges and " +
                  std::to_string(topo.non_manifold_vertices) + " non-manifold vertices");
    }
    if (!topo.oriented()) {
      throw Error("distance: signed distance needs a consistently oriented mesh, but " +
                  std::to_string(topo.inconsistent_edges) +
                  " edges are traversed the same way by both their faces (inconsistent "
                  "orientation)");
    }
    if (!topo.closed()) {
      throw Error("distance: signed distance needs a closed mesh, but it is open (" +
                  std::to_string(topo.border_edges) + " border edges)");
    }
  }
  const std::size_t nt = P.tris.size();
  Pseudonormals pn;
  pn.face.resize(nt);
  // Orientation per component: flip components that enclose a negative volume.
  std::vector<double> volume(topo.components.size(), 0.0);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = P.tris[t];
    const Vec3 a = P.pts[v[0]], b = P.pts[v[1]], c = P.pts[v[2]];
    volume[topo.face_component[t]] += dot(a, cross(b, c));
    const Vec3 n = cross(b - a, c - a);
    const double len = norm(n);
    pn.face[t] = len > 0 ? n / len : Vec3{};
  }
  for (std::size_t t = 0; t < nt; ++t) {
    const std::size_t comp = topo.face_component[t];
    if (volume[comp] < 0 && topo.components[comp].closed) pn.face[t] = -pn.face[t];
  }
  pn.vertex.assign(P.pts.size(), Vec3{});
  struct EdgeUse {
    u32 lo, hi;
    u32 slot;  // 3 * triangle + local edge
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = P.tris[t];
    for (int k = 0; k < 3; ++k) {
      const u32 i = v[static_cast<std::size_t>(k)], j = v[static_cast<std::size_t>((k + 1) % 3)],
                l = v[static_cast<std::size_t>((k + 2) % 3)];
      // Angle at vertex i between edges to j and l.
      const Vec3 e1 = P.pts[j] - P.pts[i], e2 = P.pts[l] - P.pts[i];
      const double n1 = norm(e1), n2 = norm(e2);
      if (n1 > 0 && n2 > 0) {
        const double cosang = std::clamp(dot(e1, e2) / (n1 * n2), -1.0, 1.0);
        pn.vertex[i] += pn.face[t] * std::acos(cosang);
      }
      uses.push_back(
          {std::min(i, j), std::max(i, j), static_cast<u32>(3 * t + static_cast<std::size_t>(k))});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return a.lo != b.lo ? a.lo < b.lo : (a.hi != b.hi ? a.hi < b.hi : a.slot < b.slot);
  });
  pn.tri_edges.resize(nt);
  for (std::size_t s = 0; s < uses.size();) {
    std::size_t e = s;
    Vec3 sum{};
    while (e < uses.size() && uses[e].lo == uses[s].lo && uses[e].hi == uses[s].hi) {
      sum += pn.face[uses[e].slot / 3];
      ++e;
    }
    const u32 edge_id = static_cast<u32>(pn.edge.size());
    pn.edge.push_back(sum);
    for (std::size_t k = s; k < e; ++k) pn.tri_edges[uses[k].slot / 3][uses[k].slot % 3] = edge_id;
    s = e;
  }
  return pn;
}

// ---------------------------------------------------------------------------------------------
// Bounding volume hierarchy (Gather)
// ---------------------------------------------------------------------------------------------
//
// A 4-wide tree: each node holds the bounds of its four children in float SIMD lanes (GCC vector
// extensions; SSE on x86), so one step tests four children. Every child — subtree or single
// primitive — is bounded by a box and a *slab-disc*: the points within `thick` of the plane through
// `c` with unit normal `n` and within `rho` of the axis through c along n. For a triangle that is
// its plane and circumscribing disc about the centroid, for a segment (n along it, thick = half
// its length, rho = 0) and a point (thick = rho = 0) it is the primitive itself; subtrees of
// nearly coplanar triangles get one too. Far from a flat patch a box is loose by its thickness,
// while the slab-disc bound grows with the lateral offset, so almost only the primitives under the
// query point survive to the exact kernel. Bounds are evaluated in float and compared with a
// tolerance `tol` (world units) that covers float rounding; pruning is therefore conservative.

using v4f = float __attribute__((vector_size(16)));
using v2d = double __attribute__((vector_size(16)));

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
  std::int32_t child[4];  // >= 0: node index; < 0: primitive id -(child + 1); kEmpty: none
};
constexpr std::int32_t kEmpty = std::numeric_limits<std::int32_t>::min();

// A bound in double before it is stored in a lane.
struct ChildBound {
  Bounds box;
  bool slab = false;
  Vec3 c, n;
  double thick = kInf, rho = kInf;
};

float round_down(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

class Bvh {
 public:
  explicit Bvh(const Primitives& P) : P_(P) {
    const u32 n = P.count;
    if (n >= static_cast<u32>(std::numeric_limits<std::int32_t>::max())) {
      throw Error("distance: too many primitives for the Gather strategy");
    }
    double m = 0;
    Bounds all;
    for (const Vec3& p : P.pts) {
      all.extend(p);
      m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    }
    // Float rounding of coordinates (and of unit normals) is ~6e-8 relative; 1e-6 covers the few
    // operations of a bound with a wide margin.
    tol_ = 1e-6 * (m + all.diagonal()) + std::numeric_limits<double>::min();
    order_.resize(n);
    cent_.resize(n);
    for (u32 i = 0; i < n; ++i) {
      order_[i] = i;
      cent_[i] = P.bounds(i).center();
    }
    partition(0, n);
    cent_ = {};
    nodes_.resize(count_nodes(n));
    build(0, n, 0);
    order_ = {};
  }

  // Whether some primitive's box lies within sqrt(r2) of the box [blo, bhi] (conservative).
  [[nodiscard]] bool any_within(const Vec3& blo, const Vec3& bhi, double r2) const {
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

  // Nearest primitive to p among those with squared distance below limit2 (lexicographic on
  // (d2, id)): best2/best_id hold a candidate on entry (or +inf/kNone), the result on exit.
  void nearest(const Vec3& p, double limit2, double& best2, u32& best_id,
               std::size_t& evals) const {
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
      // Children within the bound, nearest first: primitives are evaluated at once, subtrees
      // pushed in decreasing order of their bound. Empty lanes have an infinite box bound, which
      // an infinite `bound` (a reach beyond float's range) would not exclude: tested too.
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
        const double d2 = P_.dist2(id, p);
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
  ChildBound leaf_bound(u32 id) const {
    ChildBound b;
    b.box = P_.bounds(id);
    b.slab = true;
    if (id >= P_.tri_begin) {
      const auto& t = P_.tris[id - P_.tri_begin];
      const Vec3 a = P_.pts[t[0]], bb = P_.pts[t[1]], c = P_.pts[t[2]];
      const Vec3 nrm = cross(bb - a, c - a);
      const double len = norm(nrm);
      if (!(len > 0)) {
        b.slab = false;
        return b;
      }
      b.c = (a + bb + c) / 3.0;
      b.n = nrm / len;
    } else if (id >= P_.seg_begin) {
      const auto& sg = P_.segs[id - P_.seg_begin];
      const Vec3 a = P_.pts[sg[0]], bb = P_.pts[sg[1]];
      const double len = norm(bb - a);
      b.c = (a + bb) * 0.5;
      b.n = len > 0 ? (bb - a) / len : Vec3{0, 0, 1};
    } else {
      b.c = P_.pts[P_.point_ids[id]];
      b.n = {0, 0, 1};
    }
    return b;
  }

  // Thickness and radius of the slab-disc (c, n) around the vertices of primitives [begin, end).
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
    for (u32 k = begin; k < end; ++k) {
      const u32 id = order_[k];
      if (id >= P_.tri_begin) {
        for (u32 v : P_.tris[id - P_.tri_begin]) visit(P_.pts[v]);
      } else if (id >= P_.seg_begin) {
        for (u32 v : P_.segs[id - P_.seg_begin]) visit(P_.pts[v]);
      } else {
        visit(P_.pts[P_.point_ids[id]]);
      }
    }
    b.c = c;
    b.n = n;
    b.thick = thick + tol_;
    b.rho = rho + tol_;
  }

  // Slab-disc of a subtree of nearly coplanar triangles (normals summed with consistent sign).
  void subtree_slab(u32 begin, u32 end, ChildBound& b) const {
    Vec3 sum{}, first{};
    double total = 0;
    for (u32 k = begin; k < end; ++k) {
      const u32 id = order_[k];
      if (id < P_.tri_begin) return;
      const auto& t = P_.tris[id - P_.tri_begin];
      Vec3 nrm = cross(P_.pts[t[1]] - P_.pts[t[0]], P_.pts[t[2]] - P_.pts[t[0]]);
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

  // Median splits of [begin, end) along the longest axis of the centroids, recursively: the
  // shape of the tree (build() splits at the same places).
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

  // Nodes of the subtree over m >= 2 primitives (a range of one is a primitive child).
  static std::size_t count_nodes(u32 m) {
    if (m < 2) return m == 1 ? 1 : 0;  // the root of a single primitive is a node
    u32 r[5];
    const int n = quarters(0, m, r);
    std::size_t c = 1;
    for (int k = 0; k < n; ++k) {
      if (r[k + 1] - r[k] >= 2) c += count_nodes(r[k + 1] - r[k]);
    }
    return c;
  }

  // The bound of a child over primitives [begin, end).
  ChildBound child_bound(u32 begin, u32 end) const {
    if (end - begin == 1) {
      ChildBound b = leaf_bound(order_[begin]);
      if (b.slab) fit_slab(begin, end, b);
      return b;
    }
    ChildBound b;
    for (u32 k = begin; k < end; ++k) b.box.merge(P_.bounds(order_[k]));
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

  const Primitives& P_;
  double tol_ = 0;
  std::vector<Node4> nodes_;
  std::vector<u32> order_;  // primitive ids in tree order (during the build)
  std::vector<Vec3> cent_;
};

// ---------------------------------------------------------------------------------------------
// The block engine
// ---------------------------------------------------------------------------------------------

// Blocks are 8 x 8 x kz samples: kz = 8 for OpenVDB leaves, 64 on the dense path (longer rows
// amortize the per-row setup of the scan conversion).
constexpr int kMaxBlockVoxels = 8 * 8 * 64;

struct Task {
  u64 key;
  std::size_t begin, end;  // Scatter: range of pairs
};

struct Pair {
  u64 key;
  u32 prim;
};

// One computed block; the sample (i, j, k) of the block is at offset (i * 8 + j) * kz + k (for
// kz = 8, OpenVDB's leaf offset).
struct BlockOut {
  Index i0, j0, k0;  // first sample
  int ni, nj, nk;    // samples inside the grid
  int kz;            // block depth along z
  double value[kMaxBlockVoxels];
  std::uint8_t active[kMaxBlockVoxels];
  // Scratch of the strategies.
  double d2[kMaxBlockVoxels], rv[kMaxBlockVoxels];
  u32 who[kMaxBlockVoxels];
  double rowmax[64];  // the largest d2 of each of the 8 x 8 rows (an upper bound)
  bool row_dirty = false;
  std::vector<std::pair<double, u32>> order;
  std::size_t n_active = 0;
  std::size_t evals = 0;
};

class Engine {
 public:
  Engine(const Primitives& P, const GridSpec& g, const DistanceOptions& o,
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

  [[nodiscard]] double scatter_estimate() const {
    const double hv = g_.spacing.x * g_.spacing.y * g_.spacing.z;
    constexpr double pi = std::numbers::pi;
    double sum = 0;
    for (u32 id = 0; id < P_.count; ++id) {
      const double R = maxd_ + P_.extra(id);
      double v = 4.0 / 3.0 * pi * R * R * R;
      if (id >= P_.tri_begin) {
        const auto& t = P_.tris[id - P_.tri_begin];
        const Vec3 a = P_.pts[t[0]], b = P_.pts[t[1]], c = P_.pts[t[2]];
        const double area = 0.5 * norm(cross(b - a, c - a));
        const double perim = norm(b - a) + norm(c - b) + norm(a - c);
        v += 2 * area * R + 0.5 * pi * perim * R * R;
      } else if (id >= P_.seg_begin) {
        const auto& s = P_.segs[id - P_.seg_begin];
        v += pi * R * R * norm(P_.pts[s[1]] - P_.pts[s[0]]);
      }
      sum += v;
    }
    return sum / hv;
  }

  // Estimated samples within reach of some primitive: the band of the surfaces, tubes and balls
  // without their overlaps (2 R A per triangle, pi R² L per segment, a ball per point), at most
  // the samples of the grid within the primitives' bounds grown by the reach.
  [[nodiscard]] double union_estimate() const {
    const double hv = g_.spacing.x * g_.spacing.y * g_.spacing.z;
    constexpr double pi = std::numbers::pi;
    double sum = 0;
    for (u32 id = 0; id < P_.count; ++id) {
      const double R = maxd_ + P_.extra(id);
      if (id >= P_.tri_begin) {
        const auto& t = P_.tris[id - P_.tri_begin];
        const Vec3 a = P_.pts[t[0]], b = P_.pts[t[1]], c = P_.pts[t[2]];
        sum += R * norm(cross(b - a, c - a));
      } else if (id >= P_.seg_begin) {
        const auto& sg = P_.segs[id - P_.seg_begin];
        sum += pi * R * R * norm(P_.pts[sg[1]] - P_.pts[sg[0]]);
      } else {
        sum += 4.0 / 3.0 * pi * R * R * R;
      }
    }
    return std::min(sum / hv, reach_box_samples());
  }

  // Samples of the grid within the primitives' bounds grown by the reach.
  [[nodiscard]] double reach_box_samples() const {
    Bounds b;
    double extra = 0;
    for (u32 id = 0; id < P_.count; ++id) extra = std::max(extra, P_.extra(id));
    for (const Vec3& p : P_.pts) b.extend(p);
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
    const u32 n = P_.count;
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
    const bool radii = P_.has_radius();
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
      order.emplace_back(std::sqrt(P_.dist2(id, c)) - P_.extra(id), id);
    }
    out.evals += order.size();
    std::sort(order.begin(), order.end());
    for (const auto& [dc, id] : order) {
      out.evals += rasterize(id, out, d2, radii ? rv : nullptr, who);
    }
    finish(out, d2, radii ? rv : nullptr, who);
  }

  // ---- Gather ----
  std::vector<Task> gather_tasks(const Bvh& bvh) const {
    double extra = 0;
    for (u32 id = 0; id < P_.count; ++id) extra = std::max(extra, P_.extra(id));
    const double R = maxd_ + extra;
    const double r2 = R * R * (1 + kSlack);
    Bounds all;
    for (const Vec3& p : P_.pts) all.extend(p);
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

  void gather_block(const Task& t, const Bvh& bvh, BlockOut& out) const {
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
          double best2 = kInf;
          u32 best = kNone;
          if (seed != kNone) {
            best2 = P_.dist2(seed, p);
            best = seed;
            ++out.evals;
          }
          bvh.nearest(p, limit2, best2, best, out.evals);
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
    const double R = (maxd_ + P_.extra(id)) * (1 + kSlack);
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
    const double R = maxd_ + P_.extra(id);
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
        if (id < P_.seg_begin) {
          for (Index k = lo[2]; k <= hi[2]; ++k) worst = std::max(worst, rv[base + k]);
          return std::min(Rs, std::max(0.0, worst + P_.extra(id)) * (1 + kSlack));
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
      out.row_dirty = batch(coord_[0][static_cast<std::size_t>(i)], coord_[1][static_cast<std::size_t>(j)],
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
    if (id >= P_.tri_begin) {
      const auto& t = P_.tris[id - P_.tri_begin];
      const Vec3 a = P_.pts[t[0]], bb = P_.pts[t[1]], c = P_.pts[t[2]];
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
    } else if (id >= P_.seg_begin) {
      const auto& s = P_.segs[id - P_.seg_begin];
      const Vec3 a = P_.pts[s[0]], bb = P_.pts[s[1]];
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
      const Vec3 c = P_.pts[P_.point_ids[id]];
      const double r = P_.extra(id);
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

  const Primitives& P_;
  const GridSpec& g_;
  double maxd_;
  const Pseudonormals* signs_;
  int kz_;
  std::array<std::vector<double>, 3> coord_;
  Index nb_[3];
  double inv_[3];
};

// ---------------------------------------------------------------------------------------------
// Driver: validation, strategy, blocks in chunks (progress), delivery to a sink
// ---------------------------------------------------------------------------------------------

void check_common(const GridSpec& g, const DistanceOptions& o) {
  (void)checked_point_count(g.dims, "distance grid");
  for (int a = 0; a < 3; ++a) {
    if (g.dims[a] > (Index{1} << 30)) throw Error("distance: dims exceed 2^30 samples per axis");
    if (!(g.spacing[a] > 0) || !std::isfinite(g.spacing[a])) {
      throw Error("distance: spacing along axis " + std::to_string(a) + " is " +
                  fmt_double(g.spacing[a]) + ", must be positive and finite");
    }
  }
  if (!is_finite(g.origin)) throw Error("distance: the grid origin is not finite");
  if (!(o.max_distance > 0) || !std::isfinite(o.max_distance)) {
    throw Error("distance: max_distance must be positive and finite, got " +
                fmt_double(o.max_distance));
  }
}

// The strategy `o` asks for, or (Auto) Gather when Scatter's estimated kernel calls exceed
// `gather_ratio` times the samples within reach; fills the counts of `stats`.
DistanceStrategy choose_strategy(const Engine& engine, const Primitives& P,
                                 const DistanceOptions& o, double gather_ratio,
                                 DistanceStats& stats) {
  stats.points = P.point_ids.size();
  stats.segments = P.segs.size();
  stats.triangles = P.tris.size();
  stats.scatter_estimate = engine.scatter_estimate();
  DistanceStrategy s = o.strategy;
  if (s == DistanceStrategy::Gather && P.has_radius()) {
    throw Error("distance: the Gather strategy does not support radii (use Scatter or Auto)");
  }
  if (s == DistanceStrategy::Auto) {
    s = P.has_radius() || stats.scatter_estimate <= gather_ratio * engine.union_estimate()
            ? DistanceStrategy::Scatter
            : DistanceStrategy::Gather;
  }
  stats.strategy = s;
  return s;
}

// Computes every block and hands it to sink(task index, BlockOut) — in parallel, from TBB
// workers — after calling prepare(number of tasks) once.
template <class Prepare, class Sink>
void run(const GridSpec& g, const DistanceOptions& o, DistanceStats& stats, Prepare&& prepare,
         Sink&& sink, const Primitives& P, const Pseudonormals* signs, int kz) {
  Engine engine(P, g, o, signs, kz);
  const DistanceStrategy s = choose_strategy(engine, P, o, kGatherRatio, stats);
  report_progress(o.progress, 0.0, "distance");
  std::vector<Pair> pairs;
  std::vector<Task> tasks;
  std::unique_ptr<Bvh> bvh;
  if (s == DistanceStrategy::Scatter) {
    tasks = engine.scatter_tasks(pairs);
  } else {
    bvh = std::make_unique<Bvh>(P);
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

// 6-connected flood fill of the samples outside the band (flag 0) with the sign of the band
// samples they touch (+ if none); writes ±far into them.
template <class T>
void dense_flood_fill(const GridSpec& g, std::vector<std::uint8_t>& band, T* v, double far) {
  const Index nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const Index n = nx * ny * nz;
  std::vector<Index> queue;
  for (Index seed = 0; seed < n; ++seed) {
    if (band[static_cast<std::size_t>(seed)] != 0) continue;
    // Collect the region, remembering the first band neighbour's sign.
    queue.clear();
    queue.push_back(seed);
    band[static_cast<std::size_t>(seed)] = 2;
    int sign = 0;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Index id = queue[q];
      const Index i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
      const Index nbr[6] = {i > 0 ? id - 1 : -1,       i + 1 < nx ? id + 1 : -1,
                            j > 0 ? id - nx : -1,      j + 1 < ny ? id + nx : -1,
                            k > 0 ? id - nx * ny : -1, k + 1 < nz ? id + nx * ny : -1};
      for (Index m : nbr) {
        if (m < 0) continue;
        std::uint8_t& f = band[static_cast<std::size_t>(m)];
        if (f == 0) {
          f = 2;
          queue.push_back(m);
        } else if (f == 1 && sign == 0) {
          sign = v[m] < 0 ? -1 : 1;
        }
      }
    }
    const T value = static_cast<T>(sign < 0 ? -far : far);
    for (Index id : queue) v[id] = value;
  }
}

template <class T>
ImageData dense_field(const PolyData& input, const GridSpec& g, const DistanceOptions& o,
                      double far, DistanceStats& stats) {
  const Primitives P = build_primitives(input, o);
  std::unique_ptr<Pseudonormals> signs;
  if (o.signed_distance) {
    signs = std::make_unique<Pseudonormals>(build_pseudonormals(input, P, o.require_closed));
    const double hmax = std::max({g.spacing.x, g.spacing.y, g.spacing.z});
    if (o.max_distance < hmax) {
      throw Error("distance: signed distance needs max_distance (" + fmt_double(o.max_distance) +
                  ") >= the largest spacing (" + fmt_double(hmax) +
                  ") so that the band separates inside from outside");
    }
  }
  ImageData img;
  img.dims = g.dims;
  img.origin = g.origin;
  img.spacing = g.spacing;
  const std::size_t n = img.num_points();
  DataArray arr = DataArray::uninitialized(o.name, ScalarTypeOf<T>::value, 1, n);
  T* v = arr.values<T>().data();
  // The block engine's options: with points and segments only, the strategy is decided here.
  DistanceOptions engine_options = o;
  if (!signs && !P.has_radius() && P.tris.empty()) {
    // Points and segments: Scatter by rows along x (distance_rows.cpp), same values.
    const Engine engine(P, g, o, nullptr, 64);
    engine_options.strategy = choose_strategy(engine, P, o, kRowGatherRatio, stats);
    if (engine_options.strategy == DistanceStrategy::Scatter) {
      std::vector<Vec3> centers(P.point_ids.size());
      for (std::size_t i = 0; i < centers.size(); ++i) centers[i] = P.pts[P.point_ids[i]];
      std::vector<std::array<Vec3, 2>> segments(P.segs.size());
      for (std::size_t i = 0; i < segments.size(); ++i) {
        segments[i] = {P.pts[P.segs[i][0]], P.pts[P.segs[i][1]]};
      }
      report_progress(o.progress, 0.0, "distance");
      const model_detail::RowStats r =
          model_detail::distance_rows(centers, segments, g, o.max_distance, far, v, o.progress);
      stats.blocks = r.planes;
      stats.evaluations = r.evaluations;
      stats.active_voxels = r.active;
      img.point_data.add(std::move(arr), AttributeRole::Scalars);
      return img;
    }
  }
  const T far_t = static_cast<T>(far);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::fill(v + r.begin(), v + r.end(), far_t);
                    });
  std::vector<std::uint8_t> band;
  if (signs) band.assign(n, 0);
  const Index nx = g.dims[0], nxy = g.dims[0] * g.dims[1];
  run(
      g, engine_options, stats, [](std::size_t) {},
      [&](std::size_t, const BlockOut& b) {
        for (int i = 0; i < b.ni; ++i)
          for (int j = 0; j < b.nj; ++j)
            for (int k = 0; k < b.nk; ++k) {
              const int off = (i * 8 + j) * b.kz + k;
              if (!b.active[off]) continue;
              const Index id = (b.i0 + i) + nx * (b.j0 + j) + nxy * (b.k0 + k);
              v[id] = static_cast<T>(b.value[off]);
              if (signs) band[static_cast<std::size_t>(id)] = 1;
            }
      },
      P, signs.get(), 64);
  if (signs) dense_flood_fill(g, band, v, far);
  img.point_data.add(std::move(arr), AttributeRole::Scalars);
  return img;
}

}  // namespace

namespace model_detail {

ImageData distance_image(const PolyData& input, const GridSpec& grid,
                         const DistanceOptions& options, ScalarType type, double far_value,
                         DistanceStats* stats) {
  check_common(grid, options);
  // The values, and with signs a band flag and the flood fill's queue (up to 9 bytes a sample).
  require_volume_memory("distance", grid.dims, scalar_type_name(type),
                        static_cast<double>(scalar_size(type)) + (options.signed_distance ? 9 : 0));
  if (std::isnan(far_value)) throw Error("distance: the far value is NaN");
  DistanceStats local;
  ImageData img;
  if (type == ScalarType::Float32) {
    img = dense_field<float>(input, grid, options, far_value, local);
  } else if (type == ScalarType::Float64) {
    img = dense_field<double>(input, grid, options, far_value, local);
  } else {
    throw Error("distance: output type must be float32 or float64, got " +
                std::string(scalar_type_name(type)));
  }
  if (stats) *stats = local;
  return img;
}

}  // namespace model_detail

ImageData distance_image(const PolyData& input, const GridSpec& grid,
                         const DistanceOptions& options, ScalarType type, DistanceStats* stats) {
  return model_detail::distance_image(input, grid, options, type, options.max_distance, stats);
}

openvdb::FloatGrid::Ptr distance_grid(const PolyData& input, const GridSpec& grid,
                                      const DistanceOptions& options, DistanceStats* stats) {
  ensure_openvdb_initialized();
  check_common(grid, options);
  const double h = grid.spacing.x;
  if (grid.spacing.y != h || grid.spacing.z != h) {
    throw Error("distance: OpenVDB voxels must be cubes (equal spacing on all axes), got " +
                fmt_double(grid.spacing.x) + ", " + fmt_double(grid.spacing.y) + ", " +
                fmt_double(grid.spacing.z));
  }
  const openvdb::math::Transform::Ptr xform = vdb_transform(h, grid.origin, "distance");
  const Primitives P = build_primitives(input, options);
  std::unique_ptr<Pseudonormals> signs;
  if (options.signed_distance) {
    signs = std::make_unique<Pseudonormals>(build_pseudonormals(input, P, options.require_closed));
    if (options.max_distance < h) {
      throw Error("distance: signed distance needs max_distance (" +
                  fmt_double(options.max_distance) + ") >= the voxel size (" + fmt_double(h) +
                  ") so that the band separates inside from outside");
    }
  }
  using Leaf = openvdb::FloatTree::LeafNodeType;
  const float background = static_cast<float>(options.max_distance);
  DistanceStats local;
  std::vector<std::unique_ptr<Leaf>> leaves;  // by task, owned until added to the tree
  run(
      grid, options, local, [&](std::size_t n) { leaves.resize(n); },
      [&](std::size_t t, const BlockOut& b) {
        if (b.n_active == 0) return;
        auto leaf = std::make_unique<Leaf>(
            openvdb::Coord(static_cast<int>(b.i0), static_cast<int>(b.j0), static_cast<int>(b.k0)),
            background, false);
        for (int off = 0; off < 512; ++off) {  // kz = 8: leaf offsets
          const int i = off >> 6, j = (off >> 3) & 7, k = off & 7;
          if (i < b.ni && j < b.nj && k < b.nk && b.active[off]) {
            leaf->setValueOn(static_cast<openvdb::Index>(off), static_cast<float>(b.value[off]));
          }
        }
        leaves[t] = std::move(leaf);
      },
      P, signs.get(), 8);
  auto result = openvdb::FloatGrid::create(background);
  result->setName(options.name);
  result->setTransform(xform);
  result->setGridClass(options.signed_distance ? openvdb::GRID_LEVEL_SET : openvdb::GRID_UNKNOWN);
  auto& tree = result->tree();
  for (auto& leaf : leaves) {
    if (leaf) tree.addLeaf(leaf.release());
  }
  if (options.signed_distance) openvdb::tools::signedFloodFill(tree);
  report_progress(options.progress, 1.0, "distance");
  local.memory_bytes = static_cast<std::size_t>(tree.memUsage());
  if (stats) *stats = local;
  return result;
}

GridSpec cubic_grid(const Bounds& bounds, double voxel_size, double padding) {
  if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max)) {
    throw Error("cubic grid: the box is empty or not finite");
  }
  if (!(voxel_size > 0) || !std::isfinite(voxel_size)) {
    throw Error("cubic grid: voxel size must be positive and finite, got " +
                fmt_double(voxel_size));
  }
  if (!(padding >= 0) || !std::isfinite(padding)) {
    throw Error("cubic grid: padding must be finite and >= 0, got " + fmt_double(padding));
  }
  GridSpec g;
  g.spacing = {voxel_size, voxel_size, voxel_size};
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = bounds.min[a] - padding;
    const double n = std::ceil((bounds.max[a] + padding - g.origin[a]) / voxel_size - 1e-9) + 1;
    if (!(n <= static_cast<double>(Index{1} << 30))) {
      throw Error("cubic grid: more than 2^30 voxels along axis " + std::to_string(a));
    }
    g.dims[a] = std::max<Index>(1, static_cast<Index>(n));
  }
  return g;
}

openvdb::FloatGrid::Ptr openvdb_mesh_to_volume(const PolyData& input, const GridSpec& grid,
                                               double half_width_voxels, bool signed_distance) {
  ensure_openvdb_initialized();
  input.validate();
  const double h = grid.spacing.x;
  if (!(h > 0) || grid.spacing.y != h || grid.spacing.z != h) {
    throw Error("mesh to volume: voxels must be cubes (equal positive spacing)");
  }
  if (!(half_width_voxels >= 1) || !std::isfinite(half_width_voxels)) {
    throw Error("mesh to volume: half width must be >= 1 voxel, got " +
                fmt_double(half_width_voxels));
  }
  const auto tris = triangulate_faces(input);
  if (tris.empty()) throw Error("mesh to volume: the input has no triangles");
  if (input.points.first_non_finite() < input.points.size()) {
    throw Error("mesh to volume: point " + std::to_string(input.points.first_non_finite()) +
                " is not finite");
  }
  auto xform = vdb_transform(h, grid.origin, "mesh to volume");
  std::vector<openvdb::Vec3s> pts(input.points.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec3 p = input.points[i];
    pts[i] = xform->worldToIndex(openvdb::Vec3d(p.x, p.y, p.z));
  }
  std::vector<openvdb::Vec3I> idx(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    idx[t] = openvdb::Vec3I(static_cast<openvdb::Index32>(tris[t][0]),
                            static_cast<openvdb::Index32>(tris[t][1]),
                            static_cast<openvdb::Index32>(tris[t][2]));
  }
  openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> mesh(pts, idx);
  const float hw = static_cast<float>(half_width_voxels);
  auto result = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      mesh, *xform, hw, hw, signed_distance ? 0 : openvdb::tools::UNSIGNED_DISTANCE_FIELD);
  result->setGridClass(signed_distance ? openvdb::GRID_LEVEL_SET : openvdb::GRID_UNKNOWN);
  return result;
}

}  // namespace isoforge
