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
#include <cmath>
#include <cstdint>
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

struct Block {
  std::vector<Entry> entries;
  std::vector<CellType> types;        // per piece
  std::vector<std::uint8_t> sizes;    // per piece
  std::vector<Ref> refs;              // piece points
  std::vector<Centre> centres;
  std::size_t kept = 0, split = 0;
};

constexpr std::size_t kBlockCells = 4096;
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

/// The simplices of a cell, by local ids (kCentre = the centre): tetrahedra for 3D cells
/// (positively oriented), triangles (the cell's orientation), lines, vertices. `dim` is set to
/// the simplices' dimension.
void decompose(CellType type, std::span<const Index> g, std::vector<std::array<int, 4>>& out,
               int& dim) {
  out.clear();
  const auto n = static_cast<int>(g.size());
  dim = cell_dimension(type);
  switch (type) {
    case CellType::Tetra: out.push_back({0, 1, 2, 3}); return;
    case CellType::Hexahedron:
    case CellType::Voxel:
      if (six_tetrahedra(type, g, out)) return;
      [[fallthrough]];
    case CellType::Pyramid:
    case CellType::Wedge: {
      const int apex = type == CellType::Pyramid ? 4 : kCentre;
      static thread_local std::vector<std::array<int, 4>> tris;
      tris.clear();
      for (const CellFace& f : cell_faces(type)) {
        if (type == CellType::Pyramid && f.size == 3) continue;  // the apex's faces
        if (f.size == 3) tris.push_back({f.ids[0], f.ids[1], f.ids[2], 0});
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

  void process(Index cell, CellType type, std::span<const Index> ids, Block& blk,
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
    decompose(type, ids, simplices, dim);
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
    for (const auto& s : simplices) {
      if (dim == 3) {
        int nk = 0;
        for (int i = 0; i < 4; ++i) nk += kept(s[i]);
        if (nk == 0) continue;
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
          emit(CellType::Wedge,
               {at(la), edge(la, x), edge(la, y), at(lb), edge(lb, x), edge(lb, y)});
        }
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
  const std::size_t blocks = (nc + kBlockCells - 1) / kBlockCells;
  std::vector<Block> out(blocks);
  parallel_for_range(
      blocks, 1,
      [&](std::size_t b0, std::size_t b1) {
        std::vector<std::array<int, 4>> simplices;
        std::vector<double> val;
        std::vector<std::uint64_t> gid;
        for (std::size_t b = b0; b < b1; ++b) {
          cutting::visit_cells(input, b * kBlockCells, std::min(nc, (b + 1) * kBlockCells),
                               [&](Index cell, CellType type, std::span<const Index> ids) {
                                 clipper.process(cell, type, ids, out[b], simplices, val, gid);
                               });
        }
      },
      progress_range(options.progress, 0.2, 0.6), "clip");

  // Input points referenced by pieces; new points (cut points, centres): each block's sorted
  // and unique in parallel, then all of them.
  std::vector<std::vector<Ref>> block_fresh(blocks);
  parallel_for_range(blocks, 1, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      auto& bf = block_fresh[b];
      for (const Ref& r : out[b].refs) {
        if (r.a == r.b && r.a < np) used[r.a].store(1, std::memory_order_relaxed);
        else bf.push_back(r);
      }
      std::sort(bf.begin(), bf.end());
      bf.erase(std::unique(bf.begin(), bf.end()), bf.end());
    }
  });
  std::vector<Ref> fresh;
  std::vector<Centre> centres;
  {
    std::size_t total = 0;
    for (const auto& bf : block_fresh) total += bf.size();
    fresh.reserve(total);
    for (auto& bf : block_fresh) {
      fresh.insert(fresh.end(), bf.begin(), bf.end());
      std::vector<Ref>().swap(bf);
    }
    for (const Block& b : out) centres.insert(centres.end(), b.centres.begin(), b.centres.end());
  }
  tbb::parallel_sort(fresh.begin(), fresh.end());
  fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
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
  auto id_of = [&](const Ref& r) -> Index {
    if (r.a == r.b && r.a < np) return static_cast<Index>(input_id[r.a]);
    return static_cast<Index>(n_used + static_cast<std::size_t>(
                                           std::lower_bound(fresh.begin(), fresh.end(), r) - fresh.begin()));
  };
  const std::size_t total_points = n_used + fresh.size();

  // Cells.
  std::size_t total_cells = 0;
  for (const Block& b : out) {
    for (const Entry& e : b.entries) total_cells += e.pieces;
  }
  AttributeInterpolator interp;
  if (options.interpolate_attributes) {
    interp = AttributeInterpolator(point_data(input), cell_data(input), total_points, total_cells);
  }
  ClipStats stats;
  for (const Block& b : out) stats.cells_kept += b.kept, stats.cells_split += b.split;
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
    for (std::size_t p = a; p < b; ++p) {
      if (input_id[p] == UINT32_MAX) continue;
      const auto o = static_cast<std::size_t>(input_id[p]);
      points.set(o, position(p));
      interp.copy_point(o, p);
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
      [&](const std::vector<Block>& out, const auto& id_of, const auto& input_index,
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
        offsets[0] = 0;
        parallel_for_range(out.size(), 1, [&](std::size_t b0, std::size_t b1) {
          std::vector<Index> ids;
          for (std::size_t b = b0; b < b1; ++b) {
            std::size_t c = cell_at[b], at = id_at[b], piece = 0, ref = 0;
            const Block& blk = out[b];
            for (const Entry& e : blk.entries) {
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
                for (int q = 0; q < blk.sizes[piece]; ++q) conn[at++] = id_of(blk.refs[ref++]);
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
      [&](const std::vector<Block>& out, const auto& id_of, const auto& input_index,
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
        for (const Block& blk : out) {
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
              for (int q = 0; q < blk.sizes[piece]; ++q) mapped.push_back(id_of(blk.refs[ref++]));
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
