#pragma once
// Private: the pieces contour_lines.cpp (marching squares, polyline joining, polydata) and
// contour_cells.cpp (marching cells on structured and unstructured grids) share.
//
// Isolines of 2D cells follow the face rule of the case tables (tables.hpp): the crossings on a
// polygon's sides, taken counter-clockwise about its normal (right-hand rule of its point
// order), alternate between exits (from a corner at or above the isovalue to one below) and
// entries; each segment runs from an exit to an entry, which keeps the corners at or above the
// isovalue on its left when the polygon is seen from the side its normal points to. Polygons
// with four or more crossings pair them by the asymptotic decider (quads) or by the mean of the
// corner values (longer polygons).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#include "contour_internal.hpp"
#include "tables.hpp"

namespace isoforge::contour_detail {

// ------------------------------------------------------------------------------------------------
// Rows of one bit per sample (at or above the isovalue), 64 samples per word, as the 3D image
// contour keeps them.

using Word = std::uint64_t;

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
  return prefix[w] + std::popcount(mask[w] & ((Word{1} << (i & 63)) - 1));
}

/// Stores the unit vector of g (zero if g is zero or not finite), negated when `flip`.
inline void store_normal(float* n, Vec3 g, bool flip) {
  const double len = norm(g);
  g = len > 0 && std::isfinite(len) ? g / len : Vec3{0, 0, 0};
  if (flip) g = -g;
  n[0] = static_cast<float>(g.x);
  n[1] = static_cast<float>(g.y);
  n[2] = static_cast<float>(g.z);
}

/// Bit i of a row.
inline unsigned bit_at(const Word* row, Index i) {
  return static_cast<unsigned>((row[i >> 6] >> (i & 63)) & 1u);
}

/// Classifies `rows` rows of `n` samples (contiguous) into (n + 63) / 64 words each, in
/// parallel: bit set when the value is at or above `iso` (NaN: below).
template <class T>
void classify_rows(const T* values, Index n, Index rows, double iso, Word* bits) {
  const Index words = (n + 63) / 64;
  // For float data, a threshold with v >= threshold exactly when double(v) >= iso.
  [[maybe_unused]] float threshold = 0;
  if constexpr (std::is_same_v<T, float>) {
    threshold = static_cast<float>(iso);
    if (static_cast<double>(threshold) < iso)
      threshold = std::nextafter(threshold, std::numeric_limits<float>::infinity());
  }
  tbb::parallel_for(
      tbb::blocked_range<Index>(0, rows, 16), [&](const tbb::blocked_range<Index>& r) {
        for (Index row = r.begin(); row != r.end(); ++row) {
          const T* v = values + n * row;
          Word* out = bits + words * row;
          for (Index w = 0; w < words; ++w) {
            const Index count = std::min<Index>(64, n - 64 * w);
            const T* p = v + 64 * w;
            Word word = 0;
            Index b = 0;
            if constexpr (std::is_same_v<T, float>) {
              if (count == 64) {  // four samples per compare; movemask packs the sign bits
                const __m128 thr = _mm_set1_ps(threshold);
                for (; b < 64; b += 4) {
                  word |= static_cast<Word>(_mm_movemask_ps(_mm_cmpge_ps(_mm_loadu_ps(p + b), thr)))
                          << b;
                }
              }
              for (; b < count; ++b) word |= static_cast<Word>(p[b] >= threshold) << b;
            } else if constexpr (std::is_same_v<T, double>) {
              if (count == 64) {
                const __m128d thr = _mm_set1_pd(iso);
                for (; b < 64; b += 2) {
                  word |= static_cast<Word>(_mm_movemask_pd(_mm_cmpge_pd(_mm_loadu_pd(p + b), thr)))
                          << b;
                }
              }
              for (; b < count; ++b) word |= static_cast<Word>(p[b] >= iso) << b;
            } else {
              for (; b < count; ++b)
                word |= static_cast<Word>(static_cast<double>(p[b]) >= iso) << b;
            }
            out[w] = word;
          }
        }
      });
}

// ------------------------------------------------------------------------------------------------

/// Segments of one polygon with `n` corners (n >= 3) given its corner values in cyclic order:
/// calls emit(from_side, to_side) for each segment, side k joining corners k and k + 1 (mod n).
/// Returns whether the decider (asymptotic for n == 4) had to resolve four crossings.
template <class Emit>
bool polygon_segments(std::span<const double> v, double iso, Emit&& emit) {
  const std::size_t n = v.size();
  auto above = [&](std::size_t k) { return v[k % n] >= iso; };  // NaN: below
  std::size_t count = 0;
  for (std::size_t k = 0; k < n; ++k) count += above(k) != above(k + 1);
  if (count == 0) return false;
  // Joining each exit to the next entry cuts off the runs below the isovalue (the regions above
  // it stay connected); joining it to the previous entry cuts off the runs above. With two
  // crossings both rules give the one segment.
  bool connect_above = true;
  if (count > 2) {
    if (n == 4) {
      connect_above = above_connected(v[0], v[1], v[2], v[3], iso);
    } else {
      double mean = 0;
      for (double x : v) mean += x;
      connect_above = mean / static_cast<double>(n) >= iso;
    }
  }
  int first = -1, pending = -1;  // first crossed side; exit (or entry) waiting for its partner
  bool first_is_exit = false;
  for (std::size_t k = 0; k < n; ++k) {
    if (above(k) == above(k + 1)) continue;
    const int s = static_cast<int>(k);
    const bool is_exit = above(k);
    if (first < 0) {
      first = s;
      first_is_exit = is_exit;
    }
    if (connect_above) {
      if (is_exit) {
        pending = s;
      } else if (pending >= 0) {
        emit(pending, s);
        pending = -1;
      }
    } else {
      if (!is_exit) {
        pending = s;
      } else if (pending >= 0) {
        emit(s, pending);
        pending = -1;
      }
    }
  }
  // The pair that wraps around: an exit (entry) left over with the first crossing.
  if (pending >= 0 && first != pending) {
    if (connect_above && !first_is_exit) emit(pending, first);
    if (!connect_above && first_is_exit) emit(first, pending);
  }
  return count > 2 && n == 4;
}

/// Polylines made of joined segments.
struct Polylines {
  Buffer<Index> offsets{0};    ///< CellArray layout
  Buffer<Index> connectivity;  ///< a closed polyline repeats its first point at its end
  /// Per polyline: its lowest segment (join_segments) or its first point (lattice links).
  std::vector<std::size_t> first;
};

/// Joins segments (two point ids each, `segments.size() / 2` of them, no segment with equal
/// ends) into maximal polylines: two segments are chained through a point used by exactly these
/// two segments, and only if `joinable(s, t)` (when given) allows it. Polylines come in the order
/// of their lowest segment; each runs along the direction most of its segments have (all of them
/// for consistently oriented input); a closed one starts at its lowest segment.
[[nodiscard]] Polylines join_segments(
    std::span<const Index> segments, std::size_t points,
    const std::function<bool(std::size_t, std::size_t)>& joinable);

/// Whether two input cells carry bytewise equal tuples in every array of `cell_data`.
class SameCellData {
 public:
  explicit SameCellData(const Attributes& cell_data) : cell_data_(&cell_data) {}
  [[nodiscard]] bool operator()(std::size_t a, std::size_t b) const;

 private:
  const Attributes* cell_data_;
};

/// Marching squares on a structured grid with two dimensions > 1 (quads in the grid's own
/// points; polylines) or one (vertices) (contour_lines.cpp).
[[nodiscard]] PolyData contour_structured_grid_2d(const StructuredGrid& grid,
                                                  const ContourOptions& options,
                                                  ContourStats* stats);

/// A run of cells of an unstructured grid or polygonal data: `cells` with one type each
/// (`types`) or all of kind `kind` (`types` null; Polygon means triangle/quad/polygon by size,
/// PolyLine means line/polyline); cell c of the run is input cell `first_cell + c`.
struct CellRun {
  const CellArray* cells = nullptr;
  const std::vector<CellType>* types = nullptr;
  CellType kind = CellType::Empty;
  std::size_t first_cell = 0;
};

/// Marching cells on any list of linear cells sharing `points` (contour_cells.cpp): 3D cells
/// give triangles, 2D cells polylines, 1D cells vertices; points merged by global edge
/// (min id, max id) and numbered in order of first use. `what` names the caller in errors.
[[nodiscard]] PolyData contour_cell_runs(const Points& points, const Attributes& point_data,
                                         const Attributes& cell_data, std::span<const CellRun> runs,
                                         const ContourOptions& options, ContourStats* stats,
                                         const char* what);

}  // namespace isoforge::contour_detail
