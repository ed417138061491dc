#pragma once
// Cutting one cell by F = c (private to filters/cut*.cpp and clip.cpp): the polygons a 3D
// cell gives, as cycles of its crossed edges, found by walking its faces; the segments of a 2D
// cell. Method: docs/algorithms/cut.md ("Cells").

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "isoforge/core/cell.hpp"

namespace isoforge::cutting {

/// An edge of a cell by local point ids; `a` is the end below c (F < c), `b` the end above.
struct LocalEdge {
  int a = 0, b = 0;
};

/// The cut of one 3D cell: `loops` cycles stored one after another in `edges`.
struct PolyhedronCut {
  std::array<LocalEdge, 16> edges{};
  std::array<std::uint8_t, 8> loop_end{};  ///< end (exclusive) of each loop in `edges`
  int loops = 0;
};

/// Sum of values in increasing order: the same for any order of the same values, so the two
/// cells sharing a face decide its ambiguity identically.
inline double order_free_sum(double* v, int n) {
  std::sort(v, v + n);
  double s = 0;
  for (int i = 0; i < n; ++i) s += v[i];
  return s;
}

/// One crossing of a face or polygon boundary, in traversal order.
struct Crossing {
  int slot;  ///< local edge key lo * 8 + hi (3D) or boundary edge index (2D)
  bool enter;         ///< the traversal goes from below to above here
};

/// The pairs (from, to) of crossings joined by cut segments inside a face or polygon whose
/// boundary crossings are `x` (count even, alternating), oriented from the crossing where the
/// traversal enters the region above to the one where it leaves. With more than two crossings
/// the region whose value `center_above` says holds the centre is the connected one.
template <class Emit>
inline void pair_crossings(const Crossing* x, int count, bool center_above, Emit&& emit) {
  if (count == 2) {
    if (x[0].enter) emit(x[0].slot, x[1].slot);
    else emit(x[1].slot, x[0].slot);
    return;
  }
  for (int i = 0; i < count; ++i) {
    // Centre above: the below arcs are cut off, each from a leave to the next enter.
    // Centre below: the above arcs, each from an enter to the next leave.
    const bool start = center_above ? !x[i].enter : x[i].enter;
    if (!start) continue;
    const Crossing& p = x[i];
    const Crossing& q = x[(i + 1) % count];
    if (p.enter) emit(p.slot, q.slot);
    else emit(q.slot, p.slot);
  }
}

/// Cuts a 3D cell with the face table `faces`: `above[i]` says F ≥ c at local point i, `values`
/// are F − c (used only to decide ambiguous quad faces). The loops run so that their normal
/// (right-hand rule) points toward increasing F.
inline void cut_polyhedron(std::span<const CellFace> faces, const bool* above,
                           const double* values, PolyhedronCut& out) {
  std::array<std::int8_t, 64> next;
  next.fill(-1);
  std::array<std::uint8_t, 16> order{};
  int n_order = 0;
  for (const CellFace& face : faces) {
    Crossing x[4];
    int count = 0;
    for (int e = 0; e < face.size; ++e) {
      const int u = face.ids[static_cast<std::size_t>(e)];
      const int w = face.ids[static_cast<std::size_t>((e + 1) % face.size)];
      if (above[u] == above[w]) continue;
      const int lo = std::min(u, w), hi = std::max(u, w);
      x[count++] = {lo * 8 + hi, above[w]};
    }
    if (count == 0) continue;
    bool center_above = false;
    if (count == 4) {
      double v[4];
      for (int e = 0; e < 4; ++e) v[e] = values[face.ids[static_cast<std::size_t>(e)]];
      center_above = order_free_sum(v, 4) >= 0;
    }
    // Traversed with the outward normal, a face's segment runs from its leave crossing to its
    // enter crossing for a loop normal toward increasing F: reverse the enter -> leave pairs.
    pair_crossings(x, count, center_above, [&](int from, int to) {
      if (next[to] < 0 && n_order < 16) order[static_cast<std::size_t>(n_order++)] = to;
      next[to] = static_cast<std::int8_t>(from);
    });
  }
  out.loops = 0;
  int n = 0;
  std::array<bool, 64> seen{};
  for (int i = 0; i < n_order; ++i) {
    int s = order[static_cast<std::size_t>(i)];
    if (seen[static_cast<std::size_t>(s)]) continue;
    while (s >= 0 && !seen[static_cast<std::size_t>(s)] && n < 16) {
      seen[static_cast<std::size_t>(s)] = true;
      const int lo = s / 8, hi = s % 8;
      out.edges[static_cast<std::size_t>(n++)] =
          above[lo] ? LocalEdge{hi, lo} : LocalEdge{lo, hi};
      s = next[static_cast<std::size_t>(s)];
    }
    if (out.loops < 8) out.loop_end[static_cast<std::size_t>(out.loops++)] =
        static_cast<std::uint8_t>(n);
  }
}

/// Cuts a polygon whose boundary visits local points `ring` in order: calls
/// emit(LocalEdge from, LocalEdge to) for each segment. `values` are F − c at the local points.
template <class Emit>
inline void cut_polygon(std::span<const int> ring, const double* values, Emit&& emit,
                        std::vector<Crossing>& x, std::vector<double>& scratch) {
  const int n = static_cast<int>(ring.size());
  x.clear();
  for (int e = 0; e < n; ++e) {
    const int u = ring[static_cast<std::size_t>(e)];
    const int w = ring[static_cast<std::size_t>((e + 1) % n)];
    const bool au = values[u] >= 0, aw = values[w] >= 0;
    if (au == aw) continue;
    x.push_back({e, aw});
  }
  if (x.empty()) return;
  bool center_above = false;
  if (x.size() > 2) {
    scratch.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) scratch[static_cast<std::size_t>(i)] = values[ring[static_cast<std::size_t>(i)]];
    center_above = order_free_sum(scratch.data(), n) >= 0;
  }
  auto edge = [&](int e) {
    const int u = ring[static_cast<std::size_t>(e)];
    const int w = ring[static_cast<std::size_t>((e + 1) % n)];
    return values[u] >= 0 ? LocalEdge{w, u} : LocalEdge{u, w};
  };
  pair_crossings(x.data(), static_cast<int>(x.size()), center_above,
                 [&](int from, int to) { emit(edge(from), edge(to)); });
}

}  // namespace isoforge::cutting
