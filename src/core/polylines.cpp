// Joining segments into polylines (core/polylines.hpp).

#include "isoforge/core/polylines.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <limits>

namespace isoforge {

Polylines join_segments(std::span<const Index> segments, std::size_t points,
                        const std::function<bool(std::size_t, std::size_t)>& joinable) {
  const std::size_t ns = segments.size() / 2;
  // Per point, its two segments when it has exactly two (else none), each stored as s when the
  // point is the segment's first point and ~s when it is its second, with the segment's other
  // point: a walk along a chain reads one record per step. The slots are filled in parallel;
  // their order within a record never matters.
  constexpr Index kNone = std::numeric_limits<Index>::min();
  struct Link {
    Index seg[2];
    Index far[2];
  };
  Buffer<Link> links(points);
  Buffer<std::uint32_t> degree(points);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p != r.end(); ++p) degree[p] = 0;
                    });
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, ns, 1 << 14),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t s = r.begin(); s != r.end(); ++s) {
          for (std::size_t e = 0; e < 2; ++e) {
            const auto p = static_cast<std::size_t>(segments[2 * s + e]);
            const std::uint32_t slot =
                std::atomic_ref<std::uint32_t>(degree[p]).fetch_add(1, std::memory_order_relaxed);
            if (slot < 2) {
              links[p].seg[slot] = e == 0 ? static_cast<Index>(s) : ~static_cast<Index>(s);
              links[p].far[slot] = segments[2 * s + 1 - e];
            }
          }
        }
      });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points, 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p != r.end(); ++p) {
                        if (degree[p] != 2) links[p].seg[0] = links[p].seg[1] = kNone;
                      }
                    });
  degree = {};
  auto decode = [](Index v) { return v >= 0 ? v : ~v; };
  // From segment `cur` through point p: the next segment (or -1), whether it starts at p, and
  // its other point.
  struct Step {
    Index seg;
    bool starts;
    Index far;
  };
  auto step = [&](std::size_t cur, Index p) -> Step {
    const Link& l = links[static_cast<std::size_t>(p)];
    if (l.seg[0] == kNone) return {-1, false, 0};
    const int k = decode(l.seg[0]) == static_cast<Index>(cur) ? 1 : 0;
    const Index n = decode(l.seg[k]);
    if (joinable && !joinable(cur, static_cast<std::size_t>(n))) return {-1, false, 0};
    return {n, l.seg[k] >= 0, l.far[k]};
  };
  Polylines out;
  std::vector<std::uint8_t> used(ns, 0);
  std::vector<Index> back;
  out.offsets.reserve(ns / 8 + 1);
  out.connectivity.reserve(ns + ns / 8 + 1);
  for (std::size_t s = 0; s < ns; ++s) {
    if (used[s]) continue;
    used[s] = 1;
    // Forward from s until a free end, or around a loop back to s. (Chains are paths or cycles,
    // so a walk meets no used segment other than s.)
    const std::size_t mark = out.connectivity.size();
    std::size_t forward = 1, backward = 0;
    Index p = segments[2 * s + 1];
    out.connectivity.push_back(segments[2 * s]);
    out.connectivity.push_back(p);
    bool loop = false;
    for (std::size_t cur = s;;) {
      const Step n = step(cur, p);
      if (n.seg < 0) break;
      if (static_cast<std::size_t>(n.seg) == s) {
        loop = true;
        break;
      }
      cur = static_cast<std::size_t>(n.seg);
      used[cur] = 1;
      (n.starts ? forward : backward) += 1;
      p = n.far;
      out.connectivity.push_back(p);
    }
    if (!loop) {
      // Open: prepend the part behind s's first point.
      back.clear();
      p = segments[2 * s];
      for (std::size_t cur = s;;) {
        const Step n = step(cur, p);
        if (n.seg < 0) break;
        cur = static_cast<std::size_t>(n.seg);
        used[cur] = 1;
        (n.starts ? backward : forward) += 1;  // walked against the chain's direction
        p = n.far;
        back.push_back(p);
      }
      if (!back.empty()) {
        out.connectivity.insert(out.connectivity.begin() + static_cast<std::ptrdiff_t>(mark),
                                back.rbegin(), back.rend());
      }
    }
    // Along the direction most segments have; ties keep s's own direction.
    if (backward > forward) {
      std::reverse(out.connectivity.begin() + static_cast<std::ptrdiff_t>(mark),
                   out.connectivity.end());
    }
    out.offsets.push_back(static_cast<Index>(out.connectivity.size()));
    out.first.push_back(s);
  }
  return out;
}

bool SameCellData::operator()(std::size_t a, std::size_t b) const {
  if (a == b) return true;
  for (const DataArray& arr : *cell_data_) {
    const std::size_t tb = scalar_size(arr.type()) * static_cast<std::size_t>(arr.components());
    if (std::memcmp(arr.bytes() + a * tb, arr.bytes() + b * tb, tb) != 0) return false;
  }
  return true;
}

}  // namespace isoforge
