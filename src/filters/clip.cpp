// Clipping datasets with implicit functions (filters/clip.hpp).
//
// References:
// - W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit* (4th ed.), 9.4.x
//   "Clipping with scalar fields": clip the simplices of a consistent decomposition.
// - J. Dompierre, P. Labbé, M.-G. Vallet, R. Camarero, "How to subdivide pyramids, prisms and
//   hexahedra into tetrahedra", IMR 1999: quad faces split along the diagonal from their
//   smallest vertex id, so the two cells sharing a face split it alike; the cells whose faces
//   cannot all be honoured (hexahedra, prisms) get a centre point.
// Method: docs/algorithms/cut.md ("Clipping").

#include "isoforge/filters/clip.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "cut_internal.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {

/// A point of a piece: (p, p) an input point p (< N) or the centre point N + cell of a split
/// cell; (lo, hi), lo < hi, the cut point on that edge.
struct Ref {
  std::uint64_t a = 0, b = 0;
  friend bool operator<(const Ref& x, const Ref& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); }
  friend bool operator==(const Ref& x, const Ref& y) = default;
};

struct Centre {
  std::uint64_t id = 0;  // N + cell
  Vec3 position{};
  double value = 0;      // F − c at the centre
};

/// What input cells produced: `pieces` whole cells from `cell` on (`whole`), or `pieces` pieces
/// of cell `cell`.
struct Entry {
  Index cell = 0;
  bool whole = false;
  std::uint32_t pieces = 0;
};

struct ClipBlock {
  std::vector<Entry> entries;
  std::vector<CellType> types;        // per piece
  std::vector<std::uint8_t> sizes;    // per piece
  std::vector<Ref> refs;              // piece points
  std::vector<Centre> centres;
  std::size_t kept = 0, split = 0;
};

constexpr std::size_t kClipBlockCells = 4096;
constexpr int kCentre = 15;  // local id of a cell's centre point

/// Splits a quad (q0..q3, in ring order, global ids g) into two triangles of the same
/// orientation along the diagonal from its smallest point id.
void split_quad(const int q[4], std::span<const Index> g, std::vector<std::array<int, 4>>& out,
                int apex) {
  int m = 0;
  for (int i = 1; i < 4; ++i) {
    if (g[static_cast<std::size_t>(q[i])] < g[static_cast<std::size_t>(q[m])]) m = i;
  }
  const int a = q[m], b = q[(m + 1) % 4], c = q[(m + 2) % 4], d = q[(m + 3) % 4];
  out.push_back({a, b, c, apex});
  out.push_back({a, c, d, apex});
}

/// A hexahedron or voxel whose every face's smallest-id diagonal passes through its corner 0 or
/// the opposite corner (always so in image data and structured grids, whose ids grow with i, j
/// and k) splits into the 6 tetrahedra around that main diagonal, honouring every face's split
/// without a centre point. Returns false (nothing added) otherwise.
bool six_tetrahedra(CellType type, std::span<const Index> g, std::vector<std::array<int, 4>>& out) {
  // Local ids by corner bits (i, j, k): voxel order, or the hexahedron's.
  static constexpr int kVoxel[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  static constexpr int kHex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  const int* at = type == CellType::Voxel ? kVoxel : kHex;
  const int lo = at[0], hi = at[7];
  for (const CellFace& f : cell_faces(type)) {
    int m = 0;
    for (int i = 1; i < 4; ++i) {
      if (g[static_cast<std::size_t>(f.ids[static_cast<std::size_t>(i)])] <
          g[static_cast<std::size_t>(f.ids[static_cast<std::size_t>(m)])]) {
        m = i;
      }
    }
    const int a = f.ids[static_cast<std::size_t>(m)], b = f.ids[static_cast<std::size_t>((m + 2) % 4)];
    if (a != lo && a != hi && b != lo && b != hi) return false;
  }
  // Corner 0 -> one axis -> two axes -> corner 7, for the 6 orders of the axes; (0, a, b, 7) is
  // positive when the axes (p, q, r) are an even permutation, else (0, b, a, 7).
  static constexpr int kOrders[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  for (int o = 0; o < 6; ++o) {
    const int p = kOrders[o][0], q = kOrders[o][1];
    const int a = at[1 << p], b = at[(1 << p) | (1 << q)];
    if (o < 3) out.push_back({lo, a, b, hi});
    else out.push_back({lo, b, a, hi});
  }
  return true;
}

/// Whether the quad face `f` of a cell has its four points kept (`kept`: per local id).
bool quad_kept(const CellFace& f, const std::uint8_t* kept) {
  return f.size == 4 && kept[f.ids[0]] && kept[f.ids[1]] && kept[f.ids[2]] && kept[f.ids[3]];
}

/// The simplices of a cell, by local ids (kCentre = the centre): tetrahedra for 3D cells
/// (positively oriented), triangles (the cell's orientation), lines, vertices. `dim` is set to
/// the simplices' dimension. A cut 3D cell's quad face whose four points are kept (`kept`: per
/// local id) is not split: it is the base of a pyramid in `pyramids` (the face outward, then the
/// apex: the centre, or a pyramid cell's own apex), so that it stays one quad, as in the cell
/// kept whole across it.
void decompose(CellType type, std::span<const Index> g, const std::uint8_t* kept,
               std::vector<std::array<int, 4>>& out, std::vector<std::array<int, 5>>& pyramids,
               int& dim) {
  out.clear();
  pyramids.clear();
  const auto n = static_cast<int>(g.size());
  dim = cell_dimension(type);
  switch (type) {
    case CellType::Tetra: out.push_back({0, 1, 2, 3}); return;
    case CellType::Hexahedron:
    case CellType::Voxel: {
      // Split around the centre when a face is wholly on one side: its pyramid is then one
      // piece on the kept side (above) and nothing on the other. Decided alike for both sides,
      // so a clip and its complement cut the cell along the same surface.
      bool one_sided_quad = false;
      for (const CellFace& f : cell_faces(type)) {
        int k = 0;
        for (int i = 0; i < 4; ++i) k += kept[f.ids[static_cast<std::size_t>(i)]];
        one_sided_quad |= k == 0 || k == 4;
      }
      if (!one_sided_quad && six_tetrahedra(type, g, out)) return;
      [[fallthrough]];
    }
    case CellType::Pyramid:
    case CellType::Wedge: {
      const int apex = type == CellType::Pyramid ? 4 : kCentre;
      static thread_local std::vector<std::array<int, 4>> tris;
      tris.clear();
      for (const CellFace& f : cell_faces(type)) {
        if (type == CellType::Pyramid && f.size == 3) continue;  // the apex's faces
        if (f.size == 3) tris.push_back({f.ids[0], f.ids[1], f.ids[2], 0});
        else if (quad_kept(f, kept))
          pyramids.push_back({f.ids[0], f.ids[1], f.ids[2], f.ids[3], apex});
        else {
          const int q[4] = {f.ids[0], f.ids[1], f.ids[2], f.ids[3]};
          split_quad(q, g, tris, 0);
        }
      }
      // Outward face triangle (a, b, c) and an interior point m: (a, c, b, m) is positive.
      for (const auto& t : tris) out.push_back({t[0], t[2], t[1], apex});
      return;
    }
    case CellType::Triangle: out.push_back({0, 1, 2, 0}); return;
    case CellType::Quad:
    case CellType::Pixel: {
      const int q[4] = {0, 1, type == CellType::Pixel ? 3 : 2, type == CellType::Pixel ? 2 : 3};
      split_quad(q, g, out, 0);
      return;
    }
    case CellType::Polygon:
      for (int i = 1; i + 1 < n; ++i) out.push_back({0, i, i + 1, 0});
      return;
    case CellType::TriangleStrip:
      for (int i = 0; i + 2 < n; ++i) {
        if (i % 2 == 0) out.push_back({i, i + 1, i + 2, 0});
        else out.push_back({i + 1, i, i + 2, 0});
      }
      return;
    case CellType::Line:
    case CellType::PolyLine:
      for (int i = 0; i + 1 < n; ++i) out.push_back({i, i + 1, 0, 0});
      return;
    case CellType::Vertex:
    case CellType::PolyVertex:
      for (int i = 0; i < n; ++i) out.push_back({i, 0, 0, 0});
      return;
    default: return;
  }
}

// Faces of a positive tetrahedron (t0..t3) with their normal away from the vertex opposite:
// kAway[v] is the face opposite v (outward).
constexpr int kAway[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

bool distinct(const Ref* r, int n) {
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (r[i] == r[j]) return false;
  return true;
}

struct Clipper {
  DatasetRef input;
  const ImplicitFunction& f;
  const Buffer<double>& F;
  double c;
  bool keep_above;
  std::uint64_t np;
  std::atomic<char>* used;  // per input point

  void mark(std::uint64_t p) const {
    if (p < np) used[p].store(1, std::memory_order_relaxed);
  }

  void process(Index cell, CellType type, std::span<const Index> ids, ClipBlock& blk,
               std::vector<std::array<int, 4>>& simplices, std::vector<double>& val_,
               std::vector<std::uint64_t>& gid_) const {
    const std::size_t n = ids.size();
    bool any_kept = false, any_dropped = false;
    for (Index id : ids) {
      const double v = F[static_cast<std::size_t>(id)];
      ((v >= c) == keep_above ? any_kept : any_dropped) = true;
    }
    if (!any_kept) return;
    if (!any_dropped) {
      if (!blk.entries.empty() && blk.entries.back().whole &&
          blk.entries.back().cell + blk.entries.back().pieces == cell) {
        ++blk.entries.back().pieces;  // a run of whole cells
      } else {
        blk.entries.push_back({cell, true, 1});
      }
      ++blk.kept;
      for (Index id : ids) mark(static_cast<std::uint64_t>(id));
      return;
    }
    ++blk.split;
    int dim = 0;
    std::uint8_t kept_local[16] = {};
    if (n <= 8) {
      for (std::size_t i = 0; i < n; ++i) {
        kept_local[i] = (F[static_cast<std::size_t>(ids[i])] - c >= 0) == keep_above ? 1 : 0;
      }
    }
    static thread_local std::vector<std::array<int, 5>> pyramids;
    decompose(type, ids, kept_local, simplices, pyramids, dim);
    // Values (F − c) and refs of the local points, the centre last.
    // (3D cells have at most 8 points, so the centre's slot is free; long polylines, polygons
    // and strips have no centre.)
    val_.resize(std::max<std::size_t>(n, 16));
    gid_.resize(val_.size());
    double* val = val_.data();
    std::uint64_t* gid = gid_.data();
    for (std::size_t i = 0; i < n; ++i) {
      gid[i] = static_cast<std::uint64_t>(ids[i]);
      val[i] = F[static_cast<std::size_t>(ids[i])] - c;
    }
    bool has_centre = false;
    for (const auto& s : simplices) has_centre |= s[3] == kCentre;
    for (const auto& q : pyramids) has_centre |= q[4] == kCentre;
    if (has_centre) {
      Vec3 m{};
      for (Index id : ids) m += point(input, id);
      m = m / static_cast<double>(n);
      Centre ce{np + static_cast<std::uint64_t>(cell), m, f.value(m) - c};
      gid[kCentre] = ce.id;
      val[kCentre] = ce.value;
      blk.centres.push_back(ce);
    }
    auto kept = [&](int l) { return (val[l] >= 0) == keep_above; };
    auto at = [&](int l) { return Ref{gid[l], gid[l]}; };
    auto edge = [&](int u, int w) {  // the cut point of the edge (u kept or not, w the other)
      const int up = val[u] >= 0 ? u : w;  // the end above
      if (val[up] == 0) return at(up);
      return Ref{std::min(gid[u], gid[w]), std::max(gid[u], gid[w])};
    };
    const std::size_t before = blk.types.size();
    auto emit = [&](CellType t, std::initializer_list<Ref> r) {
      const Ref* p = r.begin();
      const int k = static_cast<int>(r.size());
      if (distinct(p, k)) {
        blk.types.push_back(t);
        blk.sizes.push_back(static_cast<std::uint8_t>(k));
        blk.refs.insert(blk.refs.end(), r.begin(), r.end());
        return;
      }
      if (t == CellType::Wedge) {  // degenerate: its three tetrahedra, the flat ones dropped
        const Ref w[6] = {p[0], p[1], p[2], p[3], p[4], p[5]};
        const Ref tets[3][4] = {{w[0], w[2], w[1], w[3]}, {w[1], w[3], w[2], w[4]},
                                {w[2], w[4], w[3], w[5]}};
        for (const auto& tt : tets) {
          if (!distinct(tt, 4)) continue;
          blk.types.push_back(CellType::Tetra);
          blk.sizes.push_back(4);
          blk.refs.insert(blk.refs.end(), tt, tt + 4);
        }
      } else if (t == CellType::Quad) {
        Ref tri[4];
        int m = 0;
        for (int i = 0; i < 4; ++i) {
          bool dup = false;
          for (int j = 0; j < m; ++j) dup |= tri[j] == p[i];
          if (!dup) tri[m++] = p[i];
        }
        if (m == 3) {
          blk.types.push_back(CellType::Triangle);
          blk.sizes.push_back(3);
          blk.refs.insert(blk.refs.end(), tri, tri + 3);
        }
      }
    };
    // A tetrahedron: itself, a smaller one, or a wedge.
    auto clip_tetra = [&](const std::array<int, 4>& s) {
      int nk = 0;
      for (int i = 0; i < 4; ++i) nk += kept(s[i]);
      if (nk == 0) return;
      if (nk == 4) {
        emit(CellType::Tetra, {at(s[0]), at(s[1]), at(s[2]), at(s[3])});
      } else if (nk == 1) {
        int v = 0;
        while (!kept(s[v])) ++v;
        Ref r[4];
        for (int i = 0; i < 4; ++i) r[i] = i == v ? at(s[i]) : edge(s[v], s[i]);
        emit(CellType::Tetra, {r[0], r[1], r[2], r[3]});
      } else if (nk == 3) {
        int d = 0;
        while (kept(s[d])) ++d;
        const int* b = kAway[d];
        const int p = s[b[0]], q = s[b[1]], r = s[b[2]], x = s[d];
        emit(CellType::Wedge, {at(p), at(q), at(r), edge(p, x), edge(q, x), edge(r, x)});
      } else {  // two kept (a, b), two dropped
        int a = -1, b = -1;
        for (int i = 0; i < 4; ++i) {
          if (kept(s[i])) (a < 0 ? a : b) = i;
        }
        // The face opposite b, outward (away from b), rotated to start at a.
        const int* face = kAway[b];
        int r = 0;
        while (face[r] != a) ++r;
        const int x = s[face[(r + 1) % 3]], y = s[face[(r + 2) % 3]];
        const int la = s[a], lb = s[b];
        emit(CellType::Wedge, {at(la), edge(la, x), edge(la, y), at(lb), edge(lb, x), edge(lb, y)});
      }
    };
    // A pyramid on a kept quad (outward q0..q3, apex q4): whole, or the hexahedron between the
    // quad and its four cut points (whose order follows the quad's, so the smallest-id diagonal
    // of its top is the one the other side's pieces have); with a point exactly on F = c (a flat
    // or folded piece) its two tetrahedra instead.
    for (const auto& q : pyramids) {
      const Ref base[4] = {at(q[0]), at(q[3]), at(q[2]), at(q[1])};  // normal toward the apex
      if (kept(q[4])) {
        const Ref r[5] = {base[0], base[1], base[2], base[3], at(q[4])};
        if (distinct(r, 5)) {
          emit(CellType::Pyramid, {r[0], r[1], r[2], r[3], r[4]});
          continue;
        }
      } else {
        const int order[4] = {q[0], q[3], q[2], q[1]};
        Ref r[8] = {base[0], base[1], base[2], base[3]};
        for (int i = 0; i < 4; ++i) r[4 + i] = edge(order[i], q[4]);
        if (distinct(r, 8)) {
          emit(CellType::Hexahedron, {r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7]});
          continue;
        }
      }
      std::vector<std::array<int, 4>> halves;
      const int ring[4] = {q[0], q[1], q[2], q[3]};
      split_quad(ring, ids, halves, 0);
      for (const auto& t : halves) clip_tetra({t[0], t[2], t[1], q[4]});
    }
    for (const auto& s : simplices) {
      if (dim == 3) {
        clip_tetra(s);
      } else if (dim == 2) {
        const int t[3] = {s[0], s[1], s[2]};
        int nk = 0;
        for (int i = 0; i < 3; ++i) nk += kept(t[i]);
        if (nk == 0) continue;
        if (nk == 3) {
          emit(CellType::Triangle, {at(t[0]), at(t[1]), at(t[2])});
        } else if (nk == 1) {
          int v = 0;
          while (!kept(t[v])) ++v;
          Ref r[3];
          for (int i = 0; i < 3; ++i) r[i] = i == v ? at(t[i]) : edge(t[v], t[i]);
          emit(CellType::Triangle, {r[0], r[1], r[2]});
        } else {
          int d = 0;
          while (kept(t[d])) ++d;
          const int a = t[(d + 1) % 3], b = t[(d + 2) % 3], x = t[d];
          emit(CellType::Quad, {at(a), at(b), edge(b, x), edge(a, x)});
        }
      } else if (dim == 1) {
        const int u = s[0], w = s[1];
        if (!kept(u) && !kept(w)) continue;
        if (kept(u) && kept(w)) emit(CellType::Line, {at(u), at(w)});
        else if (kept(u)) emit(CellType::Line, {at(u), edge(u, w)});
        else emit(CellType::Line, {edge(w, u), at(w)});
      } else {
        if (kept(s[0])) emit(CellType::Vertex, {at(s[0])});
      }
    }
    const auto pieces = static_cast<std::uint32_t>(blk.types.size() - before);
    if (pieces > 0) blk.entries.push_back({cell, false, pieces});
  }
};

/// 3D image data or structured grid: dimensions and cell type.
struct Structured3D {
  bool valid = false;
  bool image = false;
  Index nx = 0, ny = 0, nz = 0;
  [[nodiscard]] Index cx() const { return nx - 1; }
  [[nodiscard]] Index cy() const { return ny - 1; }
  /// The point ids of cell `cell` in the order of visit_cells (voxel or hexahedron).
  void ids(Index cell, Index* out) const {
    const Index i = cell % cx(), j = (cell / cx()) % cy(), k = cell / (cx() * cy());
    const Index p = i + nx * (j + ny * k), dy = nx, dz = nx * ny;
    if (image) {
      out[0] = p, out[1] = p + 1, out[2] = p + dy, out[3] = p + dy + 1;
    } else {
      out[0] = p, out[1] = p + 1, out[2] = p + dy + 1, out[3] = p + dy;
    }
    for (int q = 0; q < 4; ++q) out[q + 4] = out[q] + dz;
  }
};

Structured3D structured_3d(DatasetRef ds) {
  Structured3D s;
  const Dims* dims = nullptr;
  if (const auto* im = ds.get_if<ImageData>()) dims = &im->dims, s.image = true;
  if (const auto* sg = ds.get_if<StructuredGrid>()) dims = &sg->dims;
  if (dims == nullptr || structured_dimension(*dims) != 3) return s;
  s.valid = true;
  s.nx = (*dims)[0], s.ny = (*dims)[1], s.nz = (*dims)[2];
  return s;
}

/// Cut-edge masks (see EdgeNumbering) of the first n points of a line with neighbours in +j and
/// +k: byte operations the compiler vectorizes.
void full_line(const std::uint8_t* __restrict s, std::uint8_t* __restrict m, std::size_t n,
               std::size_t dy, std::size_t dz) {
  const std::uint8_t* __restrict s1 = s + 1;
  const std::uint8_t* __restrict s2 = s + dy;
  const std::uint8_t* __restrict s3 = s + dy + 1;
  const std::uint8_t* __restrict s4 = s + dz;
  const std::uint8_t* __restrict s5 = s + dz + 1;
  const std::uint8_t* __restrict s6 = s + dz + dy;
  const std::uint8_t* __restrict s7 = s + dz + dy + 1;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t a = s[i];
    // Per neighbour b: bit 0 of (a ^ b) = sides differ; bit 1 of (a | b) = one is on F = c.
    auto cut = [a](std::uint8_t b) {
      return static_cast<std::uint8_t>((a ^ b) & ~((a | b) >> 1) & 1);
    };
    m[i] = static_cast<std::uint8_t>(cut(s1[i]) | cut(s2[i]) << 1 | cut(s3[i]) << 2 |
                                     cut(s4[i]) << 3 | cut(s5[i]) << 4 | cut(s6[i]) << 5 |
                                     cut(s7[i]) << 6);
  }
}

/// The cut points of a 3D structured input, numbered without sorting. Every voxel (hexahedron)
/// splits into the 6 tetrahedra around its main diagonal, whose edges are exactly the edges from
/// each point p to p + o for the 7 offsets o of (di, dj, dk) in {0, 1}³ \ {0}: the 3 axes, the 3
/// face diagonals from a face's smallest corner, the main diagonal. A cut point is such an edge
/// with ends on both sides whose end above is not exactly on F = c (that end is the point
/// itself). `mask` holds the cut edges of every point as bits in increasing offset order, so
/// numbering them in (p, offset) order — the order of the sorted (lo, hi) keys — is a prefix
/// sum: per group of 8 points in `first` (their masks are one 64-bit word), then a popcount.
struct EdgeNumbering {
  Buffer<std::uint8_t> mask;
  std::vector<std::uint32_t> first;  ///< cut edges before each group of 8 points
  std::array<std::uint64_t, 7> offset{};
  std::size_t total = 0;

  void build(const Structured3D& g, const Buffer<std::uint8_t>& side) {
    const auto nx = static_cast<std::size_t>(g.nx), ny = static_cast<std::size_t>(g.ny),
               nz = static_cast<std::size_t>(g.nz);
    const std::size_t dy = nx, dz = nx * ny, np = side.size();
    offset = {1, dy, dy + 1, dz, dz + 1, dz + dy, dz + dy + 1};
    const std::size_t groups = (np + 7) / 8;
    mask.resize(groups * 8);
    for (std::size_t p = np; p < groups * 8; ++p) mask[p] = 0;  // whole words: no edges in the padding
    parallel_for_range(ny * nz, 64, [&](std::size_t l0, std::size_t l1) {
      for (std::size_t l = l0; l < l1; ++l) {
        const std::size_t j = l % ny, k = l / ny, p0 = l * nx;
        const bool yok = j + 1 < ny, zok = k + 1 < nz;
        const std::uint8_t* s = side.data() + p0;
        std::uint8_t* m = mask.data() + p0;
        // Bit of edge (p, q): ends on both sides, neither exactly on F = c (the one on it is
        // above, so "the end above is on it" is "either is on it").
        auto cut = [](std::uint8_t a, std::uint8_t b) {
          return static_cast<std::uint8_t>(((a ^ b) & 1) & ~((a | b) >> 1));
        };
        // The last point of the line has no +x edges; the others have all those of the line.
        const std::size_t n = nx - 1;
        if (yok && zok) {
          full_line(s, m, n, dy, dz);
          m[n] = static_cast<std::uint8_t>(cut(s[n], s[n + dy]) << 1 | cut(s[n], s[n + dz]) << 3 |
                                           cut(s[n], s[n + dz + dy]) << 5);
        } else if (yok) {
          for (std::size_t i = 0; i < n; ++i) {
            m[i] = static_cast<std::uint8_t>(cut(s[i], s[i + 1]) | cut(s[i], s[i + dy]) << 1 |
                                             cut(s[i], s[i + dy + 1]) << 2);
          }
          m[n] = static_cast<std::uint8_t>(cut(s[n], s[n + dy]) << 1);
        } else if (zok) {
          for (std::size_t i = 0; i < n; ++i) {
            m[i] = static_cast<std::uint8_t>(cut(s[i], s[i + 1]) | cut(s[i], s[i + dz]) << 3 |
                                             cut(s[i], s[i + dz + 1]) << 4);
          }
          m[n] = static_cast<std::uint8_t>(cut(s[n], s[n + dz]) << 3);
        } else {
          for (std::size_t i = 0; i < n; ++i) m[i] = cut(s[i], s[i + 1]);
          m[n] = 0;
        }
      }
    });
    // Cut edges before each group of 8 points (one 64-bit word of masks).
    first.resize(groups + 1);
    constexpr std::size_t kChunk = 1 << 14;
    const std::size_t chunks = (groups + kChunk - 1) / kChunk;
    std::vector<std::size_t> chunk_sum(chunks + 1, 0);
    auto word = [&](std::size_t g8) {
      std::uint64_t x;
      std::memcpy(&x, mask.data() + 8 * g8, 8);
      return x;
    };
    parallel_for_range(chunks, 1, [&](std::size_t c0, std::size_t c1) {
      for (std::size_t c = c0; c < c1; ++c) {
        std::size_t n = 0;
        for (std::size_t g8 = c * kChunk; g8 < std::min(groups, (c + 1) * kChunk); ++g8) {
          n += static_cast<std::size_t>(std::popcount(word(g8)));
        }
        chunk_sum[c + 1] = n;
      }
    });
    for (std::size_t c = 0; c < chunks; ++c) chunk_sum[c + 1] += chunk_sum[c];
    const std::size_t sum = chunk_sum[chunks];
    if (sum >= UINT32_MAX) throw Error("clip: more than 2^32 - 1 new points");
    parallel_for_range(chunks, 1, [&](std::size_t c0, std::size_t c1) {
      for (std::size_t c = c0; c < c1; ++c) {
        std::size_t n = chunk_sum[c];
        for (std::size_t g8 = c * kChunk; g8 < std::min(groups, (c + 1) * kChunk); ++g8) {
          first[g8] = static_cast<std::uint32_t>(n);
          n += static_cast<std::size_t>(std::popcount(word(g8)));
        }
      }
    });
    first[groups] = static_cast<std::uint32_t>(sum);
    total = sum;
  }

  /// The number of edge (lo, hi), or UINT32_MAX if it is not a cut edge.
  [[nodiscard]] std::uint32_t number(std::uint64_t lo, std::uint64_t hi) const {
    int d = 0;
    while (d < 7 && offset[static_cast<std::size_t>(d)] != hi - lo) ++d;
    if (d == 7 || lo >= mask.size() || !((mask[lo] >> d) & 1)) return UINT32_MAX;
    const std::size_t g8 = lo / 8, before = lo % 8;
    std::uint64_t x;
    std::memcpy(&x, mask.data() + 8 * g8, 8);
    const std::uint64_t low = before == 0 ? 0 : x & (~std::uint64_t{0} >> (64 - 8 * before));
    const std::uint32_t n = first[g8] + static_cast<std::uint32_t>(std::popcount(low));
    return n + static_cast<std::uint32_t>(std::popcount(static_cast<unsigned>(mask[lo] & ((1u << d) - 1))));
  }
};

/// Cells [0, n) of a row whose point lines (side bytes, bit 0: F ≥ c) are a0..a3: all[i] = every
/// corner kept, any[i] = some corner kept, where kept is bit 0 (flip = 0) or its complement
/// (flip = 1). Byte operations the compiler vectorizes.
void classify_row(const std::uint8_t* __restrict a0, const std::uint8_t* __restrict a1,
                  const std::uint8_t* __restrict a2, const std::uint8_t* __restrict a3,
                  std::uint8_t* __restrict all, std::uint8_t* __restrict any, std::size_t n,
                  std::uint8_t flip) {
  const auto fm = static_cast<std::uint8_t>(flip ? 0xff : 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto x = static_cast<std::uint8_t>(a0[i] & a0[i + 1] & a1[i] & a1[i + 1]);
    const auto y = static_cast<std::uint8_t>(a2[i] & a2[i + 1] & a3[i] & a3[i + 1]);
    const auto u = static_cast<std::uint8_t>(a0[i] | a0[i + 1] | a1[i] | a1[i + 1]);
    const auto v = static_cast<std::uint8_t>(a2[i] | a2[i + 1] | a3[i] | a3[i + 1]);
    const auto a = static_cast<std::uint8_t>(x & y), o = static_cast<std::uint8_t>(u | v);
    all[i] = static_cast<std::uint8_t>(((a & ~fm) | (~o & fm)) & 1);
    any[i] = static_cast<std::uint8_t>(((o & ~fm) | (~a & fm)) & 1);
  }
}

/// The cell pass of a 3D structured input, row of cells by row of cells (along i): the kept side
/// of every point is known first, so the cells of a row wholly kept (runs of them) or wholly
/// dropped are found with byte operations, and only the cells on the surface go through
/// Clipper::process. Same blocks' content as the generic pass, in cell order.
std::vector<ClipBlock> clip_structured(const Clipper& clipper, const Structured3D& g,
                                   EdgeNumbering& edges, const ProgressCallback& progress) {
  const std::size_t np = clipper.np;
  // Per point: bit 0 above (F ≥ c; NaN is below), bit 1 F = c exactly.
  Buffer<std::uint8_t> side(np);
  parallel_for_range(np, 1 << 16, [&](std::size_t a, std::size_t b) {
    const double* F = clipper.F.data();
    const double c = clipper.c;
    for (std::size_t p = a; p < b; ++p) {
      side[p] = static_cast<std::uint8_t>((F[p] >= c) | ((F[p] == c) << 1));
    }
  });
  edges.build(g, side);
  const auto flip = static_cast<std::uint8_t>(clipper.keep_above ? 0 : 1);
  const Index cx = g.cx(), rows = g.cy() * (g.nz - 1);
  const Index rows_per_block = std::max<Index>(1, static_cast<Index>(kClipBlockCells) / cx);
  const auto blocks = static_cast<std::size_t>((rows + rows_per_block - 1) / rows_per_block);
  std::vector<ClipBlock> out(blocks);
  const CellType type = g.image ? CellType::Voxel : CellType::Hexahedron;
  parallel_for_range(
      blocks, 1,
      [&](std::size_t b0, std::size_t b1) {
        std::vector<std::array<int, 4>> simplices;
        std::vector<double> val;
        std::vector<std::uint64_t> gid;
        std::vector<std::uint8_t> all(static_cast<std::size_t>(cx)), any(static_cast<std::size_t>(cx));
        Index ids[8];
        for (std::size_t b = b0; b < b1; ++b) {
          ClipBlock& blk = out[b];
          const Index r0 = static_cast<Index>(b) * rows_per_block;
          const Index r1 = std::min(rows, r0 + rows_per_block);
          for (Index r = r0; r < r1; ++r) {
            const Index j = r % g.cy(), k = r / g.cy();
            const std::size_t p00 = static_cast<std::size_t>(g.nx * (j + g.ny * k));
            const std::size_t dy = static_cast<std::size_t>(g.nx), dz = static_cast<std::size_t>(g.nx * g.ny);
            const std::uint8_t* a0 = side.data() + p00;
            const std::uint8_t* a1 = a0 + dy;
            const std::uint8_t* a2 = a0 + dz;
            const std::uint8_t* a3 = a0 + dy + dz;
            std::uint8_t* al = all.data();
            std::uint8_t* an = any.data();
            classify_row(a0, a1, a2, a3, al, an, static_cast<std::size_t>(cx), flip);
            const Index row_cell = r * cx;
            for (Index i = 0; i < cx;) {
              // Cells with no kept corner, 8 at a time.
              while (i + 8 <= cx) {
                std::uint64_t w;
                std::memcpy(&w, an + i, 8);
                if (w != 0) break;
                i += 8;
              }
              if (i >= cx) break;
              if (al[i]) {  // a run of whole cells
                Index e = i + 1;
                while (e + 8 <= cx) {
                  std::uint64_t w;
                  std::memcpy(&w, al + e, 8);
                  if (w != 0x0101010101010101ull) break;
                  e += 8;
                }
                while (e < cx && al[e]) ++e;
                const Index cell = row_cell + i;
                const auto n = static_cast<std::uint32_t>(e - i);
                if (!blk.entries.empty() && blk.entries.back().whole &&
                    blk.entries.back().cell + blk.entries.back().pieces == cell) {
                  blk.entries.back().pieces += n;
                } else {
                  blk.entries.push_back({cell, true, n});
                }
                blk.kept += n;
                for (const std::size_t line : {p00, p00 + dy, p00 + dz, p00 + dy + dz}) {
                  std::atomic<char>* u = clipper.used + line;
                  for (Index q = i; q <= e; ++q) u[q].store(1, std::memory_order_relaxed);
                }
                i = e;
                continue;
              }
              if (an[i]) {
                g.ids(row_cell + i, ids);
                clipper.process(row_cell + i, type, std::span<const Index>(ids, 8), blk, simplices,
                                val, gid);
              }
              ++i;
            }
          }
        }
      },
      progress_range(progress, 0.2, 0.6), "clip");
  return out;
}

struct Assembled {
  std::vector<std::int64_t> input_id;  // output id of each used input point, or -1
  std::vector<Ref> new_points;         // sorted
  std::size_t used = 0;
};

template <class Out>
ClipStats clip_impl(DatasetRef input, const ImplicitFunction& f, const ClipOptions& options,
                    Out&& write_cells, Points& points, Attributes& point_data_out,
                    Attributes& cell_data_out) {
  if (!std::isfinite(options.value)) {
    throw Error("clip: the clip value " + std::to_string(options.value) + " is not finite");
  }
  validate(input);
  const std::uint64_t np = num_points(input);
  const std::size_t nc = num_cells(input);
  if (np >= UINT32_MAX) throw Error("clip: more than 2^32 - 1 points");
  if (np + nc >= (std::uint64_t{1} << 62)) throw Error("clip: too many points and cells");
  cutting::LinearField plane;
  const bool is_plane = f.kind() == ImplicitFunction::Kind::Plane;
  if (is_plane) plane = {f.value(Vec3{0, 0, 0}), f.gradient(Vec3{0, 0, 0})};
  const Buffer<double> F = cutting::evaluate_at_points(input, f, is_plane ? &plane : nullptr,
                                                       progress_range(options.progress, 0, 0.2));
  std::vector<std::atomic<char>> used(np);
  parallel_for_range(np, 1 << 16, [&](std::size_t a, std::size_t b) {
    for (std::size_t i = a; i < b; ++i) used[i].store(0, std::memory_order_relaxed);
  });
  const Clipper clipper{input, f, F, options.value, !options.inside_out, np, used.data()};
  const Structured3D grid = structured_3d(input);
  EdgeNumbering edges;
  std::vector<ClipBlock> out;
  if (grid.valid) {
    out = clip_structured(clipper, grid, edges, options.progress);
  } else {
    const std::size_t blocks = (nc + kClipBlockCells - 1) / kClipBlockCells;
    out.resize(blocks);
    parallel_for_range(
        blocks, 1,
        [&](std::size_t b0, std::size_t b1) {
          std::vector<std::array<int, 4>> simplices;
          std::vector<double> val;
          std::vector<std::uint64_t> gid;
          for (std::size_t b = b0; b < b1; ++b) {
            cutting::visit_cells(input, b * kClipBlockCells, std::min(nc, (b + 1) * kClipBlockCells),
                                 [&](Index cell, CellType type, std::span<const Index> ids) {
                                   clipper.process(cell, type, ids, out[b], simplices, val, gid);
                                 });
          }
        },
        progress_range(options.progress, 0.2, 0.6), "clip");
  }
  const std::size_t blocks = out.size();

  // Input points referenced by pieces; new points (cut points, centres): each block's sorted
  // and unique in parallel, then all of them. Every ref of a block gets a slot: its place in the
  // block's unique list, turned into its place in the global list below (kInput: an input point).
  constexpr std::uint32_t kInput = UINT32_MAX;
  std::vector<std::vector<Ref>> block_fresh(blocks);
  std::vector<std::vector<std::uint32_t>> slots(blocks);
  // Structured: a cell's centre and the cut points on its edges to the centre, per block in
  // order of appearance (unique to their cell, so to their block), numbered after the edges.
  std::vector<std::vector<Ref>> block_extra(grid.valid ? blocks : 0);
  constexpr std::uint32_t kExtra = std::uint32_t{1} << 31;
  if (grid.valid) {
    // Structured: cut points numbered by edge (EdgeNumbering), nothing to sort.
    parallel_for_range(blocks, 1, [&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b) {
        const auto& refs = out[b].refs;
        auto& slot = slots[b];
        auto& extra = block_extra[b];
        slot.resize(refs.size());
        for (std::size_t i = 0; i < refs.size(); ++i) {
          const Ref& r = refs[i];
          if (r.a == r.b && r.a < np) {
            used[r.a].store(1, std::memory_order_relaxed);
            slot[i] = kInput;
          } else if (r.b >= np) {
            // A cell's refs are consecutive and it has at most 9 of these: the last 16 hold any
            // earlier occurrence.
            std::size_t e = extra.size();
            const std::size_t stop = e > 16 ? e - 16 : 0;
            while (e > stop && !(extra[e - 1] == r)) --e;
            if (e == stop) {
              extra.push_back(r);
              e = extra.size();
            }
            check_invariant(extra.size() < kExtra - 1, "clip: centre points of a block");
            slot[i] = kExtra | static_cast<std::uint32_t>(e - 1);
          } else {
            slot[i] = edges.number(r.a, r.b);
            check_invariant(slot[i] < kExtra, "clip: a cut point off the structured edges");
          }
        }
      }
    });
  } else {
  parallel_for_range(blocks, 1, [&](std::size_t b0, std::size_t b1) {
    std::vector<std::pair<Ref, std::uint32_t>> items;  // fresh refs with their place in the block
    for (std::size_t b = b0; b < b1; ++b) {
      const auto& refs = out[b].refs;
      auto& slot = slots[b];
      slot.resize(refs.size());
      items.clear();
      for (std::size_t i = 0; i < refs.size(); ++i) {
        const Ref& r = refs[i];
        if (r.a == r.b && r.a < np) {
          used[r.a].store(1, std::memory_order_relaxed);
          slot[i] = kInput;
        } else {
          items.emplace_back(r, static_cast<std::uint32_t>(i));
        }
      }
      std::sort(items.begin(), items.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      auto& bf = block_fresh[b];
      for (const auto& [r, i] : items) {
        if (bf.empty() || !(bf.back() == r)) bf.push_back(r);
        slot[i] = static_cast<std::uint32_t>(bf.size() - 1);
      }
    }
  });
  }
  std::vector<Ref> fresh;
  std::vector<Centre> centres;
  if (grid.valid) {
    // The cut edges in number order (EdgeNumbering), then the blocks' centre points.
    std::vector<std::size_t> extra_at(blocks + 1, edges.total);
    for (std::size_t b = 0; b < blocks; ++b) extra_at[b + 1] = extra_at[b] + block_extra[b].size();
    if (extra_at[blocks] >= kExtra) throw Error("clip: more than 2^31 - 1 new points");
    fresh.resize(extra_at[blocks]);
    for (std::size_t b = 0; b < blocks; ++b) {
      std::copy(block_extra[b].begin(), block_extra[b].end(),
                fresh.begin() + static_cast<std::ptrdiff_t>(extra_at[b]));
      centres.insert(centres.end(), out[b].centres.begin(), out[b].centres.end());
    }
    parallel_for_range(edges.first.size() - 1, 4096, [&](std::size_t c0, std::size_t c1) {
      for (std::size_t c = c0; c < c1; ++c) {
        std::size_t at = edges.first[c];
        if (at == edges.first[c + 1]) continue;
        for (std::size_t p = 8 * c; p < std::min<std::size_t>(np, 8 * c + 8); ++p) {
          for (std::size_t d = 0; d < 7; ++d) {
            if ((edges.mask[p] >> d) & 1) fresh[at++] = Ref{p, p + edges.offset[d]};
          }
        }
      }
    });
    if (extra_at[blocks] > edges.total) {
      // Some cells were split around their centre. Their centre points go where sorting all new
      // points would put them (the generic pass's order, so both passes give the same output):
      // the edges are sorted already, the few centre points are sorted and merged in. Such a
      // cell does not use its main diagonal: that cut point is numbered but in no piece, and is
      // left out. Then every slot is renumbered once.
      const auto index_of = [&](std::size_t b, std::uint32_t sl) -> std::size_t {
        return (sl & kExtra) ? extra_at[b] + (sl & ~kExtra) : sl;
      };
      std::vector<std::atomic<std::uint8_t>> referenced(fresh.size());
      parallel_for_range(blocks, 1, [&](std::size_t b0, std::size_t b1) {
        for (std::size_t b = b0; b < b1; ++b) {
          for (const std::uint32_t sl : slots[b]) {
            if (sl != kInput) referenced[index_of(b, sl)].store(1, std::memory_order_relaxed);
          }
        }
      });
      const std::size_t ne = edges.total, nx = fresh.size() - ne;
      std::vector<std::uint32_t> order(nx);
      for (std::size_t j = 0; j < nx; ++j) order[j] = static_cast<std::uint32_t>(j);
      std::sort(order.begin(), order.end(),
                [&](std::uint32_t x, std::uint32_t y) { return fresh[ne + x] < fresh[ne + y]; });
      std::vector<std::uint32_t> final_id(fresh.size(), kInput);
      std::vector<Ref> merged;
      merged.reserve(fresh.size());
      for (std::size_t e = 0, x = 0; e < ne || x < nx;) {
        const bool take_extra = x < nx && (e == ne || fresh[ne + order[x]] < fresh[e]);
        const std::size_t k = take_extra ? ne + order[x++] : e++;
        if (!referenced[k].load(std::memory_order_relaxed)) continue;
        final_id[k] = static_cast<std::uint32_t>(merged.size());
        merged.push_back(fresh[k]);
      }
      fresh.swap(merged);
      parallel_for_range(blocks, 1, [&](std::size_t b0, std::size_t b1) {
        for (std::size_t b = b0; b < b1; ++b) {
          for (std::uint32_t& sl : slots[b]) {
            if (sl != kInput) sl = final_id[index_of(b, sl)];
          }
        }
      });
    }
  } else {
    std::size_t total = 0;
    for (const auto& bf : block_fresh) total += bf.size();
    fresh.reserve(total);
    for (auto& bf : block_fresh) fresh.insert(fresh.end(), bf.begin(), bf.end());
    for (const ClipBlock& b : out) centres.insert(centres.end(), b.centres.begin(), b.centres.end());
    tbb::parallel_sort(fresh.begin(), fresh.end());
    fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
    if (fresh.size() >= kInput) throw Error("clip: more than 2^32 - 1 new points");
    // ClipBlock slots to global places: each block's sorted list is found in the global one by
    // galloping forward from its previous element.
    parallel_for_range(blocks, 1, [&](std::size_t b0, std::size_t b1) {
      std::vector<std::uint32_t> place;
      for (std::size_t b = b0; b < b1; ++b) {
        const auto& bf = block_fresh[b];
        place.resize(bf.size());
        std::size_t at = 0;
        for (std::size_t u = 0; u < bf.size(); ++u) {
          std::size_t step = 1, hi = at;
          while (hi < fresh.size() && fresh[hi] < bf[u]) {
            at = hi + 1;
            hi += step;
            step *= 2;
          }
          at = static_cast<std::size_t>(
              std::lower_bound(fresh.begin() + static_cast<std::ptrdiff_t>(at),
                               fresh.begin() + static_cast<std::ptrdiff_t>(std::min(hi, fresh.size())),
                               bf[u]) -
              fresh.begin());
          place[u] = static_cast<std::uint32_t>(at);
        }
        for (auto& sl : slots[b]) {
          if (sl != kInput) sl = place[sl];
        }
        std::vector<Ref>().swap(block_fresh[b]);
      }
    });
  }
  // Output ids of the used input points (32-bit: memory traffic is much of the cost), by a
  // parallel prefix sum over chunks.
  Buffer<std::uint32_t> input_id(np);
  constexpr std::size_t kChunk = 1 << 16;
  const std::size_t chunks = (np + kChunk - 1) / kChunk;
  std::vector<std::size_t> chunk_used(chunks + 1, 0);
  parallel_for_range(chunks, 1, [&](std::size_t c0, std::size_t c1) {
    for (std::size_t c = c0; c < c1; ++c) {
      std::size_t n = 0;
      for (std::size_t p = c * kChunk; p < std::min<std::size_t>(np, (c + 1) * kChunk); ++p) {
        n += used[p].load(std::memory_order_relaxed) != 0;
      }
      chunk_used[c + 1] = n;
    }
  });
  for (std::size_t c = 0; c < chunks; ++c) chunk_used[c + 1] += chunk_used[c];
  parallel_for_range(chunks, 1, [&](std::size_t c0, std::size_t c1) {
    for (std::size_t c = c0; c < c1; ++c) {
      auto next = static_cast<std::uint32_t>(chunk_used[c]);
      for (std::size_t p = c * kChunk; p < std::min<std::size_t>(np, (c + 1) * kChunk); ++p) {
        input_id[p] = used[p].load(std::memory_order_relaxed) ? next++ : UINT32_MAX;
      }
    }
  });
  const std::size_t n_used = chunk_used[chunks];
  // The output id of ref `i` of block `b`.
  auto id_of = [&](std::size_t b, std::size_t i) -> Index {
    const std::uint32_t sl = slots[b][i];
    if (sl == kInput) return static_cast<Index>(input_id[out[b].refs[i].a]);
    return static_cast<Index>(n_used + sl);
  };
  const std::size_t total_points = n_used + fresh.size();

  // Cells.
  std::size_t total_cells = 0;
  for (const ClipBlock& b : out) {
    for (const Entry& e : b.entries) total_cells += e.pieces;
  }
  AttributeInterpolator interp;
  if (options.interpolate_attributes) {
    interp = AttributeInterpolator(point_data(input), cell_data(input), total_points, total_cells);
  }
  ClipStats stats;
  for (const ClipBlock& b : out) stats.cells_kept += b.kept, stats.cells_split += b.split;
  auto input_index = [&](Index p) { return static_cast<Index>(input_id[static_cast<std::size_t>(p)]); };
  write_cells(out, id_of, input_index, interp);
  stats.cells = total_cells;

  // Points.
  const ImageData* image = input.get_if<ImageData>();
  const Points* pts = nullptr;
  input.visit([&](const auto& d) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(d)>, ImageData>) pts = &d.points;
  });
  auto position = [&](std::uint64_t id) {
    return image ? image->point(static_cast<Index>(id)) : (*pts)[id];
  };
  points = Points(total_points, pts ? pts->type() : ScalarType::Float32);
  parallel_for_range(np, 1 << 14, [&](std::size_t a, std::size_t b) {
    // Image data: (i, j, k) stepped along (the coordinates of ImageData::point(id)).
    Index ii = 0, jj = 0, kk = 0;
    if (image) {
      const auto id = static_cast<Index>(a);
      ii = id % image->dims[0], jj = (id / image->dims[0]) % image->dims[1];
      kk = id / (image->dims[0] * image->dims[1]);
    }
    for (std::size_t p = a; p < b; ++p) {
      if (input_id[p] != UINT32_MAX) {
        const auto o = static_cast<std::size_t>(input_id[p]);
        points.set(o, image ? image->point(ii, jj, kk) : (*pts)[p]);
        interp.copy_point(o, p);
      }
      if (image && ++ii == image->dims[0]) {
        ii = 0;
        if (++jj == image->dims[1]) jj = 0, ++kk;
      }
    }
  });
  const bool linear = is_plane;
  const double c = options.value;
  parallel_for_range(
      fresh.size(), 512,
      [&](std::size_t k0, std::size_t k1) {
        std::vector<Index> ids;
        std::vector<AttributeInterpolator::Term> terms;
        for (std::size_t k = k0; k < k1; ++k) {
          const Ref& r = fresh[k];
          const std::size_t o = n_used + k;
          // The centre of cell `cell`: position, value, and its points for the attributes.
          auto centre = [&](std::uint64_t id) -> const Centre& {
            const auto it = std::lower_bound(centres.begin(), centres.end(), id,
                                             [](const Centre& ce, std::uint64_t v) { return ce.id < v; });
            check_invariant(it != centres.end() && it->id == id, "clip: centre point");
            return *it;
          };
          auto add_terms = [&](std::uint64_t id, double w) {
            if (id < np) {
              terms.emplace_back(static_cast<std::size_t>(id), w);
              return;
            }
            cell_point_ids(input, static_cast<Index>(id - np), ids);
            for (Index p : ids) terms.emplace_back(static_cast<std::size_t>(p), w / static_cast<double>(ids.size()));
          };
          terms.clear();
          if (r.a == r.b) {  // a centre
            const Centre& ce = centre(r.a);
            points.set(o, ce.position);
            add_terms(r.a, 1.0);
            interp.combine(o, terms);
            continue;
          }
          const Vec3 pa = r.a < np ? position(r.a) : centre(r.a).position;
          const Vec3 pb = r.b < np ? position(r.b) : centre(r.b).position;
          const double ga = r.a < np ? F[r.a] - c : centre(r.a).value;
          const double gb = r.b < np ? F[r.b] - c : centre(r.b).value;
          double t = std::isfinite(ga) && std::isfinite(gb) ? ga / (ga - gb) : 0.5;
          t = std::clamp(t, 0.0, 1.0);
          if (!linear && std::isfinite(ga) && std::isfinite(gb)) {
            t = cutting::refine_root(f, pa, pb, ga, gb, c, t);
          }
          points.set(o, pa + (pb - pa) * t);
          if (r.b < np) {
            interp.interpolate(o, r.a, r.b, t);
          } else {
            add_terms(r.a, 1 - t);
            add_terms(r.b, t);
            interp.combine(o, terms);
          }
        }
      },
      progress_range(options.progress, 0.8, 1.0), "clip");
  interp.move_into(point_data_out, cell_data_out);
  stats.points = total_points;
  return stats;
}

}  // namespace

ClipResult clip(DatasetRef input, const ImplicitFunction& f, const ClipOptions& options) {
  ClipResult r;
  UnstructuredGrid& g = r.output;
  r.stats = clip_impl(
      input, f, options,
      [&](const std::vector<ClipBlock>& out, const auto& id_of, const auto& input_index,
          AttributeInterpolator& interp) {
        // Offsets of each block's cells and ids, then every block written in parallel.
        std::vector<std::size_t> cell_at(out.size() + 1, 0), id_at(out.size() + 1, 0);
        parallel_for_range(out.size(), 1, [&](std::size_t b0, std::size_t b1) {
          std::vector<Index> ids;
          for (std::size_t b = b0; b < b1; ++b) {
            std::size_t cells = 0, idn = 0, piece = 0;
            for (const Entry& e : out[b].entries) {
              if (e.whole) {
                cells += e.pieces;
                if (const auto* ug = input.get_if<UnstructuredGrid>()) {
                  for (std::uint32_t w = 0; w < e.pieces; ++w) {
                    idn += ug->cells.cell_size(static_cast<std::size_t>(e.cell) + w);
                  }
                } else if (input.index() <= 1) {  // structured: every cell has as many points
                  cell_point_ids(input, e.cell, ids);
                  idn += ids.size() * e.pieces;
                } else {
                  for (std::uint32_t w = 0; w < e.pieces; ++w) {
                    cell_point_ids(input, e.cell + static_cast<Index>(w), ids);
                    idn += ids.size();
                  }
                }
              } else {
                cells += e.pieces;
                for (std::uint32_t p = 0; p < e.pieces; ++p) idn += out[b].sizes[piece++];
              }
            }
            cell_at[b + 1] = cells;
            id_at[b + 1] = idn;
          }
        });
        for (std::size_t b = 0; b < out.size(); ++b) {
          cell_at[b + 1] += cell_at[b];
          id_at[b + 1] += id_at[b];
        }
        const std::size_t nc = cell_at.back();
        g.types.resize(nc);
        Buffer<Index> offsets(nc + 1), conn(id_at.back());
        const Structured3D grid = structured_3d(input);
        const bool cell_arrays = interp.has_cell_arrays();
        offsets[0] = 0;
        parallel_for_range(out.size(), 1, [&](std::size_t b0, std::size_t b1) {
          std::vector<Index> ids;
          for (std::size_t b = b0; b < b1; ++b) {
            std::size_t c = cell_at[b], at = id_at[b], piece = 0, ref = 0;
            const ClipBlock& blk = out[b];
            for (const Entry& e : blk.entries) {
              if (e.whole && grid.valid) {  // a run along i: ids by arithmetic
                Index sid[8];
                grid.ids(e.cell, sid);
                const CellType type = grid.image ? CellType::Voxel : CellType::Hexahedron;
                Index in_row = e.cell % grid.cx();  // the cell's i
                for (std::uint32_t w = 0; w < e.pieces; ++w, ++in_row) {
                  const Index cell = e.cell + static_cast<Index>(w);
                  if (in_row == grid.cx()) grid.ids(cell, sid), in_row = 0;  // next row
                  g.types[c] = type;
                  for (Index& id : sid) conn[at++] = input_index(id++);
                  offsets[++c] = static_cast<Index>(at);
                  if (cell_arrays) interp.copy_cell(c - 1, static_cast<std::size_t>(cell));
                }
                continue;
              }
              if (e.whole) {
                for (std::uint32_t w = 0; w < e.pieces; ++w) {
                  const Index cell = e.cell + static_cast<Index>(w);
                  cell_point_ids(input, cell, ids);
                  g.types[c] = cell_type(input, cell);
                  for (Index id : ids) conn[at++] = input_index(id);
                  offsets[++c] = static_cast<Index>(at);
                  interp.copy_cell(c - 1, static_cast<std::size_t>(cell));
                }
                continue;
              }
              for (std::uint32_t p = 0; p < e.pieces; ++p, ++piece) {
                g.types[c] = blk.types[piece];
                for (int q = 0; q < blk.sizes[piece]; ++q) conn[at++] = id_of(b, ref++);
                offsets[++c] = static_cast<Index>(at);
                interp.copy_cell(c - 1, static_cast<std::size_t>(e.cell));
              }
            }
          }
        });
        g.cells = CellArray(std::move(offsets), std::move(conn));
      },
      g.points, g.point_data, g.cell_data);
  g.field_data = field_data(input);
  return r;
}

ClipPolyResult clip_polydata(const PolyData& input, const ImplicitFunction& f,
                             const ClipOptions& options) {
  ClipPolyResult r;
  PolyData& pd = r.output;
  r.stats = clip_impl(
      input, f, options,
      [&](const std::vector<ClipBlock>& out, const auto& id_of, const auto& input_index,
          AttributeInterpolator& interp) {
        // Each output cell goes to verts, lines, polys or strips by its type; cell data follows
        // the PolyData order (all verts, then lines, polys, strips).
        struct Made {
          int kind;
          Index src;
        };
        std::vector<Made> made;
        std::array<CellArray*, 4> kinds{&pd.verts, &pd.lines, &pd.polys, &pd.strips};
        std::vector<Index> ids, mapped;
        auto kind_of = [](CellType t) {
          switch (cell_dimension(t)) {
            case 0: return 0;
            case 1: return 1;
            default: return t == CellType::TriangleStrip ? 3 : 2;
          }
        };
        for (const ClipBlock& blk : out) {
          std::size_t piece = 0, ref = 0;
          for (const Entry& e : blk.entries) {
            if (e.whole) {
              for (std::uint32_t w = 0; w < e.pieces; ++w) {
                const Index cell = e.cell + static_cast<Index>(w);
                cell_point_ids(input, cell, ids);
                mapped.clear();
                for (Index id : ids) mapped.push_back(input_index(id));
                const int k = kind_of(cell_type(input, cell));
                kinds[static_cast<std::size_t>(k)]->add(mapped);
                made.push_back({k, cell});
              }
              continue;
            }
            for (std::uint32_t p = 0; p < e.pieces; ++p, ++piece) {
              mapped.clear();
              for (int q = 0; q < blk.sizes[piece]; ++q) mapped.push_back(id_of(static_cast<std::size_t>(&blk - out.data()), ref++));
              const int k = kind_of(blk.types[piece]);
              kinds[static_cast<std::size_t>(k)]->add(mapped);
              made.push_back({k, e.cell});
            }
          }
        }
        std::size_t o = 0;
        for (int k = 0; k < 4; ++k) {
          for (const Made& m : made) {
            if (m.kind == k) interp.copy_cell(o++, static_cast<std::size_t>(m.src));
          }
        }
      },
      pd.points, pd.point_data, pd.cell_data);
  pd.field_data = input.field_data;
  return r;
}

}  // namespace isoforge
