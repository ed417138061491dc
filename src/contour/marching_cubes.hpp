#pragma once
// Private: marching cubes on a lattice of hexahedral cells (3D images and structured grids),
// organised like Flying Edges (Schroeder, Maynard & Geveci, "Flying Edges: A High-Performance
// Scalable Isocontouring Algorithm", LDAV 2015) but with the edge classification done on bit
// planes:
//   pass 1  every sample becomes one bit (value >= isovalue), 64 samples per word;
//   pass 2  per row of samples: crossings of its x-, y- and z-edges are popcounts of XORs of bit
//           words, and the cells that are not all-above or all-below come out of a handful of
//           word operations; only those are looked up in the case table;
//   pass 3  prefix sums of the per-row counts give every row its exact output offsets;
//   pass 4  rows generate their points and triangles in parallel, writing only their own ranges;
//           a triangle's point id is its row's offset plus the rank of its edge among the row's
//           crossings (a popcount), so no hash map or lock is needed.
// The output does not depend on the number of threads.
//
// The geometry is a policy: image data places points on the regular grid (computed exactly as
// the sparse OpenVDB contour does, so the two agree bit for bit), structured grids interpolate
// their explicit points and may contain mirrored (left-handed) cells.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "bit_rows.hpp"
#include "contour_output.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/prefetch.hpp"
#include "tables.hpp"

namespace isoforge::contour_detail {

/// Per row of samples: crossings on its x-, y- and z-edges; per row of cells: interior points,
/// triangles and ambiguous faces. Also the totals over all rows.
struct LatticeCounts {
  Index x = 0, y = 0, z = 0, centers = 0, tris = 0, ambiguous = 0;
};

/// The same for one row, in 32 bits (a row has at most 5 triangles, 3 crossings and a few
/// centres per sample): half the memory of the per-row table.
struct RowCounts {
  std::uint32_t x = 0, y = 0, z = 0, centers = 0, tris = 0, ambiguous = 0;
};

/// Image data: point (i, j, k) at origin + (i, j, k) * spacing.
struct ImageGeometry {
  const ImageData& image;
  bool mirrored_cells;  ///< a negative spacing count that is odd mirrors every voxel

  explicit ImageGeometry(const ImageData& img)
      : image(img), mirrored_cells(img.spacing.x * img.spacing.y * img.spacing.z < 0) {}

  [[nodiscard]] Vec3 position(Index i, Index j, Index k) const { return image.point(i, j, k); }
  /// The crossing at parameter t on the edge from (i, j, k) along +axis.
  [[nodiscard]] Vec3 edge_point(Index i, Index j, Index k, int axis, double t) const {
    Vec3 p = image.point(i, j, k);
    p[axis] += t * image.spacing[axis];
    return p;
  }
  /// Central differences (one-sided on the boundary), in world units.
  template <class Value>
  [[nodiscard]] Vec3 gradient(const Value& value, Index i, Index j, Index k) const {
    const Dims& n = image.dims;
    const Index at[3] = {i, j, k};
    Vec3 g;
    for (int d = 0; d < 3; ++d) {
      Index lo[3] = {i, j, k}, hi[3] = {i, j, k};
      if (at[d] > 0) --lo[d];
      if (at[d] + 1 < n[d]) ++hi[d];
      g[d] = (value(hi[0], hi[1], hi[2]) - value(lo[0], lo[1], lo[2])) /
             (static_cast<double>(hi[d] - lo[d]) * image.spacing[d]);
    }
    return g;
  }
  [[nodiscard]] bool mirrored(Index, Index, Index) const { return mirrored_cells; }
};

/// Structured grid: explicit points; cells may be mirrored with respect to the voxel table.
struct GridGeometry {
  const StructuredGrid& grid;

  [[nodiscard]] Index id(Index i, Index j, Index k) const {
    return i + grid.dims[0] * (j + grid.dims[1] * k);
  }
  [[nodiscard]] Vec3 position(Index i, Index j, Index k) const {
    return grid.points[static_cast<std::size_t>(id(i, j, k))];
  }
  [[nodiscard]] Vec3 edge_point(Index i, Index j, Index k, int axis, double t) const {
    Index e[3] = {i, j, k};
    ++e[axis];
    const Vec3 a = position(i, j, k), b = position(e[0], e[1], e[2]);
    return a + (b - a) * t;
  }
  /// Index-space central differences (one-sided at the border) of the values and of the
  /// positions, through the chain rule g = J⁻ᵀ ∇f.
  template <class Value>
  [[nodiscard]] Vec3 gradient(const Value& value, Index i, Index j, Index k) const {
    const Dims& n = grid.dims;
    const Index at[3] = {i, j, k};
    Vec3 col[3];
    double df[3];
    for (int d = 0; d < 3; ++d) {
      Index lo[3] = {i, j, k}, hi[3] = {i, j, k};
      if (at[d] > 0) --lo[d];
      if (at[d] + 1 < n[d]) ++hi[d];
      const double h = static_cast<double>(hi[d] - lo[d]);
      col[d] = (position(hi[0], hi[1], hi[2]) - position(lo[0], lo[1], lo[2])) / h;
      df[d] = (value(hi[0], hi[1], hi[2]) - value(lo[0], lo[1], lo[2])) / h;
    }
    // Solve Jᵀ g = ∇f: g = (df0 (c1 × c2) + df1 (c2 × c0) + df2 (c0 × c1)) / det J.
    const double det = dot(col[0], cross(col[1], col[2]));
    if (det == 0 || !std::isfinite(det)) return {0, 0, 0};
    return (cross(col[1], col[2]) * df[0] + cross(col[2], col[0]) * df[1] +
            cross(col[0], col[1]) * df[2]) /
           det;
  }
  /// Whether the hexahedron of cell (i, j, k) is mirrored (left-handed).
  [[nodiscard]] bool mirrored(Index i, Index j, Index k) const {
    Vec3 c[8];
    for (int q = 0; q < 8; ++q) c[q] = position(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
    return mirrored_voxel(c);
  }
};

template <class T, class Geometry>
class LatticeContourer {
 public:
  LatticeContourer(const Geometry& geometry, const Dims& dims, const T* values, double iso,
                   const ContourOptions& options)
      : geo_(geometry), v_(values), iso_(iso), opt_(options), nx_(dims[0]), ny_(dims[1]),
        nz_(dims[2]), words_((nx_ + 63) / 64), rows_(ny_ * nz_) {
    if (nx_ > (Index{1} << 28)) {
      throw Error("contour: rows of more than 2^28 samples along x are not supported (dims[0] = " +
                  std::to_string(nx_) + ")");
    }
  }

  /// Passes 1-3, reporting the fraction of rows counted. Returns the totals (x = all points,
  /// tris = all triangles).
  LatticeCounts count(const ProgressCallback& progress) {
    bits_.resize(static_cast<std::size_t>(rows_ * words_));
    classify_rows(v_, nx_, rows_, iso_, bits_.data());
    counts_.assign(static_cast<std::size_t>(rows_), RowCounts{});
    parallel_for_range(static_cast<std::size_t>(rows_), 16, [&](std::size_t begin, std::size_t end) {
      for (auto row = static_cast<Index>(begin); row != static_cast<Index>(end); ++row) {
        const Index j = row % ny_, k = row / ny_;
        RowCounts& rc = counts_[static_cast<std::size_t>(row)];
        const Word* b00 = row_bits(j, k);
        for (Index w = 0; w < words_; ++w) {
          rc.x += std::popcount((b00[w] ^ shifted(b00, w, words_)) & valid_bits(w, nx_ - 1));
        }
        const Word* b10 = j + 1 < ny_ ? row_bits(j + 1, k) : nullptr;
        const Word* b01 = k + 1 < nz_ ? row_bits(j, k + 1) : nullptr;
        if (b10) for (Index w = 0; w < words_; ++w) rc.y += std::popcount(b00[w] ^ b10[w]);
        if (b01) for (Index w = 0; w < words_; ++w) rc.z += std::popcount(b00[w] ^ b01[w]);
        if (!b10 || !b01) continue;
        const Word* b11 = row_bits(j + 1, k + 1);
        for_each_mixed_cell(b00, b10, b01, b11, j, k,
                            [&](Index, const CaseTable::Case& c, const CaseTable::Variant& var) {
                              rc.ambiguous += c.ambiguous;
                              rc.tris += var.triangles;
                              rc.centers += var.centers;
                            });
      }
    }, progress, "contour");
    point_offset_.resize(static_cast<std::size_t>(rows_) + 1);
    tri_offset_.resize(static_cast<std::size_t>(rows_) + 1);
    point_offset_[0] = 0;
    tri_offset_[0] = 0;
    LatticeCounts total;
    for (std::size_t r = 0; r < static_cast<std::size_t>(rows_); ++r) {
      const RowCounts& c = counts_[r];
      point_offset_[r + 1] = point_offset_[r] + c.x + c.y + c.z + c.centers;
      tri_offset_[r + 1] = tri_offset_[r] + c.tris;
      total.ambiguous += c.ambiguous;
    }
    total.x = point_offset_.back();
    total.tris = tri_offset_.back();
    return total;
  }

  /// Pass 4 into preallocated outputs (3 floats per point, 3 ids per triangle, and the cell
  /// offsets 3 t for triangle t: `offsets[0]` is set by the caller), reporting the fraction of
  /// rows generated.
  void generate(float* pts, Index* conn, Index* offsets, const ContourArrays& arrays,
                const ProgressCallback& progress) const {
    const CaseTable& table = voxel_table();
    // Cell edge e -> (crossing mask, offset along x); masks 0-3 are the x-edges of sample rows
    // 00 10 01 11, 4-5 the y-edges of rows 00 01, 6-7 the z-edges of rows 00 10.
    static constexpr int kEdgeMask[12] = {0, 1, 2, 3, 4, 4, 5, 5, 6, 6, 7, 7};
    static constexpr int kEdgeDi[12] = {0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0, 1};
    parallel_for_range(static_cast<std::size_t>(rows_), 8, [&](std::size_t begin, std::size_t end) {
      std::vector<Word> masks(static_cast<std::size_t>(8 * words_));
      std::vector<Index> prefix(static_cast<std::size_t>(8 * (words_ + 1)));
      for (auto row = static_cast<Index>(begin); row != static_cast<Index>(end); ++row) {
        if (row + kPrefetchRows < rows_) prefetch_row(row + kPrefetchRows);
        const Index j = row % ny_, k = row / ny_;
        const auto ur = static_cast<std::size_t>(row);
        const RowCounts& rc = counts_[ur];
        const Word* b00 = row_bits(j, k);
        // Points on this row's x-, y- and z-edges.
        Index p = point_offset_[ur];
        if (rc.x + rc.y + rc.z + rc.tris == 0) continue;
        for (Index w = 0; w < words_; ++w) {
          Word m = (b00[w] ^ shifted(b00, w, words_)) & valid_bits(w, nx_ - 1);
          while (m) {
            const Index i = 64 * w + std::countr_zero(m);
            m &= m - 1;
            emit(pts, arrays, p++, i, j, k, 0);
          }
        }
        if (j + 1 < ny_) {
          const Word* b10 = row_bits(j + 1, k);
          for (Index w = 0; w < words_; ++w) {
            Word m = b00[w] ^ b10[w];
            while (m) {
              const Index i = 64 * w + std::countr_zero(m);
              m &= m - 1;
              emit(pts, arrays, p++, i, j, k, 1);
            }
          }
        }
        if (k + 1 < nz_) {
          const Word* b01 = row_bits(j, k + 1);
          for (Index w = 0; w < words_; ++w) {
            Word m = b00[w] ^ b01[w];
            while (m) {
              const Index i = 64 * w + std::countr_zero(m);
              m &= m - 1;
              emit(pts, arrays, p++, i, j, k, 2);
            }
          }
        }
        check_invariant(p == point_offset_[ur] + rc.x + rc.y + rc.z, "row edge points = count");
        // Rows of cells without triangles (most of them, for a compact surface) skip the
        // per-row set-up below.
        if (j + 1 >= ny_ || k + 1 >= nz_ || rc.tris == 0) continue;

        // Triangles of the row of cells (j, k).
        const std::size_t r00 = ur, r10 = ur + 1, r01 = ur + static_cast<std::size_t>(ny_), r11 = r01 + 1;
        const Word* b10 = row_bits(j + 1, k);
        const Word* b01 = row_bits(j, k + 1);
        const Word* b11 = row_bits(j + 1, k + 1);
        const Word* rows4[4] = {b00, b10, b01, b11};
        for (int m = 0; m < 4; ++m)
          for (Index w = 0; w < words_; ++w)
            masks[static_cast<std::size_t>(m * words_ + w)] =
                (rows4[m][w] ^ shifted(rows4[m], w, words_)) & valid_bits(w, nx_ - 1);
        for (Index w = 0; w < words_; ++w) {
          masks[static_cast<std::size_t>(4 * words_ + w)] = b00[w] ^ b10[w];
          masks[static_cast<std::size_t>(5 * words_ + w)] = b01[w] ^ b11[w];
          masks[static_cast<std::size_t>(6 * words_ + w)] = b00[w] ^ b01[w];
          masks[static_cast<std::size_t>(7 * words_ + w)] = b10[w] ^ b11[w];
        }
        for (int m = 0; m < 8; ++m) {
          Index* pre = prefix.data() + m * (words_ + 1);
          const Word* mk = masks.data() + m * words_;
          pre[0] = 0;
          for (Index w = 0; w < words_; ++w) pre[w + 1] = pre[w] + std::popcount(mk[w]);
        }
        auto xb = [&](std::size_t rr) { return point_offset_[rr]; };
        auto yb = [&](std::size_t rr) { return point_offset_[rr] + counts_[rr].x; };
        auto zb = [&](std::size_t rr) { return point_offset_[rr] + counts_[rr].x + counts_[rr].y; };
        const Index gbase[8] = {xb(r00), xb(r10), xb(r01), xb(r11), yb(r00), yb(r01), zb(r00), zb(r10)};
        Index t = tri_offset_[ur];
        Index center = p;  // the row's cell-interior points follow its edge points
        for_each_mixed_cell(b00, b10, b01, b11, j, k,
                            [&](Index i, const CaseTable::Case&, const CaseTable::Variant& var) {
            for (unsigned q = 0; q < var.centers; ++q) {
              emit_center(pts, arrays, center + static_cast<Index>(q), table.center_edges(var, q), i, j, k);
            }
            const bool mirrored = geo_.mirrored(i, j, k);
            const auto edges = table.triangles(var);
            const Index cell = i + (nx_ - 1) * (j + (ny_ - 1) * k);
            // Point ids of the cell's crossed edges, each computed once.
            Index ids[12];
            unsigned have = 0;
            auto edge_id = [&](unsigned edge) -> Index {
              if (edge >= 12) return center + static_cast<Index>(edge - 12);
              if (!((have >> edge) & 1u)) {
                const int m = kEdgeMask[edge];
                ids[edge] = gbase[m] + rank(masks.data() + m * words_, prefix.data() + m * (words_ + 1),
                                            i + kEdgeDi[edge]);
                have |= 1u << edge;
              }
              return ids[edge];
            };
            for (std::size_t e = 0; e < edges.size(); e += 3) {
              Index* tri = conn + 3 * t;
              tri[0] = edge_id(edges[e]);
              tri[1] = edge_id(edges[mirrored ? e + 2 : e + 1]);
              tri[2] = edge_id(edges[mirrored ? e + 1 : e + 2]);
              offsets[t + 1] = 3 * (t + 1);
              if (arrays.cell_data) arrays.attributes.copy_cell(static_cast<std::size_t>(t), static_cast<std::size_t>(cell));
              ++t;
            }
            center += var.centers;
                            });
        check_invariant(t == tri_offset_[ur + 1], "row triangles = count");
        check_invariant(center == point_offset_[ur + 1], "row points = count");
      }
    }, progress, "contour");
  }

 private:
  [[nodiscard]] Index id(Index i, Index j, Index k) const { return i + nx_ * (j + ny_ * k); }
  [[nodiscard]] double value(Index i, Index j, Index k) const { return static_cast<double>(v_[id(i, j, k)]); }
  [[nodiscard]] const Word* row_bits(Index j, Index k) const { return bits_.data() + (j + ny_ * k) * words_; }

  // Calls f(i, case, variant) for every cell (i, j, k) of the row of cells whose corners (sample
  // rows b00 b10 b01 b11) are not all on one side, in increasing i; ambiguous faces are resolved
  // by the asymptotic decider. Passes 2 and 4 walk the cells through this, so they agree.
  template <class F>
  void for_each_mixed_cell(const Word* b00, const Word* b10, const Word* b01, const Word* b11, Index j, Index k,
                           F&& f) const {
    const CaseTable& table = voxel_table();
    for (Index w = 0; w < words_; ++w) {
      const CellWords cw = cell_words(b00, b10, b01, b11, w);
      Word active = cw.mixed(valid_bits(w, nx_ - 1));
      while (active) {
        const int bit = std::countr_zero(active);
        const Index i = 64 * w + bit;
        active &= active - 1;
        const CaseTable::Case& c = table.at(cw.case_at(bit));
        const unsigned vb = c.ambiguous ? variant_bits(c, i, j, k) : 0u;
        f(i, c, table.variant(c, vb));
      }
    }
  }

  // Pass 4 reads the samples at the ends of a row's crossed edges: few and scattered when the
  // surface is sparse, so each would be a cache miss by then (the volume was streamed through
  // once, in pass 1). Some rows ahead, the cache lines of the three sample rows (j, k),
  // (j + 1, k) and (j, k + 1) that hold crossed edges' ends are prefetched.
  static constexpr Index kPrefetchRows = 8;
  void prefetch_row(Index row) const {
    const RowCounts& rc = counts_[static_cast<std::size_t>(row)];
    if (rc.x + rc.y + rc.z == 0) return;
    const Index j = row % ny_, k = row / ny_;
    const Word* b00 = row_bits(j, k);
    const Word* b10 = j + 1 < ny_ ? row_bits(j + 1, k) : nullptr;
    const Word* b01 = k + 1 < nz_ ? row_bits(j, k + 1) : nullptr;
    constexpr Index kLine = 64 / static_cast<Index>(sizeof(T));  // samples per cache line
    for (Index w = 0; w < words_; ++w) {
      Word m = (b00[w] ^ shifted(b00, w, words_)) & valid_bits(w, nx_ - 1);
      if (b10) m |= b00[w] ^ b10[w];
      if (b01) m |= b00[w] ^ b01[w];
      while (m) {
        const Index g = std::countr_zero(m) / kLine * kLine;  // first sample of the line
        m &= g + kLine >= 64 ? Word{0} : ~Word{0} << (g + kLine);
        const Index i = 64 * w + g;
        isoforge::prefetch(v_ + id(i, j, k));
        if (b10) isoforge::prefetch(v_ + id(i, j + 1, k));
        if (b01) isoforge::prefetch(v_ + id(i, j, k + 1));
      }
    }
  }

  // The eight corner bits of the cells of word w: rows 00 10 01 11 at i and (shifted) at i + 1.
  struct CellWords {
    Word c[8];  // voxel corner order: 00@i, 00@i+1, 10@i, 10@i+1, 01@i, 01@i+1, 11@i, 11@i+1
    /// Cells whose 8 corners are not all on one side.
    [[nodiscard]] Word mixed(Word valid) const {
      const Word a = c[0];
      return ((a ^ c[1]) | (a ^ c[2]) | (a ^ c[3]) | (a ^ c[4]) | (a ^ c[5]) | (a ^ c[6]) | (a ^ c[7])) &
             valid;
    }
    [[nodiscard]] unsigned case_at(int b) const {
      unsigned cs = 0;
      for (int q = 0; q < 8; ++q) cs |= static_cast<unsigned>((c[q] >> b) & 1u) << q;
      return cs;
    }
  };
  [[nodiscard]] CellWords cell_words(const Word* b00, const Word* b10, const Word* b01, const Word* b11,
                                     Index w) const {
    return {{b00[w], shifted(b00, w, words_), b10[w], shifted(b10, w, words_), b01[w],
             shifted(b01, w, words_), b11[w], shifted(b11, w, words_)}};
  }

  // Variant bits of an ambiguous case: the asymptotic decider on each ambiguous face.
  [[nodiscard]] unsigned variant_bits(const CaseTable::Case& c, Index i, Index j, Index k) const {
    double cv[8];
    for (int q = 0; q < 8; ++q) cv[q] = value(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
    unsigned bits = 0;
    const auto& faces = voxel_table().topology().faces;
    for (unsigned a = 0; a < c.ambiguous; ++a) {
      const auto& f = faces[c.faces[a]];
      if (above_connected(cv[f[0]], cv[f[1]], cv[f[2]], cv[f[3]], iso_)) bits |= 1u << a;
    }
    return bits;
  }

  [[nodiscard]] Vec3 gradient(Index i, Index j, Index k) const {
    return geo_.gradient([this](Index a, Index b, Index c) { return value(a, b, c); }, i, j, k);
  }

  // The crossing on the edge from (i, j, k) along +axis.
  void emit(float* pts, const ContourArrays& arrays, Index out, Index i, Index j, Index k, int axis) const {
    Index e[3] = {i, j, k};
    ++e[axis];
    const double t = crossing(value(i, j, k), value(e[0], e[1], e[2]), iso_);
    const Vec3 x = geo_.edge_point(i, j, k, axis, t);
    pts[3 * out] = static_cast<float>(x.x);
    pts[3 * out + 1] = static_cast<float>(x.y);
    pts[3 * out + 2] = static_cast<float>(x.z);
    if (arrays.attributes.has_point_arrays()) {
      arrays.attributes.interpolate(static_cast<std::size_t>(out), static_cast<std::size_t>(id(i, j, k)),
                         static_cast<std::size_t>(id(e[0], e[1], e[2])), t);
    }
    if (arrays.normals) {
      const Vec3 ga = gradient(i, j, k), gb = gradient(e[0], e[1], e[2]);
      store_normal(arrays.normals + 3 * out, ga + (gb - ga) * t, opt_.flip);
    }
  }

  // A point inside cell (i, j, k): the mean of the crossings on `edges` (see tables.hpp).
  void emit_center(float* pts, const ContourArrays& arrays, Index out,
                   std::span<const std::uint8_t> edges, Index i, Index j, Index k) const {
    const auto& topo = voxel_table().topology();
    Vec3 x{0, 0, 0}, g{0, 0, 0};
    AttributeInterpolator::Term terms[24];
    const double w = 1.0 / static_cast<double>(edges.size());
    std::size_t nt = 0;
    for (const std::uint8_t e : edges) {
      const int c0 = topo.edges[e][0], c1 = topo.edges[e][1];
      const Index i0 = i + (c0 & 1), j0 = j + ((c0 >> 1) & 1), k0 = k + ((c0 >> 2) & 1);
      const Index i1 = i + (c1 & 1), j1 = j + ((c1 >> 1) & 1), k1 = k + ((c1 >> 2) & 1);
      const double t = crossing(value(i0, j0, k0), value(i1, j1, k1), iso_);
      const Vec3 a = geo_.position(i0, j0, k0), b = geo_.position(i1, j1, k1);
      x += (a + (b - a) * t) * w;
      terms[nt++] = {static_cast<std::size_t>(id(i0, j0, k0)), (1 - t) * w};
      terms[nt++] = {static_cast<std::size_t>(id(i1, j1, k1)), t * w};
      if (arrays.normals) {
        const Vec3 ga = gradient(i0, j0, k0), gb = gradient(i1, j1, k1);
        g += (ga + (gb - ga) * t) * w;
      }
    }
    pts[3 * out] = static_cast<float>(x.x);
    pts[3 * out + 1] = static_cast<float>(x.y);
    pts[3 * out + 2] = static_cast<float>(x.z);
    if (arrays.attributes.has_point_arrays()) {
      arrays.attributes.combine(static_cast<std::size_t>(out), std::span<const AttributeInterpolator::Term>(terms, nt));
    }
    if (arrays.normals) store_normal(arrays.normals + 3 * out, g, opt_.flip);
  }

  const Geometry& geo_;
  const T* v_;
  double iso_;
  const ContourOptions& opt_;
  Index nx_, ny_, nz_, words_, rows_;
  Buffer<Word> bits_;
  std::vector<RowCounts> counts_;
  std::vector<Index> point_offset_, tri_offset_;
};

}  // namespace isoforge::contour_detail
