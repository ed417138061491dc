#pragma once
// Private: isolines of 2D cells, shared by marching squares and marching cells. They follow the
// face rule of the case tables (tables.hpp): the crossings on a polygon's sides, taken
// counter-clockwise about its normal (right-hand rule of its point order), alternate between
// exits (from a corner at or above the isovalue to one below) and entries; each segment runs from
// an exit to an entry, which keeps the corners at or above the isovalue on its left when the
// polygon is seen from the side its normal points to. Polygons with four or more crossings pair
// them by the asymptotic decider (quads) or by the mean of the corner values (longer polygons).

#include <cstddef>
#include <span>

#include "tables.hpp"

namespace isoforge::contour_detail {

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

}  // namespace isoforge::contour_detail
