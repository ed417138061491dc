// Marching cubes on 3D images, organised like Flying Edges (Schroeder, Maynard & Geveci,
// "Flying Edges: A High-Performance Scalable Isocontouring Algorithm", LDAV 2015) but with the
// edge classification done on bit planes:
//   pass 1  every sample becomes one bit (value >= isovalue), 64 samples per word;
//   pass 2  per row: crossings of its x-, y- and z-edges are popcounts of XORs of bit words, and
//           the voxels that are not all-above or all-below come out of a handful of word
//           operations; only those are looked up in the case table (triangle counts);
//   pass 3  prefix sums of the per-row counts give every row its exact output offsets;
//   pass 4  rows generate their points and triangles in parallel, writing only their own
//           ranges; a triangle's point id is its row's offset plus the rank of its edge among
//           the row's crossings (a popcount), so no hash map or lock is needed.
// The output does not depend on the number of threads.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "contour_internal.hpp"
#include "isoforge/contour/contour.hpp"
#include "tables.hpp"

namespace isoforge {

namespace {

using namespace contour_detail;
using Word = std::uint64_t;

struct RowCounts {
  Index x = 0, y = 0, z = 0, centers = 0, tris = 0, ambiguous = 0;
};

/// Bits [0, limit - 64 w) of word w (all 64 when the limit is beyond the word).
inline Word valid_bits(Index w, Index limit) {
  const Index n = limit - 64 * w;
  if (n >= 64) return ~Word{0};
  if (n <= 0) return 0;
  return (Word{1} << n) - 1;
}

/// Bits shifted so that bit b holds sample b + 1 of the row.
inline Word shifted(const Word* row, Index w, Index words) {
  return (row[w] >> 1) | (w + 1 < words ? row[w + 1] << 63 : Word{0});
}

/// Rank of position i among the set bits of a mask, from per-word prefix counts.
inline Index rank(const Word* mask, const Index* prefix, Index i) {
  const Index w = i >> 6;
  const int b = static_cast<int>(i & 63);
  return prefix[w] + std::popcount(mask[w] & ((Word{1} << b) - 1));
}

template <class T>
class ImageContourer {
 public:
  ImageContourer(const ImageData& img, const T* values, double iso, const ContourOptions& options)
      : img_(img), v_(values), iso_(iso), opt_(options),
        nx_(img.dims[0]), ny_(img.dims[1]), nz_(img.dims[2]), words_((nx_ + 63) / 64),
        rows_(ny_ * nz_) {}

  void classify() {
    bits_.assign(static_cast<std::size_t>(rows_ * words_), 0);
    // Threshold such that v >= threshold exactly when double(v) >= iso.
    T threshold;
    if constexpr (std::is_same_v<T, float>) {
      float f = static_cast<float>(iso_);
      if (static_cast<double>(f) < iso_) f = std::nextafter(f, std::numeric_limits<float>::infinity());
      threshold = f;
    }
    tbb::parallel_for(tbb::blocked_range<Index>(0, rows_, 64), [&](const tbb::blocked_range<Index>& r) {
      for (Index row = r.begin(); row != r.end(); ++row) {
        const T* v = v_ + row * nx_;
        Word* out = bits_.data() + row * words_;
        for (Index w = 0; w < words_; ++w) {
          const Index n = std::min<Index>(64, nx_ - 64 * w);
          const T* p = v + 64 * w;
          Word word = 0;
          if constexpr (std::is_same_v<T, float>) {
            Index b = 0;
            if (n == 64) {
              // Four samples per compare; movemask packs the four sign bits.
              const __m128 thr = _mm_set1_ps(threshold);
              for (; b < 64; b += 4) {
                const __m128 cmp = _mm_cmpge_ps(_mm_loadu_ps(p + b), thr);
                word |= static_cast<Word>(_mm_movemask_ps(cmp)) << b;
              }
            }
            for (; b < n; ++b) word |= static_cast<Word>(p[b] >= threshold) << b;
          } else {
            for (Index b = 0; b < n; ++b) word |= static_cast<Word>(static_cast<double>(p[b]) >= iso_) << b;
          }
          out[w] = word;
        }
      }
    });
  }

  const Word* row_bits(Index j, Index k) const { return bits_.data() + (j + ny_ * k) * words_; }

  double value(Index i, Index j, Index k) const {
    return static_cast<double>(v_[i + nx_ * (j + ny_ * k)]);
  }

  // Variant bits of an ambiguous case from the voxel's 8 values (voxel corner order).
  unsigned variant_bits(const CaseTable::Case& c, const double* cv) const {
    unsigned bits = 0;
    const auto& faces = voxel_table().topology().faces;
    for (unsigned a = 0; a < c.ambiguous; ++a) {
      const auto& f = faces[c.faces[a]];
      if (above_connected(cv[f[0]], cv[f[1]], cv[f[2]], cv[f[3]], iso_)) bits |= 1u << a;
    }
    return bits;
  }

  void corner_values(Index i, Index j, Index k, double* cv) const {
    for (int c = 0; c < 8; ++c) cv[c] = value(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
  }

  void count() {
    counts_.assign(static_cast<std::size_t>(rows_), RowCounts{});
    const CaseTable& table = voxel_table();
    tbb::parallel_for(tbb::blocked_range<Index>(0, rows_, 16), [&](const tbb::blocked_range<Index>& r) {
      for (Index row = r.begin(); row != r.end(); ++row) {
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
        for (Index w = 0; w < words_; ++w) {
          Word active = mixed_voxels(b00, b10, b01, b11, w);
          while (active) {
            const int bit = std::countr_zero(active);
            active &= active - 1;
            const Index i = 64 * w + bit;
            const unsigned cs = case_index(b00, b10, b01, b11, i);
            const CaseTable::Case& c = table.at(cs);
            unsigned vb = 0;
            if (c.ambiguous) {
              double cv[8];
              corner_values(i, j, k, cv);
              vb = variant_bits(c, cv);
              rc.ambiguous += c.ambiguous;
            }
            const CaseTable::Variant& var = table.variant(c, vb);
            rc.tris += var.triangles;
            rc.centers += var.centers;
          }
        }
      }
    });
  }

  // Voxels of word w whose 8 corners are not all on one side.
  Word mixed_voxels(const Word* b00, const Word* b10, const Word* b01, const Word* b11, Index w) const {
    const Word a = b00[w];
    const Word diff = (a ^ shifted(b00, w, words_)) | (a ^ b10[w]) | (a ^ shifted(b10, w, words_)) |
                      (a ^ b01[w]) | (a ^ shifted(b01, w, words_)) | (a ^ b11[w]) |
                      (a ^ shifted(b11, w, words_));
    return diff & valid_bits(w, nx_ - 1);
  }

  static unsigned bit_at(const Word* row, Index i) { return static_cast<unsigned>((row[i >> 6] >> (i & 63)) & 1u); }

  static unsigned case_index(const Word* b00, const Word* b10, const Word* b01, const Word* b11, Index i) {
    return bit_at(b00, i) | bit_at(b00, i + 1) << 1 | bit_at(b10, i) << 2 | bit_at(b10, i + 1) << 3 |
           bit_at(b01, i) << 4 | bit_at(b01, i + 1) << 5 | bit_at(b11, i) << 6 | bit_at(b11, i + 1) << 7;
  }

  /// Prefix sums; returns totals.
  RowCounts offsets() {
    point_offset_.resize(static_cast<std::size_t>(rows_) + 1);
    tri_offset_.resize(static_cast<std::size_t>(rows_) + 1);
    RowCounts total;
    point_offset_[0] = 0;
    tri_offset_[0] = 0;
    for (Index r = 0; r < rows_; ++r) {
      const RowCounts& c = counts_[static_cast<std::size_t>(r)];
      point_offset_[static_cast<std::size_t>(r) + 1] = point_offset_[static_cast<std::size_t>(r)] + c.x + c.y + c.z + c.centers;
      tri_offset_[static_cast<std::size_t>(r) + 1] = tri_offset_[static_cast<std::size_t>(r)] + c.tris;
      total.tris += c.tris;
      total.ambiguous += c.ambiguous;
    }
    total.x = point_offset_.back();
    return total;
  }

  // Per-thread scratch for pass 4: crossing masks of the rows a voxel row touches, and their
  // prefix popcounts.
  struct Scratch {
    std::vector<Word> masks;   // 8 masks x words
    std::vector<Index> prefix;  // 8 x (words + 1)
  };

  void generate(PolyData& out) {
    float* pts = out.points.floats().data();
    Index* conn = out.polys.connectivity().data();
    const CaseTable& table = voxel_table();
    const double ox = img_.origin.x, oy = img_.origin.y, oz = img_.origin.z;
    const double hx = img_.spacing.x, hy = img_.spacing.y, hz = img_.spacing.z;
    const bool copy_cells = arrays_ && arrays_->cell_data;
    tbb::parallel_for(tbb::blocked_range<Index>(0, rows_, 8), [&](const tbb::blocked_range<Index>& r) {
      Scratch s;
      s.masks.resize(static_cast<std::size_t>(8 * words_));
      s.prefix.resize(static_cast<std::size_t>(8 * (words_ + 1)));
      for (Index row = r.begin(); row != r.end(); ++row) {
        const Index j = row % ny_, k = row / ny_;
        const Index base = point_offset_[static_cast<std::size_t>(row)];
        const RowCounts& rc = counts_[static_cast<std::size_t>(row)];
        const Word* b00 = row_bits(j, k);
        const double y = oy + static_cast<double>(j) * hy, z = oz + static_cast<double>(k) * hz;
        // Points on this row's x-, y- and z-edges.
        Index p = base;
        for (Index w = 0; w < words_; ++w) {
          Word m = (b00[w] ^ shifted(b00, w, words_)) & valid_bits(w, nx_ - 1);
          while (m) {
            const Index i = 64 * w + std::countr_zero(m);
            m &= m - 1;
            const double t = crossing(value(i, j, k), value(i + 1, j, k), iso_);
            emit(pts, p++, {ox + static_cast<double>(i) * hx + t * hx, y, z}, i, j, k, i + 1, j, k, t);
          }
        }
        if (j + 1 < ny_) {
          const Word* b10 = row_bits(j + 1, k);
          for (Index w = 0; w < words_; ++w) {
            Word m = b00[w] ^ b10[w];
            while (m) {
              const Index i = 64 * w + std::countr_zero(m);
              m &= m - 1;
              const double t = crossing(value(i, j, k), value(i, j + 1, k), iso_);
              emit(pts, p++, {ox + static_cast<double>(i) * hx, y + t * hy, z}, i, j, k, i, j + 1, k, t);
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
              const double t = crossing(value(i, j, k), value(i, j, k + 1), iso_);
              emit(pts, p++, {ox + static_cast<double>(i) * hx, y, z + t * hz}, i, j, k, i, j, k + 1, t);
            }
          }
        }
        ISOFORGE_ASSERT(p == base + rc.x + rc.y + rc.z);
        if (j + 1 >= ny_ || k + 1 >= nz_) continue;

        // Triangles of the voxel row (j, k).
        const Index r00 = row, r10 = row + 1, r01 = row + ny_, r11 = row + ny_ + 1;
        const Word* b10 = row_bits(j + 1, k);
        const Word* b01 = row_bits(j, k + 1);
        const Word* b11 = row_bits(j + 1, k + 1);
        // masks: 0-3 x-crossings of rows 00 10 01 11; 4-5 y of 00 01; 6-7 z of 00 10.
        const Word* rows4[4] = {b00, b10, b01, b11};
        for (int m = 0; m < 4; ++m)
          for (Index w = 0; w < words_; ++w)
            s.masks[static_cast<std::size_t>(m * words_ + w)] =
                (rows4[m][w] ^ shifted(rows4[m], w, words_)) & valid_bits(w, nx_ - 1);
        for (Index w = 0; w < words_; ++w) {
          s.masks[static_cast<std::size_t>(4 * words_ + w)] = b00[w] ^ b10[w];
          s.masks[static_cast<std::size_t>(5 * words_ + w)] = b01[w] ^ b11[w];
          s.masks[static_cast<std::size_t>(6 * words_ + w)] = b00[w] ^ b01[w];
          s.masks[static_cast<std::size_t>(7 * words_ + w)] = b10[w] ^ b11[w];
        }
        for (int m = 0; m < 8; ++m) {
          Index* pre = s.prefix.data() + m * (words_ + 1);
          const Word* mk = s.masks.data() + m * words_;
          pre[0] = 0;
          for (Index w = 0; w < words_; ++w) pre[w + 1] = pre[w] + std::popcount(mk[w]);
        }
        // Point id bases of the edge groups used by a voxel row.
        auto group_base = [&](Index rr, int kind) {
          const RowCounts& c = counts_[static_cast<std::size_t>(rr)];
          return point_offset_[static_cast<std::size_t>(rr)] + (kind >= 1 ? c.x : 0) + (kind >= 2 ? c.y : 0);
        };
        const Index gbase[8] = {group_base(r00, 0), group_base(r10, 0), group_base(r01, 0), group_base(r11, 0),
                                group_base(r00, 1), group_base(r01, 1), group_base(r00, 2), group_base(r10, 2)};
        // Voxel edge e -> (mask, offset along x).
        static constexpr int kEdgeMask[12] = {0, 1, 2, 3, 4, 4, 5, 5, 6, 6, 7, 7};
        static constexpr int kEdgeDi[12] = {0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0, 1};
        Index t = tri_offset_[static_cast<std::size_t>(row)];
        Index center = base + rc.x + rc.y + rc.z;  // this row's cell-interior points
        for (Index w = 0; w < words_; ++w) {
          Word active = mixed_voxels(b00, b10, b01, b11, w);
          while (active) {
            const Index i = 64 * w + std::countr_zero(active);
            active &= active - 1;
            const CaseTable::Case& c = table.at(case_index(b00, b10, b01, b11, i));
            unsigned vb = 0;
            if (c.ambiguous) {
              double cv[8];
              corner_values(i, j, k, cv);
              vb = variant_bits(c, cv);
            }
            const CaseTable::Variant& var = table.variant(c, vb);
            const auto edges = table.triangles(var);
            const Index voxel = i + (nx_ - 1) * (j + (ny_ - 1) * k);
            for (unsigned q = 0; q < var.centers; ++q) {
              emit_center(pts, center + static_cast<Index>(q), table.center_edges(var, q), i, j, k);
            }
            // Point ids of the voxel's crossed edges, each computed once.
            Index ids[12];
            unsigned have = 0;
            auto edge_id = [&](unsigned edge) -> Index {
              if (edge >= 12) return center + static_cast<Index>(edge - 12);
              if (!((have >> edge) & 1u)) {
                const int m = kEdgeMask[edge];
                ids[edge] = gbase[m] + rank(s.masks.data() + m * words_, s.prefix.data() + m * (words_ + 1),
                                            i + kEdgeDi[edge]);
                have |= 1u << edge;
              }
              return ids[edge];
            };
            for (std::size_t e = 0; e < edges.size(); e += 3) {
              Index* tri = conn + 3 * t;
              tri[0] = edge_id(edges[e]);
              tri[1] = edge_id(edges[e + 1]);
              tri[2] = edge_id(edges[e + 2]);
              if (copy_cells) copy_cell(t, voxel);
              ++t;
            }
            center += var.centers;
          }
        }
        ISOFORGE_ASSERT(t == tri_offset_[static_cast<std::size_t>(row) + 1]);
      }
    });
  }

  void set_arrays(const InterpolatedArrays* arrays) { arrays_ = arrays; }

 private:
  std::vector<Index> point_offset_, tri_offset_;

  void emit(float* pts, Index id, const Vec3& p, Index i0, Index j0, Index k0, Index i1, Index j1, Index k1,
            double t) {
    pts[3 * id] = static_cast<float>(p.x);
    pts[3 * id + 1] = static_cast<float>(p.y);
    pts[3 * id + 2] = static_cast<float>(p.z);
    const Index a = i0 + nx_ * (j0 + ny_ * k0), b = i1 + nx_ * (j1 + ny_ * k1);
    if (!arrays_) return;
    if (arrays_->has_point_arrays()) {
      arrays_->interpolate(static_cast<std::size_t>(id), static_cast<std::size_t>(a), static_cast<std::size_t>(b), t);
    }
    if (arrays_->normals) {
      const Vec3 ga = gradient(i0, j0, k0), gb = gradient(i1, j1, k1);
      Vec3 g = ga + (gb - ga) * t;
      const double len = norm(g);
      g = len > 0 ? g / len : Vec3{0, 0, 0};
      if (opt_.flip) g = -g;
      float* n = arrays_->normals + 3 * id;
      n[0] = static_cast<float>(g.x);
      n[1] = static_cast<float>(g.y);
      n[2] = static_cast<float>(g.z);
    }
  }

  // A point inside voxel (i, j, k): the mean of the crossings on `edges` (see tables.hpp).
  void emit_center(float* pts, Index id, std::span<const std::uint8_t> edges, Index i, Index j, Index k) {
    const auto& topo = voxel_table().topology();
    Vec3 p{0, 0, 0}, g{0, 0, 0};
    InterpolatedArrays::Term terms[24];
    const double w = 1.0 / static_cast<double>(edges.size());
    std::size_t nt = 0;
    for (const std::uint8_t e : edges) {
      const int c0 = topo.edges[e][0], c1 = topo.edges[e][1];
      const Index i0 = i + (c0 & 1), j0 = j + ((c0 >> 1) & 1), k0 = k + ((c0 >> 2) & 1);
      const Index i1 = i + (c1 & 1), j1 = j + ((c1 >> 1) & 1), k1 = k + ((c1 >> 2) & 1);
      const double t = crossing(value(i0, j0, k0), value(i1, j1, k1), iso_);
      const Vec3 a = img_.point(i0, j0, k0), b = img_.point(i1, j1, k1);
      p += (a + (b - a) * t) * w;
      terms[nt++] = {static_cast<std::size_t>(i0 + nx_ * (j0 + ny_ * k0)), (1 - t) * w};
      terms[nt++] = {static_cast<std::size_t>(i1 + nx_ * (j1 + ny_ * k1)), t * w};
      if (arrays_ && arrays_->normals) {
        const Vec3 ga = gradient(i0, j0, k0), gb = gradient(i1, j1, k1);
        g += (ga + (gb - ga) * t) * w;
      }
    }
    pts[3 * id] = static_cast<float>(p.x);
    pts[3 * id + 1] = static_cast<float>(p.y);
    pts[3 * id + 2] = static_cast<float>(p.z);
    if (!arrays_) return;
    arrays_->combine(static_cast<std::size_t>(id), std::span<const InterpolatedArrays::Term>(terms, nt));
    if (arrays_->normals) {
      const double len = norm(g);
      g = len > 0 ? g / len : Vec3{0, 0, 0};
      if (opt_.flip) g = -g;
      float* n = arrays_->normals + 3 * id;
      n[0] = static_cast<float>(g.x);
      n[1] = static_cast<float>(g.y);
      n[2] = static_cast<float>(g.z);
    }
  }

  void copy_cell(Index tri, Index voxel) const {
    arrays_->copy_cell(static_cast<std::size_t>(tri), static_cast<std::size_t>(voxel));
  }

  // Central differences (one-sided on the boundary), in world units.
  Vec3 gradient(Index i, Index j, Index k) const {
    auto d = [&](Index a0, Index a1, Index n, int axis) {
      const Index lo = a0 > 0 ? a0 - 1 : a0, hi = a0 + 1 < n ? a0 + 1 : a0;
      (void)a1;
      double vl, vh;
      if (axis == 0) {
        vl = value(lo, j, k);
        vh = value(hi, j, k);
      } else if (axis == 1) {
        vl = value(i, lo, k);
        vh = value(i, hi, k);
      } else {
        vl = value(i, j, lo);
        vh = value(i, j, hi);
      }
      return (vh - vl) / (static_cast<double>(hi - lo) * img_.spacing[axis]);
    };
    return {d(i, 0, nx_, 0), d(j, 0, ny_, 1), d(k, 0, nz_, 2)};
  }

  const ImageData& img_;
  const T* v_;
  double iso_;
  const ContourOptions& opt_;
  const InterpolatedArrays* arrays_ = nullptr;
  Index nx_, ny_, nz_, words_, rows_;
  std::vector<Word> bits_;
  std::vector<RowCounts> counts_;
};

template <class T>
PolyData contour_one(const ImageData& img, const T* values, double iso, const ContourOptions& opt,
                     ContourStats& stats) {
  PolyData out;
  if (img.dims[0] < 2 || img.dims[1] < 2 || img.dims[2] < 2) return out;
  ImageContourer<T> c(img, values, iso, opt);
  c.classify();
  c.count();
  const RowCounts total = c.offsets();
  const auto npts = static_cast<std::size_t>(total.x);
  const auto ntris = static_cast<std::size_t>(total.tris);
  // Outputs are allocated uninitialized and first touched by the parallel passes below.
  out.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, npts));
  out.polys.offsets().resize(ntris + 1);
  out.polys.connectivity().resize(3 * ntris);
  Index* offsets = out.polys.offsets().data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ntris + 1, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t) offsets[t] = static_cast<Index>(3 * t);
  });
  InterpolatedArrays arrays(img.point_data, img.cell_data, npts, ntris, opt.interpolate_attributes,
                            opt.normals == ContourNormals::Gradient);
  c.set_arrays(&arrays);
  c.generate(out);
  arrays.move_into(out.point_data, out.cell_data);
  stats.points += npts;
  stats.cells += ntris;
  stats.ambiguous_faces += static_cast<std::size_t>(total.ambiguous);
  return out;
}

}  // namespace

PolyData contour_image(const ImageData& input, const ContourOptions& options, ContourStats* stats) {
  input.validate();
  const DataArray& scalars = contour_scalars(input.point_data, options, "contour_image");
  if (structured_dimension(input.dims) < 3) {
    return contour_image_2d(input, options, stats);
  }
  ContourStats local;
  std::vector<PolyData> parts;
  for (std::size_t v = 0; v < options.values.size(); ++v) {
    PolyData part = scalars.visit([&](const auto& vec) {
      return contour_one(input, vec.data(), options.values[v], options, local);
    });
    add_isovalue_index(part, static_cast<int>(v));
    parts.push_back(std::move(part));
    report_progress(options.progress, static_cast<double>(v + 1) / static_cast<double>(options.values.size()),
                    "contour");
  }
  PolyData out = append_polydata(std::move(parts));
  finish_output(out, options);
  if (stats) *stats = local;
  return out;
}

}  // namespace isoforge
