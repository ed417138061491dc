#pragma once
// Private: rows of one bit per sample (at or above the isovalue), 64 samples per word, and the
// word operations on them that the lattice contours (marching cubes, marching squares, sparse
// marching cubes) count and rank crossings with.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "isoforge/core/cell_array.hpp"

namespace isoforge::contour_detail {

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

}  // namespace isoforge::contour_detail
