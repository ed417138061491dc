// Generation of the marching-cells case tables (see tables.hpp for the construction).

#include "tables.hpp"

#include <algorithm>
#include <stdexcept>

#include "isoforge/core/error.hpp"

namespace isoforge::contour_detail {

namespace {

using P = std::array<double, 3>;

P sub(const P& a, const P& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P crossp(const P& a, const P& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dotp(const P& a, const P& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Reorders every face so it runs counter-clockwise seen from outside the cell.
void orient_faces(CellTopology& t) {
  P center{0, 0, 0};
  for (const auto& p : t.positions)
    for (int i = 0; i < 3; ++i) center[i] += p[static_cast<std::size_t>(i)] / t.corners;
  for (auto& f : t.faces) {
    P n{0, 0, 0}, fc{0, 0, 0};
    for (std::size_t i = 0; i < f.size(); ++i) {
      const P& a = t.positions[static_cast<std::size_t>(f[i])];
      const P& b = t.positions[static_cast<std::size_t>(f[(i + 1) % f.size()])];
      const P c = crossp(a, b);
      for (int k = 0; k < 3; ++k) {
        n[k] += c[k];
        fc[k] += a[k] / static_cast<double>(f.size());
      }
    }
    if (dotp(n, sub(fc, center)) < 0) std::reverse(f.begin(), f.end());
  }
}

int edge_of(const CellTopology& t, int a, int b) {
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    if ((t.edges[e][0] == a && t.edges[e][1] == b) || (t.edges[e][0] == b && t.edges[e][1] == a)) {
      return static_cast<int>(e);
    }
  }
  throw Error("contour tables: face edge missing from the edge list");
}

// Bit f of face_mask[e] is set when edge e is a side of face f.
std::vector<unsigned> face_masks(const CellTopology& t) {
  std::vector<unsigned> mask(t.edges.size(), 0);
  for (std::size_t f = 0; f < t.faces.size(); ++f) {
    const auto& face = t.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      mask[static_cast<std::size_t>(edge_of(t, face[i], face[(i + 1) % face.size()]))] |= 1u << f;
    }
  }
  return mask;
}

// Triangulates the polygon loop[lo..hi] (a contiguous run of the loop, closed by the edge
// loop[hi]-loop[lo]) with no diagonal joining two crossings on a common face: such a diagonal
// would lie in the face, where the neighbouring cell may make the same one (four triangles on an
// edge) or overlap it. Prefers a fan from loop[lo]; tries every apex otherwise.
bool triangulate_range(const std::vector<unsigned>& face_mask, const std::vector<int>& loop, std::size_t lo,
                       std::size_t hi, std::vector<std::array<int, 3>>& out) {
  if (hi - lo < 2) return true;
  // Sides lo-k and k-hi of the triangle (lo, k, hi) are loop sides when adjacent, otherwise new
  // diagonals (lo-hi was checked by the caller, or is the loop's closing side).
  auto diagonal_ok = [&](std::size_t a, std::size_t b) {
    return b - a == 1 ||
           (face_mask[static_cast<std::size_t>(loop[a])] & face_mask[static_cast<std::size_t>(loop[b])]) == 0;
  };
  for (std::size_t k = lo + 1; k < hi; ++k) {
    // Triangle (lo, k, hi): its sides lo-k and k-hi are diagonals unless adjacent on the loop.
    if (!diagonal_ok(lo, k) || !diagonal_ok(k, hi)) continue;
    const std::size_t mark = out.size();
    out.push_back({loop[lo], loop[k], loop[hi]});
    if (triangulate_range(face_mask, loop, lo, k, out) && triangulate_range(face_mask, loop, k, hi, out)) return true;
    out.resize(mark);
  }
  return false;
}

bool triangulate_loop(const std::vector<unsigned>& face_mask, const std::vector<int>& loop,
                      std::vector<std::array<int, 3>>& out) {
  // Try every rotation of the loop (different apexes for the outer triangle).
  for (std::size_t r = 0; r < loop.size(); ++r) {
    std::vector<int> rotated(loop.begin() + static_cast<std::ptrdiff_t>(r), loop.end());
    rotated.insert(rotated.end(), loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(r));
    out.clear();
    if (triangulate_range(face_mask, rotated, 0, rotated.size() - 1, out)) return true;
  }
  return false;
}

}  // namespace

CaseTable::CaseTable(const CellTopology& topology) : topo_(topology) {
  orient_faces(topo_);
  const std::vector<unsigned> face_mask = face_masks(topo_);
  // edge_index[a][b]: the edge joining corners a and b.
  std::vector<std::vector<int>> edge_index(static_cast<std::size_t>(topo_.corners),
                                           std::vector<int>(static_cast<std::size_t>(topo_.corners), -1));
  for (std::size_t e = 0; e < topo_.edges.size(); ++e) {
    edge_index[static_cast<std::size_t>(topo_.edges[e][0])][static_cast<std::size_t>(topo_.edges[e][1])] = static_cast<int>(e);
    edge_index[static_cast<std::size_t>(topo_.edges[e][1])][static_cast<std::size_t>(topo_.edges[e][0])] = static_cast<int>(e);
  }
  const unsigned ncases = 1u << topo_.corners;
  cases_.resize(ncases);
  for (unsigned c = 0; c < ncases; ++c) {
    auto above = [c](int corner) { return ((c >> corner) & 1u) != 0; };
    Case& info = cases_[c];
    std::vector<int> amb;
    for (std::size_t f = 0; f < topo_.faces.size(); ++f) {
      const auto& face = topo_.faces[f];
      if (face.size() != 4) continue;
      if (above(face[0]) == above(face[2]) && above(face[1]) == above(face[3]) &&
          above(face[0]) != above(face[1])) {
        amb.push_back(static_cast<int>(f));
      }
    }
    info.ambiguous = static_cast<std::uint8_t>(amb.size());
    for (std::size_t i = 0; i < amb.size(); ++i) info.faces[i] = static_cast<std::uint8_t>(amb[i]);
    info.first_variant = static_cast<std::uint32_t>(variants_.size());
    for (unsigned bits = 0; bits < (1u << amb.size()); ++bits) {
      // next[e] = the crossing that follows crossing e along its loop.
      std::vector<int> next(topo_.edges.size(), -1);
      for (std::size_t f = 0; f < topo_.faces.size(); ++f) {
        const auto& face = topo_.faces[f];
        const std::size_t n = face.size();
        // Crossings in counter-clockwise order: (edge, is_exit).
        std::vector<std::pair<int, bool>> xs;
        for (std::size_t i = 0; i < n; ++i) {
          const int a = face[i], b = face[(i + 1) % n];
          if (above(a) != above(b)) {
            xs.push_back({edge_index[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)], above(a)});
          }
        }
        if (xs.empty()) continue;
        if (xs.size() == 2) {
          const int from = xs[0].second ? xs[0].first : xs[1].first;
          const int to = xs[0].second ? xs[1].first : xs[0].first;
          next[static_cast<std::size_t>(from)] = to;
          continue;
        }
        // Four crossings on an ambiguous quad face.
        const auto pos = std::find(amb.begin(), amb.end(), static_cast<int>(f)) - amb.begin();
        const bool connect_above = ((bits >> pos) & 1u) != 0;
        for (std::size_t k = 0; k < 4; ++k) {
          if (!xs[k].second) continue;  // start at each exit
          // Cutting off the below runs pairs an exit with the next entry; cutting off the above
          // runs pairs it with the previous entry.
          const std::size_t partner = connect_above ? (k + 1) % 4 : (k + 3) % 4;
          next[static_cast<std::size_t>(xs[k].first)] = xs[partner].first;
        }
      }
      Variant v;
      v.first = static_cast<std::uint32_t>(tri_edges_.size());
      std::vector<bool> used(topo_.edges.size(), false);
      for (std::size_t start = 0; start < next.size(); ++start) {
        if (next[start] < 0 || used[start]) continue;
        std::vector<int> loop;
        for (int e = static_cast<int>(start); !used[static_cast<std::size_t>(e)]; e = next[static_cast<std::size_t>(e)]) {
          used[static_cast<std::size_t>(e)] = true;
          loop.push_back(e);
          if (next[static_cast<std::size_t>(e)] < 0) throw Error("contour tables: open loop");
        }
        std::vector<std::array<int, 3>> tris;
        if (!triangulate_loop(face_mask, loop, tris)) {
          // No triangulation avoids a diagonal on a face: fan around a point inside the cell
          // (the mean of the loop's crossings), numbered after the cell's edges.
          const int center = static_cast<int>(topo_.edges.size() + v.centers);
          tris.clear();
          for (std::size_t i = 0; i < loop.size(); ++i) {
            tris.push_back({center, loop[i], loop[(i + 1) % loop.size()]});
          }
          center_loops_.push_back({static_cast<std::uint32_t>(center_edges_.size()), static_cast<std::uint8_t>(loop.size())});
          for (int e : loop) center_edges_.push_back(static_cast<std::uint8_t>(e));
          if (v.centers == 0) v.first_center = static_cast<std::uint32_t>(center_loops_.size() - 1);
          ++v.centers;
        }
        for (const auto& t : tris) {
          for (int e : t) tri_edges_.push_back(static_cast<std::uint8_t>(e));
          ++v.triangles;
        }
      }
      variants_.push_back(v);
    }
  }
}

const CaseTable& voxel_table() {
  static const CaseTable table = [] {
    CellTopology t;
    t.corners = 8;
    for (int c = 0; c < 8; ++c) t.positions.push_back({double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)});
    t.edges = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    t.faces = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    return CaseTable(t);
  }();
  return table;
}

const CaseTable& tetra_table() {
  static const CaseTable table = [] {
    CellTopology t;
    t.corners = 4;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    t.edges = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    t.faces = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 2, 1}};
    return CaseTable(t);
  }();
  return table;
}

const CaseTable& wedge_table() {
  static const CaseTable table = [] {
    CellTopology t;
    t.corners = 6;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    t.edges = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}, {0, 3}, {1, 4}, {2, 5}};
    t.faces = {{0, 1, 2}, {3, 5, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}};
    return CaseTable(t);
  }();
  return table;
}

const CaseTable& pyramid_table() {
  static const CaseTable table = [] {
    CellTopology t;
    t.corners = 5;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
    t.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {1, 4}, {2, 4}, {3, 4}};
    t.faces = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    return CaseTable(t);
  }();
  return table;
}

}  // namespace isoforge::contour_detail
