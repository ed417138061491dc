#pragma once
/// \file
/// Joining line segments into polylines, shared by contouring (isolines), cutting (contour lines
/// of surfaces) and streamline output.

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "isoforge/core/attributes.hpp"
#include "isoforge/core/buffer.hpp"
#include "isoforge/core/cell_array.hpp"

namespace isoforge {

/// Polylines in the `CellArray` layout.
struct Polylines {
  Buffer<Index> offsets{0};    ///< cells + 1 offsets into `connectivity`
  Buffer<Index> connectivity;  ///< point ids; a closed polyline repeats its first point at its end
  std::vector<std::size_t> first;  ///< per polyline: the segment (or point) it was started from
};

/// Joins segments (two point ids each, `segments.size() / 2` of them, no segment with equal
/// ends, ids < `points`) into maximal polylines: two segments are chained through a point used
/// by exactly these two segments, and only if `joinable(s, t)` (when given) allows it.
/// Polylines come in the order of their lowest segment; each runs along the direction most of
/// its segments have (all of them for consistently oriented input); a closed one starts at its
/// lowest segment. Linear time; the point degree pass is parallel, the result deterministic.
[[nodiscard]] Polylines join_segments(
    std::span<const Index> segments, std::size_t points,
    const std::function<bool(std::size_t, std::size_t)>& joinable = {});

/// Whether two cells carry bytewise equal tuples in every array of `cell_data` (so a polyline
/// joining their segments can carry one tuple).
class SameCellData {
 public:
  explicit SameCellData(const Attributes& cell_data) : cell_data_(&cell_data) {}
  [[nodiscard]] bool operator()(std::size_t a, std::size_t b) const;

 private:
  const Attributes* cell_data_;
};

}  // namespace isoforge
