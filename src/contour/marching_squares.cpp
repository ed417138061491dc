// Isolines: marching squares on 2D images and 2D structured grids (Lorensen & Cline, "Marching
// cubes", SIGGRAPH '87, in two dimensions; Maple, "Geometric design and space planning using the
// marching squares and marching cube algorithms", GMAG 2003), with saddle pixels resolved by the
// asymptotic decider (Nielson & Hamann, Visualization '91), and crossing points of 1D images and
// grids.
//
// Marching squares is organised like the 3D image contour: one bit per sample; per-row counts
// from word operations (crossings are popcounts of XORs; a pixel neither all above nor all below
// has one segment, a saddle two); prefix sums into exact output offsets; row-parallel generation
// where a point's id is its row's offset plus its rank among the row's crossings (no hash map).
// In a lattice every point has at most one segment leaving it and one arriving, so segments are
// stored as successor links and joined by one walk; the points are generated row-parallel last.
// The output does not depend on the number of threads.
//
// Orientation: a pixel or quad is the face (0,0) (1,0) (1,1) (0,1) in its two grid axes, taken
// in increasing axis order, and its isolines keep the values at or above the isovalue on their
// left seen from the side its normal points to (+z for xy images, −y for xz, +x for yz): closed
// lines around a maximum run counter-clockwise when the plane is drawn with its first axis to the
// right and its second axis up.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "bit_rows.hpp"
#include "contour_internal.hpp"
#include "contour_output.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/polylines.hpp"
#include "polygon_segments.hpp"
#include "tables.hpp"

namespace isoforge::contour_detail {

namespace {

// Joins consistently oriented segments given as links succ[from] = to (-1: none), with bit 0 of
// flags[p] set when a segment arrives at p and bit 1 when a chain must end at p (a polyline
// leaving p starts there). Polylines that start somewhere come first, in order of their first
// point, then closed ones, each starting at its lowest point. `flags` is used as scratch.
Polylines join_links(const Buffer<Index>& succ, Buffer<std::uint8_t>& flags) {
  const std::size_t np = succ.size();
  constexpr std::uint8_t kArrives = 1, kCut = 2, kDone = 4;
  Polylines out;
  auto walk = [&](std::size_t p0) {
    std::size_t p = p0;
    out.connectivity.push_back(static_cast<Index>(p));
    for (;;) {
      flags[p] |= kDone;
      const auto q = static_cast<std::size_t>(succ[p]);
      out.connectivity.push_back(static_cast<Index>(q));
      if (q == p0 || (flags[q] & kCut) || succ[q] < 0) break;
      p = q;
    }
    out.offsets.push_back(static_cast<Index>(out.connectivity.size()));
    out.first.push_back(p0);
  };
  for (std::size_t p = 0; p < np; ++p) {
    if (succ[p] >= 0 && (!(flags[p] & kArrives) || (flags[p] & kCut))) walk(p);
  }
  for (std::size_t p = 0; p < np; ++p) {
    if (succ[p] >= 0 && !(flags[p] & kDone)) walk(p);
  }
  return out;
}

// ------------------------------------------------------------------------------------------------
// Marching squares on a lattice of nu x nv points (point id u + nu * v).

// Segments of a pixel, corners c0 (u,v), c1 (u+1,v), c2 (u+1,v+1), c3 (u,v+1) as bits 0-3;
// sides 0: c0-c1 (u-edge of row v), 1: c1-c2 (v-edge u+1), 2: c2-c3 (u-edge of row v+1),
// 3: c3-c0 (v-edge u). Variant 1 connects the corners at or above the isovalue across a saddle.
struct SquareCase {
  std::uint8_t segments = 0;
  std::array<std::uint8_t, 4> sides{};  // from, to of each segment
};

struct SquareTable {
  std::array<std::array<SquareCase, 2>, 16> cases;
  SquareTable() {
    for (unsigned c = 0; c < 16; ++c) {
      for (int variant = 0; variant < 2; ++variant) {
        // Values that make the decider pick this variant on a saddle.
        const double hi = variant ? 1.0 : 0.5, lo = -1.0;
        double v[4];
        for (int k = 0; k < 4; ++k) v[k] = ((c >> k) & 1u) ? hi : lo;
        SquareCase& sc = cases[c][static_cast<std::size_t>(variant)];
        polygon_segments(std::span<const double>(v, 4), 0.0, [&](int from, int to) {
          sc.sides[2 * sc.segments] = static_cast<std::uint8_t>(from);
          sc.sides[2 * sc.segments + 1] = static_cast<std::uint8_t>(to);
          ++sc.segments;
        });
      }
    }
  }
};

const SquareTable& square_table() {
  static const SquareTable table;
  return table;
}

// Uniform image lattice: u and v step along the image's two varying axes.
struct ImageLattice {
  Vec3 origin, du, dv;
  [[nodiscard]] Vec3 position(Index u, Index v) const {
    return origin + du * static_cast<double>(u) + dv * static_cast<double>(v);
  }
};

// Curvilinear lattice: the structured grid's own points.
struct GridLattice {
  const Points* points;
  Index nu;
  [[nodiscard]] Vec3 position(Index u, Index v) const {
    return (*points)[static_cast<std::size_t>(u + nu * v)];
  }
};

struct RowCounts {
  Index u_edges = 0, v_edges = 0, segments = 0, ambiguous = 0;
};

// Marching squares on a lattice, organised like the 3D image contour: one bit per sample (at or
// above the isovalue), per-row counts from word operations (crossings are popcounts of XORs;
// every pixel that is not all above or all below has one segment, saddles two), prefix sums,
// then row-parallel generation visiting only crossed edges and mixed pixels.
template <class T, class Lattice>
class SquareContourer {
 public:
  SquareContourer(const Lattice& lattice, const T* values, Index nu, Index nv, double iso,
                  const ContourOptions& options)
      : lat_(lattice),
        v_(values),
        nu_(nu),
        nv_(nv),
        iso_(iso),
        opt_(options),
        words_((nu + 63) / 64) {}

  double value(Index u, Index v) const { return static_cast<double>(v_[u + nu_ * v]); }
  bool above(Index u, Index v) const { return static_cast<double>(v_[u + nu_ * v]) >= iso_; }
  const Word* row_bits(Index v) const { return bits_.data() + v * words_; }

  // Pass 1: one bit per sample.
  void classify() {
    bits_.resize(static_cast<std::size_t>(nv_ * words_));
    classify_rows(v_, nu_, nv_, iso_, bits_.data());
  }

  // Pass 2: crossings and segments per row, then their prefix sums.
  void count(const ProgressCallback& progress) {
    rows_.assign(static_cast<std::size_t>(nv_), RowCounts{});
    parallel_for_range(
        static_cast<std::size_t>(nv_), 64,
        [&](std::size_t begin, std::size_t end) {
          for (auto v = static_cast<Index>(begin); v != static_cast<Index>(end); ++v) {
            RowCounts& rc = rows_[static_cast<std::size_t>(v)];
            const Word* a = row_bits(v);
            for (Index w = 0; w < words_; ++w) {
              rc.u_edges += std::popcount((a[w] ^ shifted(a, w, words_)) & valid_bits(w, nu_ - 1));
            }
            if (v + 1 >= nv_) continue;
            const Word* b = row_bits(v + 1);
            for (Index w = 0; w < words_; ++w) {
              const Word sa = shifted(a, w, words_), sb = shifted(b, w, words_);
              const Word valid = valid_bits(w, nu_ - 1);
              rc.v_edges += std::popcount(a[w] ^ b[w]);
              const Word mixed = ((a[w] ^ sa) | (a[w] ^ b[w]) | (a[w] ^ sb)) & valid;
              const Word saddle = (a[w] ^ sa) & ~(a[w] ^ sb) & ~(sa ^ b[w]) & valid;
              rc.segments += std::popcount(mixed) + std::popcount(saddle);
              rc.ambiguous += std::popcount(saddle);
            }
          }
        },
        progress, "contour");
    point_offset_.assign(static_cast<std::size_t>(nv_) + 1, 0);
    segment_offset_.assign(static_cast<std::size_t>(nv_) + 1, 0);
    for (std::size_t v = 0; v < static_cast<std::size_t>(nv_); ++v) {
      point_offset_[v + 1] = point_offset_[v] + rows_[v].u_edges + rows_[v].v_edges;
      segment_offset_[v + 1] = segment_offset_[v] + rows_[v].segments;
      ambiguous_ += rows_[v].ambiguous;
    }
  }

  [[nodiscard]] Index points() const { return point_offset_.back(); }
  [[nodiscard]] Index segments() const { return segment_offset_.back(); }
  [[nodiscard]] Index ambiguous() const { return ambiguous_; }

  // Pass 3: the segments of every pixel row, as links between points: succ[from] = to and bit 0
  // of flags[to] set (in a lattice every point has at most one segment leaving it and one
  // arriving); with `cells`, cell_out[from] and cell_in[to] record the pixel.
  void generate_links(Index* succ, std::uint8_t* flags, Index* cell_out, Index* cell_in,
                      const ProgressCallback& progress) const {
    parallel_for_range(
        static_cast<std::size_t>(nv_ - 1), 16,
        [&](std::size_t begin, std::size_t end) {
          // Crossing masks of the u-edges of rows v and v+1 and of the v-edges between them, with
          // their per-word prefix counts.
          std::vector<Word> masks(static_cast<std::size_t>(3 * words_));
          std::vector<Index> prefix(static_cast<std::size_t>(3 * (words_ + 1)));
          const auto& table = square_table();
          for (auto v = static_cast<Index>(begin); v != static_cast<Index>(end); ++v) {
            const Word* a = row_bits(v);
            const Word* b = row_bits(v + 1);
            Word* lo = masks.data();
            Word* hi = lo + words_;
            Word* mid = hi + words_;
            for (Index w = 0; w < words_; ++w) {
              const Word valid = valid_bits(w, nu_ - 1);
              lo[w] = (a[w] ^ shifted(a, w, words_)) & valid;
              hi[w] = (b[w] ^ shifted(b, w, words_)) & valid;
              mid[w] = a[w] ^ b[w];
            }
            for (int m = 0; m < 3; ++m) {
              Index* pre = prefix.data() + m * (words_ + 1);
              const Word* mk = masks.data() + m * words_;
              pre[0] = 0;
              for (Index w = 0; w < words_; ++w) pre[w + 1] = pre[w] + std::popcount(mk[w]);
            }
            const Index* plo = prefix.data();
            const Index* phi = plo + (words_ + 1);
            const Index* pmid = phi + (words_ + 1);
            const auto vv = static_cast<std::size_t>(v);
            const Index base_lo = point_offset_[vv];                       // u-edges of row v
            const Index base_mid = point_offset_[vv] + rows_[vv].u_edges;  // v-edges of rows v, v+1
            const Index base_hi = point_offset_[vv + 1];                   // u-edges of row v+1
            Index s = segment_offset_[vv];
            for (Index w = 0; w < words_; ++w) {
              Word mixed = (lo[w] | hi[w] | mid[w] | (a[w] ^ shifted(b, w, words_))) &
                           valid_bits(w, nu_ - 1);
              while (mixed) {
                const Index u = 64 * w + std::countr_zero(mixed);
                mixed &= mixed - 1;
                const unsigned c = bit_at(a, u) | bit_at(a, u + 1) << 1 | bit_at(b, u + 1) << 2 |
                                   bit_at(b, u) << 3;
                unsigned variant = 0;
                if (c == 5 || c == 10) {
                  variant = above_connected(value(u, v), value(u + 1, v), value(u + 1, v + 1),
                                            value(u, v + 1), iso_);
                }
                const Index left = base_mid + rank(mid, pmid, u);
                const Index side_id[4] = {base_lo + rank(lo, plo, u),
                                          left + static_cast<Index>(bit_at(mid, u)),
                                          base_hi + rank(hi, phi, u), left};
                const SquareCase& sc = table.cases[c][variant];
                for (unsigned k = 0; k < sc.segments; ++k) {
                  const Index from = side_id[sc.sides[2 * k]], to = side_id[sc.sides[2 * k + 1]];
                  succ[from] = to;
                  flags[to] = 1;
                  if (cell_out) {
                    cell_out[from] = cell_in[to] = u + (nu_ - 1) * v;
                  }
                  ++s;
                }
              }
            }
            check_invariant(s == segment_offset_[vv + 1], "row segments = count");
          }
        },
        progress, "contour");
  }

  // Pass 4: the points of every row, with interpolated attributes and normals.
  void generate_points(float* pts, const ContourArrays& arrays) const {
    tbb::parallel_for(tbb::blocked_range<Index>(0, nv_, 16),
                      [&](const tbb::blocked_range<Index>& r) {
                        for (Index v = r.begin(); v != r.end(); ++v) {
                          Index p = point_offset_[static_cast<std::size_t>(v)];
                          const Word* a = row_bits(v);
                          for (Index w = 0; w < words_; ++w) {
                            Word m = (a[w] ^ shifted(a, w, words_)) & valid_bits(w, nu_ - 1);
                            while (m) {
                              const Index u = 64 * w + std::countr_zero(m);
                              m &= m - 1;
                              emit(pts, arrays, p++, u, v, u + 1, v);
                            }
                          }
                          if (v + 1 < nv_) {
                            const Word* b = row_bits(v + 1);
                            for (Index w = 0; w < words_; ++w) {
                              Word m = a[w] ^ b[w];
                              while (m) {
                                const Index u = 64 * w + std::countr_zero(m);
                                m &= m - 1;
                                emit(pts, arrays, p++, u, v, u, v + 1);
                              }
                            }
                          }
                          check_invariant(p == point_offset_[static_cast<std::size_t>(v) + 1],
                                          "row points = count");
                        }
                      });
  }

 private:
  void emit(float* pts, const ContourArrays& arrays, Index id, Index u0, Index v0, Index u1,
            Index v1) const {
    const double t = crossing(value(u0, v0), value(u1, v1), iso_);
    const Vec3 a = lat_.position(u0, v0), b = lat_.position(u1, v1);
    const Vec3 x = a + (b - a) * t;
    pts[3 * id] = static_cast<float>(x.x);
    pts[3 * id + 1] = static_cast<float>(x.y);
    pts[3 * id + 2] = static_cast<float>(x.z);
    arrays.attributes.interpolate(static_cast<std::size_t>(id),
                                  static_cast<std::size_t>(u0 + nu_ * v0),
                                  static_cast<std::size_t>(u1 + nu_ * v1), t);
    if (arrays.normals) {
      const Vec3 ga = gradient(u0, v0), gb = gradient(u1, v1);
      store_normal(arrays.normals + 3 * id, ga + (gb - ga) * t, opt_.flip);
    }
  }

 public:
  // World-space gradient at a lattice point from index-space central differences (one-sided at
  // the border) through the chain rule: g = J (JᵀJ)⁻¹ ∇f, J the lattice's tangent vectors.
  Vec3 gradient(Index u, Index v) const {
    const Index ul = u > 0 ? u - 1 : u, uh = u + 1 < nu_ ? u + 1 : u;
    const Vec3 ju = (lat_.position(uh, v) - lat_.position(ul, v)) / static_cast<double>(uh - ul);
    const double fu = (value(uh, v) - value(ul, v)) / static_cast<double>(uh - ul);
    if (nv_ == 1) {
      const double l2 = norm2(ju);
      return l2 > 0 ? ju * (fu / l2) : Vec3{0, 0, 0};
    }
    const Index vl = v > 0 ? v - 1 : v, vh = v + 1 < nv_ ? v + 1 : v;
    const Vec3 jv = (lat_.position(u, vh) - lat_.position(u, vl)) / static_cast<double>(vh - vl);
    const double fv = (value(u, vh) - value(u, vl)) / static_cast<double>(vh - vl);
    const double g00 = dot(ju, ju), g01 = dot(ju, jv), g11 = dot(jv, jv);
    const double det = g00 * g11 - g01 * g01;
    if (!(det > 0)) return {0, 0, 0};
    const double cu = (g11 * fu - g01 * fv) / det, cv = (g00 * fv - g01 * fu) / det;
    return ju * cu + jv * cv;
  }

 private:
  const Lattice& lat_;
  const T* v_;
  Index nu_, nv_;
  double iso_;
  const ContourOptions& opt_;
  Index words_;
  Buffer<Word> bits_;
  std::vector<RowCounts> rows_;
  std::vector<Index> point_offset_, segment_offset_;
  Index ambiguous_ = 0;
};

// Isolines of one isovalue on a lattice with nv > 1.
template <class T, class Lattice>
PolyData contour_squares(const Lattice& lat, const T* values, Index nu, Index nv, double iso,
                         const Attributes& point_data, const Attributes& cell_data,
                         const ContourOptions& opt, ContourStats& stats,
                         const ProgressCallback& progress) {
  SquareContourer<T, Lattice> c(lat, values, nu, nv, iso, opt);
  c.classify();
  c.count(progress_range(progress, 0.0, 0.5));
  const auto np = static_cast<std::size_t>(c.points());
  const auto ns = static_cast<std::size_t>(c.segments());
  // Cell data survives on polylines that join segments of pixels with equal cell data.
  const bool cells = opt.interpolate_attributes && !cell_data.empty();
  Buffer<Index> succ(np), cell_out(cells ? np : 0), cell_in(cells ? np : 0);
  Buffer<std::uint8_t> flags(np);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, np, 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p != r.end(); ++p) {
                        succ[p] = -1;
                        flags[p] = 0;
                      }
                    });
  c.generate_links(succ.data(), flags.data(), cells ? cell_out.data() : nullptr,
                   cells ? cell_in.data() : nullptr, progress_range(progress, 0.5, 0.9));
  if (cells) {
    // A polyline ends where the pixel data changes: bit 1 marks points where a chain is cut.
    const SameCellData same(cell_data);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, np, 1 << 12),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p != r.end(); ++p) {
                          if (flags[p] && succ[p] >= 0 &&
                              !same(static_cast<std::size_t>(cell_in[p]),
                                    static_cast<std::size_t>(cell_out[p]))) {
                            flags[p] |= 2;
                          }
                        }
                      });
  }
  Polylines lines = join_links(succ, flags);
  succ = {};
  flags = {};
  PolyData out;
  out.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, np));
  const std::size_t nl = lines.first.size();
  ContourArrays arrays(point_data, cell_data, np, nl, opt);
  c.generate_points(out.points.floats().data(), arrays);
  if (cells) {
    for (std::size_t l = 0; l < nl; ++l) {
      arrays.attributes.copy_cell(
          l, static_cast<std::size_t>(cell_out[lines.first[l]]));  // its first point
    }
  }
  out.lines = CellArray(std::move(lines.offsets), std::move(lines.connectivity));
  arrays.move_into(out);
  stats.points += np;
  stats.cells += ns;
  stats.ambiguous_faces += static_cast<std::size_t>(c.ambiguous());
  return out;
}

// Crossing points of one isovalue on a lattice with nv == 1 (one vertex per crossed edge, which
// is also the cell it comes from).
template <class T, class Lattice>
PolyData contour_points(const Lattice& lat, const T* values, Index nu, double iso,
                        const Attributes& point_data, const Attributes& cell_data,
                        const ContourOptions& opt, ContourStats& stats) {
  SquareContourer<T, Lattice> c(lat, values, nu, 1, iso, opt);
  std::vector<Index> edges;
  for (Index u = 0; u + 1 < nu; ++u) {
    if (c.above(u, 0) != c.above(u + 1, 0)) edges.push_back(u);
  }
  const std::size_t np = edges.size();
  PolyData out;
  out.points = Points(np);
  ContourArrays arrays(point_data, cell_data, np, np, opt);
  float* pts = out.points.floats().data();
  auto& offsets = out.verts.offsets();
  offsets.resize(np + 1);
  out.verts.connectivity().resize(np);
  for (std::size_t k = 0; k < np; ++k) {
    const Index u = edges[k];
    const double t = crossing(c.value(u, 0), c.value(u + 1, 0), iso);
    const Vec3 a = lat.position(u, 0), b = lat.position(u + 1, 0);
    const Vec3 x = a + (b - a) * t;
    pts[3 * k] = static_cast<float>(x.x);
    pts[3 * k + 1] = static_cast<float>(x.y);
    pts[3 * k + 2] = static_cast<float>(x.z);
    arrays.attributes.interpolate(k, static_cast<std::size_t>(u), static_cast<std::size_t>(u + 1),
                                  t);
    if (arrays.cell_data) arrays.attributes.copy_cell(k, static_cast<std::size_t>(u));
    if (arrays.normals) {
      const Vec3 ga = c.gradient(u, 0), gb = c.gradient(u + 1, 0);
      store_normal(arrays.normals + 3 * k, ga + (gb - ga) * t, opt.flip);
    }
    out.verts.connectivity()[k] = static_cast<Index>(k);
    offsets[k + 1] = static_cast<Index>(k + 1);
  }
  arrays.move_into(out);
  stats.points += np;
  stats.cells += np;
  return out;
}

// Every isovalue on a lattice: the varying axes of `dims` (at most two) become u and v.
template <class Lattice>
PolyData lattice_lines(const Lattice& lat, Index nu, Index nv, const Attributes& point_data,
                       const Attributes& cell_data, const DataArray& scalars,
                       const ContourOptions& options, ContourStats& stats) {
  return contour_each_value(options, stats, [&](std::size_t v, const ProgressCallback& progress) {
    const double iso = options.values[v];
    return scalars.visit([&](const auto& vec) {
      using T = typename std::decay_t<decltype(vec)>::value_type;
      if (nv > 1)
        return contour_squares<T>(lat, vec.data(), nu, nv, iso, point_data, cell_data, options,
                                  stats, progress);
      return contour_points<T>(lat, vec.data(), nu, iso, point_data, cell_data, options, stats);
    });
  });
}

// The varying axes of structured dims (at most two, in increasing order); nu, nv = 1 if absent.
void lattice_axes(const Dims& dims, int axes[2], Index& nu, Index& nv) {
  int n = 0;
  axes[0] = axes[1] = -1;
  for (int a = 0; a < 3; ++a) {
    if (dims[static_cast<std::size_t>(a)] > 1) {
      check_invariant(n < 2, "at most two varying axes");
      axes[n++] = a;
    }
  }
  nu = axes[0] >= 0 ? dims[static_cast<std::size_t>(axes[0])] : 1;
  nv = axes[1] >= 0 ? dims[static_cast<std::size_t>(axes[1])] : 1;
}

}  // namespace

PolyData marching_squares(const ImageData& input, const DataArray& scalars,
                          const ContourOptions& options, ContourStats& stats) {
  int axes[2];
  Index nu, nv;
  lattice_axes(input.dims, axes, nu, nv);
  ImageLattice lat;
  lat.origin = input.origin;
  if (axes[0] >= 0) lat.du[axes[0]] = input.spacing[axes[0]];
  if (axes[1] >= 0) lat.dv[axes[1]] = input.spacing[axes[1]];
  return lattice_lines(lat, nu, nv, input.point_data, input.cell_data, scalars, options, stats);
}

PolyData marching_squares(const StructuredGrid& grid, const DataArray& scalars,
                          const ContourOptions& options, ContourStats& stats) {
  int axes[2];
  Index nu, nv;
  lattice_axes(grid.dims, axes, nu, nv);
  const GridLattice lat{&grid.points, nu};
  return lattice_lines(lat, nu, nv, grid.point_data, grid.cell_data, scalars, options, stats);
}

}  // namespace isoforge::contour_detail
