// Self-intersections of triangle meshes and the dynamic triangle grid (self_intersections.hpp).
//
// Candidates come from a uniform grid of the triangles' bounding boxes: each triangle looks at
// the cells its box covers and keeps the later triangles whose boxes meet its own, taking a pair
// only in the cell of the lower corner of the two boxes' intersection, so each pair is tested
// once. The test itself is core/predicates.hpp's exact faces_intersect. Method:
// docs/algorithms/predicates.md.

#include "isoforge/spatial/self_intersections.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <string>

#include "isoforge/core/error.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/predicates.hpp"

namespace isoforge {

namespace {

constexpr int kMaxDim = (1 << 21) - 1;      // cells per axis: keys pack three 21-bit indices
constexpr double kCellsPerFace = 4;         // grid size bound of triangle_grid_cell_size
constexpr std::size_t kPairBlock = 512;         // triangles per result block (results in order)
constexpr std::size_t kBlocksPerWave = 64;  // blocks between progress reports / max_pairs checks

// The float next to f toward −∞ / +∞ (f not NaN; ±∞ step to ±FLT_MAX), inline: the box of
// every grid query is rounded through these, and the library call was a tenth of a query.
float next_down(float f) {
  if (f == 0) return -std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0 ? bits - 1 : bits + 1);
}
float next_up(float f) {
  if (f == 0) return std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0 ? bits + 1 : bits - 1);
}
float round_down(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? next_down(f) : f;
}
float round_up(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? next_up(f) : f;
}

// Cells along one axis for an extent, or 0 when there would be more than kMaxDim.
int cells_along(double extent, double cell) {
  const double n = std::floor(extent / cell) + 1;
  return n > kMaxDim ? 0 : static_cast<int>(n);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// TriangleGrid

TriangleGrid::TriangleGrid(const Bounds& bounds, double cell_size) {
  if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max)) {
    throw Error("TriangleGrid: the bounds are empty or not finite");
  }
  if (!(cell_size > 0) || !std::isfinite(cell_size)) {
    throw Error("TriangleGrid: cell size " + std::to_string(cell_size) +
                " is not positive and finite");
  }
  cell_size_ = cell_size;
  inv_cell_ = 1.0 / cell_size;
  for (int a = 0; a < 3; ++a) {
    origin_[a] = bounds.min[a];
    dims_[a] = cells_along(bounds.max[a] - bounds.min[a], cell_size);
    if (dims_[a] == 0) {
      throw Error("TriangleGrid: cell size " + std::to_string(cell_size) +
                  " is too small for the bounds (more than 2^21 cells along an axis)");
    }
  }
  slots_.assign(64, Slot{});
  mask_ = 63;
  shift_ = 64 - 6;
}

TriangleGrid::Box TriangleGrid::box_of(const Vec3& lo, const Vec3& hi) const {
  if (!is_finite(lo) || !is_finite(hi)) throw Error("TriangleGrid: a box is not finite");
  Box b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = round_down(lo[a]);
    b.hi[a] = round_up(hi[a]);
    b.c0[a] = cell_of(b.lo[a], a);
    b.c1[a] = cell_of(b.hi[a], a);
  }
  return b;
}

void TriangleGrid::grow() {
  std::vector<Slot> old = std::move(slots_);
  slots_.assign(old.size() * 2, Slot{});
  mask_ = slots_.size() - 1;
  --shift_;
  for (const Slot& slot : old) {
    if (slot.key == kEmpty) continue;
    std::size_t t = slot_of(slot.key);
    while (slots_[t].key != kEmpty) t = (t + 1) & mask_;
    slots_[t] = slot;
  }
}

std::vector<TriangleGrid::Entry>& TriangleGrid::find_or_add(Key key) {
  for (std::size_t s = slot_of(key);; s = (s + 1) & mask_) {
    if (slots_[s].key == key) return lists_[slots_[s].list];
    if (slots_[s].key == kEmpty) {
      // Occupied cells stay in the table (their lists may empty and refill): no tombstones.
      if (2 * (lists_.size() + 1) > slots_.size()) {
        grow();
        return find_or_add(key);
      }
      slots_[s] = {key, static_cast<std::uint32_t>(lists_.size())};
      lists_.emplace_back();
      return lists_.back();
    }
  }
}

void TriangleGrid::insert(std::uint32_t face, const Vec3& lo, const Vec3& hi) {
  const Box b = box_of(lo, hi);
  Entry e{face, {b.lo[0], b.lo[1], b.lo[2]}, {b.hi[0], b.hi[1], b.hi[2]}};
  for (int k = b.c0[2]; k <= b.c1[2]; ++k) {
    for (int j = b.c0[1]; j <= b.c1[1]; ++j) {
      for (int i = b.c0[0]; i <= b.c1[0]; ++i) find_or_add(key_of(i, j, k)).push_back(e);
    }
  }
  ++faces_;
}

void TriangleGrid::remove(std::uint32_t face, const Vec3& lo, const Vec3& hi) {
  const Box b = box_of(lo, hi);
  for (int k = b.c0[2]; k <= b.c1[2]; ++k) {
    for (int j = b.c0[1]; j <= b.c1[1]; ++j) {
      for (int i = b.c0[0]; i <= b.c1[0]; ++i) {
        auto* list = const_cast<std::vector<Entry>*>(find(key_of(i, j, k)));
        bool found = false;
        if (list != nullptr) {
          for (std::size_t n = 0; n < list->size(); ++n) {
            if ((*list)[n].face == face) {
              (*list)[n] = list->back();
              list->pop_back();
              found = true;
              break;
            }
          }
        }
        if (!found) {
          throw Error("TriangleGrid::remove: face " + std::to_string(face) +
                      " is not in the cells of the given box");
        }
      }
    }
  }
  --faces_;
}

// ---------------------------------------------------------------------------------------------
// Cell sizes

double triangle_grid_cell_size(const Bounds& bounds, std::size_t faces, double mean_edge) {
  const double diagonal = bounds.diagonal();
  double cell = 2 * mean_edge;
  if (!(cell > 0) || !std::isfinite(cell)) cell = diagonal > 0 ? diagonal / 16 : 1;
  if (bounds.empty() || !(diagonal > 0) || !std::isfinite(diagonal)) return cell;
  const double max_cells = std::max(1.0, kCellsPerFace * static_cast<double>(faces));
  const Vec3 size = bounds.size();
  for (int iteration = 0; iteration < 200; ++iteration) {
    double cells = 1;
    bool fits = true;
    for (int a = 0; a < 3; ++a) {
      const double n = std::floor(size[a] / cell) + 1;
      fits = fits && n <= kMaxDim;
      cells *= n;
    }
    if (fits && cells <= max_cells) break;
    cell *= 1.25;
  }
  return cell;
}

double triangle_grid_cell_size(const PolyData& mesh) {
  mesh.polys.validate(mesh.points.size(), "triangle_grid_cell_size: polys");
  mesh.strips.validate(mesh.points.size(), "triangle_grid_cell_size: strips");
  const auto tris = triangulate_faces(mesh);
  Bounds bounds;
  double length = 0;
  for (const auto& t : tris) {
    const Vec3 p[3] = {mesh.points[static_cast<std::size_t>(t[0])],
                       mesh.points[static_cast<std::size_t>(t[1])],
                       mesh.points[static_cast<std::size_t>(t[2])]};
    for (int k = 0; k < 3; ++k) {
      bounds.extend(p[k]);
      length += norm(p[(k + 1) % 3] - p[k]);
    }
  }
  const double mean = tris.empty() ? 0 : length / (3.0 * static_cast<double>(tris.size()));
  return triangle_grid_cell_size(bounds, tris.size(), mean);
}

// ---------------------------------------------------------------------------------------------
// self_intersections

std::vector<std::pair<Index, Index>> self_intersections(const PolyData& mesh,
                                                        const SelfIntersectionOptions& options) {
  mesh.polys.validate(mesh.points.size(), "self_intersections: polys");
  mesh.strips.validate(mesh.points.size(), "self_intersections: strips");
  const auto tris = triangulate_faces(mesh);
  const std::size_t nf = tris.size();
  if (nf >= std::numeric_limits<std::uint32_t>::max()) {
    throw Error("self_intersections: " + std::to_string(nf) + " triangles (2^32 or more)");
  }
  std::vector<std::pair<Index, Index>> result;
  if (nf < 2) return result;

  const std::size_t np = mesh.points.size();
  std::vector<Vec3> pts(np);
  parallel_for_range(np, 1 << 14, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) pts[i] = mesh.points[i];
  });

  // Faces with an interior, their boxes and the mean edge length.
  struct Face {
    std::array<Vec3, 3> p;
    Vec3 lo, hi;
  };
  std::vector<Face> faces(nf);
  std::vector<char> valid(nf, 0);
  parallel_for_range(nf, 1 << 12, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const auto& t = tris[f];
      Face& face = faces[f];
      for (int k = 0; k < 3; ++k) face.p[k] = pts[static_cast<std::size_t>(t[k])];
      face.lo = face.hi = face.p[0];
      for (int k = 1; k < 3; ++k) {
        for (int a = 0; a < 3; ++a) {
          face.lo[a] = std::min(face.lo[a], face.p[k][a]);
          face.hi[a] = std::max(face.hi[a], face.p[k][a]);
        }
      }
      const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
      const bool finite = is_finite(face.p[0]) && is_finite(face.p[1]) && is_finite(face.p[2]);
      valid[f] = finite && !repeated && !triangle_degenerate(face.p[0], face.p[1], face.p[2]);
      if (!finite) valid[f] = 2;  // reported below, from the calling thread
    }
  });
  Bounds bounds;
  double length = 0;
  std::size_t counted = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    if (valid[f] == 2) {
      throw Error("self_intersections: triangle " + std::to_string(f) +
                  " has a point that is not finite");
    }
    if (!valid[f]) continue;
    bounds.extend(faces[f].lo);
    bounds.extend(faces[f].hi);
    const auto& p = faces[f].p;
    length += norm(p[1] - p[0]) + norm(p[2] - p[1]) + norm(p[0] - p[2]);
    ++counted;
  }
  if (counted < 2) return result;
  const double cell = triangle_grid_cell_size(bounds, counted, length / (3.0 * double(counted)));

  // A static grid in compressed rows: the cells of each face's box.
  int dims[3];
  for (int a = 0; a < 3; ++a) {
    dims[a] = cells_along(bounds.max[a] - bounds.min[a], cell);
    check_invariant(dims[a] > 0, "grid dimensions within 2^21");
  }
  const double inv = 1.0 / cell;
  const auto cell_of = [&](double x, int a) {
    const double t = std::floor((x - bounds.min[a]) * inv);
    return t <= 0 ? 0 : (t >= dims[a] - 1 ? dims[a] - 1 : static_cast<int>(t));
  };
  struct CellRange {
    int c0[3], c1[3];
  };
  std::vector<CellRange> ranges(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    if (!valid[f]) continue;
    for (int a = 0; a < 3; ++a) {
      ranges[f].c0[a] = cell_of(faces[f].lo[a], a);
      ranges[f].c1[a] = cell_of(faces[f].hi[a], a);
    }
  }
  const auto linear = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims[0]) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(k));
  };
  const std::size_t ncells = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
                             static_cast<std::size_t>(dims[2]);
  std::vector<std::size_t> start(ncells + 1, 0);
  const auto for_cells = [&](const CellRange& r, auto&& fn) {
    for (int k = r.c0[2]; k <= r.c1[2]; ++k)
      for (int j = r.c0[1]; j <= r.c1[1]; ++j)
        for (int i = r.c0[0]; i <= r.c1[0]; ++i) fn(i, j, k);
  };
  for (std::size_t f = 0; f < nf; ++f) {
    if (valid[f]) for_cells(ranges[f], [&](int i, int j, int k) { ++start[linear(i, j, k) + 1]; });
  }
  for (std::size_t c = 0; c < ncells; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> members(start[ncells]);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f) {  // in face order: each cell lists faces ascending
      if (!valid[f]) continue;
      for_cells(ranges[f], [&](int i, int j, int k) {
        members[fill[linear(i, j, k)]++] = static_cast<std::uint32_t>(f);
      });
    }
  }

  // Each face tests the later faces in its cells; results by blocks of faces, in order.
  const std::size_t nblocks = (nf + kPairBlock - 1) / kPairBlock;
  std::vector<std::vector<std::pair<Index, Index>>> found(nblocks);
  const auto run_block = [&](std::size_t block) {
    auto& out = found[block];
    const std::size_t end = std::min(nf, (block + 1) * kPairBlock);
    for (std::size_t f = block * kPairBlock; f < end; ++f) {
      if (!valid[f]) continue;
      const Face& a = faces[f];
      const CellRange& ra = ranges[f];
      const std::size_t first = out.size();
      for_cells(ra, [&](int i, int j, int k) {
        const std::size_t c = linear(i, j, k);
        // Members are ascending: skip to the faces after f.
        const std::uint32_t* m = members.data() + start[c];
        const std::uint32_t* m_end = members.data() + start[c + 1];
        m = std::upper_bound(m, m_end, static_cast<std::uint32_t>(f));
        for (; m != m_end; ++m) {
          const std::size_t g = *m;
          const Face& b = faces[g];
          if (b.lo.x > a.hi.x || b.hi.x < a.lo.x || b.lo.y > a.hi.y || b.hi.y < a.lo.y ||
              b.lo.z > a.hi.z || b.hi.z < a.lo.z) {
            continue;
          }
          const CellRange& rb = ranges[g];
          if (i != std::max(ra.c0[0], rb.c0[0]) || j != std::max(ra.c0[1], rb.c0[1]) ||
              k != std::max(ra.c0[2], rb.c0[2])) {
            continue;  // the pair is tested in another cell
          }
          if (faces_intersect(a.p, tris[f], b.p, tris[g])) {
            out.emplace_back(static_cast<Index>(f), static_cast<Index>(g));
          }
        }
      });
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
    }
  };
  std::size_t total = 0;
  for (std::size_t wave = 0; wave < nblocks; wave += kBlocksPerWave) {
    const std::size_t wave_end = std::min(nblocks, wave + kBlocksPerWave);
    parallel_for_range(wave_end - wave, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t block = wave + b; block < wave + e; ++block) run_block(block);
    });
    for (std::size_t block = wave; block < wave_end; ++block) total += found[block].size();
    report_progress(options.progress, static_cast<double>(wave_end) / static_cast<double>(nblocks),
                    "self_intersections");
    if (options.max_pairs != 0 && total >= options.max_pairs) {
      found.resize(wave_end);
      break;
    }
  }
  result.reserve(total);
  for (const auto& block : found) result.insert(result.end(), block.begin(), block.end());
  if (options.max_pairs != 0 && result.size() > options.max_pairs) result.resize(options.max_pairs);
  return result;
}

}  // namespace isoforge
