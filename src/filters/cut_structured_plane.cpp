// The plane fast path of a 3D structured grid (filters/cut.hpp): the output of the general
// path (same points, order, polygons) without storing F at every point or sorting edge keys.
// Method: docs/algorithms/cut.md ("Plane through a structured grid").

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "cut_cells.hpp"
#include "cut_internal.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/core/error.hpp"
#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge::cutting {

namespace {

/// Where a grid line along i crosses F = c: its points [0, xl] are on the side of point 0
/// (`s0`), its points [xr, nx − 1] on the side of the last point (`s1`); xl = nx − 1, xr = 0
/// when it is not crossed.
struct Line {
  std::int32_t xl = 0, xr = 0;
  bool s0 = false, s1 = false;
};

/// F at the points of a grid, as evaluate_at_points computes it (the same expression, so the
/// same doubles as the general path).
struct PlaneValues {
  const float* f = nullptr;
  const Points* pts = nullptr;
  LinearField field;

  [[nodiscard]] double at(std::size_t p) const {
    if (f) {
      return field.a + field.g.x * f[3 * p] + field.g.y * f[3 * p + 1] + field.g.z * f[3 * p + 2];
    }
    return field.a + dot(field.g, (*pts)[p]);
  }
};

struct Counts {
  std::size_t bad = 0, above = 0;
};

/// F at the n float points x (as PlaneValues::at) into v; how many are not finite or exactly c
/// (`bad`), how many ≥ c. Compiled for AVX-512, AVX2 and the baseline (ISOFORGE_SIMD_CLONES;
/// no FMA contraction, so every clone gives the same bits).
ISOFORGE_SIMD_CLONES
Counts float_line(const float* __restrict x, std::size_t n, LinearField field, double c,
                  double* __restrict v) {
  const double a = field.a, gx = field.g.x, gy = field.g.y, gz = field.g.z;
  std::size_t bad = 0, above = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = a + gx * x[3 * i] + gy * x[3 * i + 1] + gz * x[3 * i + 2];
    v[i] = w;
    bad += !(std::abs(w) <= std::numeric_limits<double>::max()) | (w == c);
    above += w >= c;
  }
  return {bad, above};
}

/// Points [lo, hi] of line `a` whose side may differ from that of the same point of line `b`
/// (empty when lo > hi).
std::pair<std::int32_t, std::int32_t> differ_range(const Line& a, const Line& b, std::int32_t nx) {
  const std::int32_t lo = a.s0 != b.s0 ? 0 : std::min(a.xl, b.xl);
  const std::int32_t hi = a.s1 != b.s1 ? nx - 1 : std::max(a.xr, b.xr);
  return {lo, std::min(hi, nx - 1)};
}

/// The cut of a hexahedron for each of the 256 sign cases, from cut_polyhedron with values ±1,
/// and whether the case has a face with four crossings (then the values decide: not tabled).
struct HexCases {
  std::array<PolyhedronCut, 256> cut{};
  std::array<bool, 256> ambiguous{};
  HexCases() {
    const auto faces = cell_faces(CellType::Hexahedron);
    for (int m = 0; m < 256; ++m) {
      bool above[8];
      double vals[8];
      for (int q = 0; q < 8; ++q) above[q] = (m >> q) & 1, vals[q] = above[q] ? 1.0 : -1.0;
      for (const CellFace& f : faces) {
        int crossings = 0;
        for (int e = 0; e < f.size; ++e) {
          crossings += above[f.ids[static_cast<std::size_t>(e)]] !=
                       above[f.ids[static_cast<std::size_t>((e + 1) % f.size)]];
        }
        ambiguous[static_cast<std::size_t>(m)] = ambiguous[static_cast<std::size_t>(m)] || crossings == 4;
      }
      cut_polyhedron(faces, above, vals, cut[static_cast<std::size_t>(m)]);
    }
  }
};

const HexCases& hex_cases() {
  static const HexCases cases;
  return cases;
}

}  // namespace

std::optional<PolyData> cut_structured_plane(const StructuredGrid& sg, const LinearField& field,
                                             double c, const CutOptions& options,
                                             CutStats& stats) {
  const auto nx = static_cast<std::int32_t>(sg.dims[0]);
  const auto ny = static_cast<std::size_t>(sg.dims[1]), nz = static_cast<std::size_t>(sg.dims[2]);
  const auto unx = static_cast<std::size_t>(nx);
  if (sg.dims[0] > std::numeric_limits<std::int32_t>::max() / 2) return std::nullopt;
  const PlaneValues F{sg.points.type() == ScalarType::Float32 ? sg.points.floats().data() : nullptr,
                      &sg.points, field};
  const std::size_t lines = ny * nz;

  // (1) Every line: where it is crossed. A value exactly c or not finite: general path.
  std::vector<Line> line(lines);
  std::atomic<bool> general{false};
  parallel_for_range(
      lines, 64,
      [&](std::size_t l0, std::size_t l1) {
        std::vector<double> v(unx);
        for (std::size_t l = l0; l < l1; ++l) {
          const std::size_t p0 = l * unx;
          std::size_t bad = 0, above = 0;
          if (F.f) {
            const Counts n = float_line(F.f + 3 * p0, unx, field, c, v.data());
            bad = n.bad, above = n.above;
          } else {
            for (std::size_t i = 0; i < unx; ++i) {
              v[i] = F.at(p0 + i);
              bad += int{!(std::abs(v[i]) <= std::numeric_limits<double>::max())} | int{v[i] == c};
              above += v[i] >= c;
            }
          }
          if (bad) {
            general.store(true, std::memory_order_relaxed);
            return;
          }
          Line& L = line[l];
          L.s0 = v[0] >= c, L.s1 = v[unx - 1] >= c;
          L.xl = nx - 1, L.xr = 0;
          if (above == 0 || above == unx) continue;  // not crossed
          std::int32_t i = 0;
          while ((v[static_cast<std::size_t>(i + 1)] >= c) == L.s0) ++i;
          L.xl = i;
          std::int32_t e = nx - 1;
          while ((v[static_cast<std::size_t>(e - 1)] >= c) == L.s1) --e;
          L.xr = e;
        }
      },
      progress_range(options.progress, 0, 0.6), "cut");
  if (general.load()) return std::nullopt;

  // (2) Every line: the range of its points whose +i, +j or +k edge may be crossed, and the
  // crossed edges there counted.
  std::vector<std::int32_t> lo(lines), hi(lines);
  std::vector<std::size_t> count(lines + 1, 0), slots(lines + 1, 0);
  auto crossed = [&](std::size_t p, std::size_t q) { return (F.at(p) >= c) != (F.at(q) >= c); };
  parallel_for_range(lines, 256, [&](std::size_t l0, std::size_t l1) {
    for (std::size_t l = l0; l < l1; ++l) {
      const std::size_t j = l % ny, k = l / ny;
      const Line& L = line[l];
      std::int32_t a = L.xl, b = L.xr;
      if (j + 1 < ny) {
        const auto [u, w] = differ_range(L, line[l + 1], nx);
        if (u <= w) a = std::min(a, u), b = std::max(b, w);
      }
      if (k + 1 < nz) {
        const auto [u, w] = differ_range(L, line[l + ny], nx);
        if (u <= w) a = std::min(a, u), b = std::max(b, w);
      }
      b = std::min(b, nx - 1);
      lo[l] = a, hi[l] = b;
      std::size_t n = 0;
      const std::size_t p0 = l * unx;
      for (std::int32_t i = a; i <= b; ++i) {
        const std::size_t p = p0 + static_cast<std::size_t>(i);
        if (i + 1 < nx) n += crossed(p, p + 1);
        if (j + 1 < ny) n += crossed(p, p + unx);
        if (k + 1 < nz) n += crossed(p, p + unx * ny);
      }
      count[l + 1] = n;
      slots[l + 1] = a <= b ? static_cast<std::size_t>(b - a + 1) : 0;
    }
  });
  for (std::size_t l = 0; l < lines; ++l) count[l + 1] += count[l], slots[l + 1] += slots[l];
  const std::size_t np = count[lines];

  // (3) Points, numbered line by line, point by point, +i, +j, +k: the order of the general
  // path's sorted (lo, hi) keys. `edge_id` holds the ids of the three edges of every point of
  // the ranges (−1: not crossed).
  PolyData result;
  result.points = Points(np, sg.points.type());
  std::vector<std::array<std::int32_t, 3>> edge_id(slots[lines]);
  // The cells' polygons are counted first (their number sizes the cell data).
  const std::size_t cx = unx - 1, cy = ny - 1, rows = cy * (nz - 1);
  std::vector<std::int32_t> clo(rows), chi(rows);
  std::vector<std::size_t> row_polys(rows + 1, 0), row_ids(rows + 1, 0), row_cut(rows + 1, 0);
  const std::size_t dy = unx, dz = unx * ny;
  // Local hexahedron points by their (di, dj, dk): offsets of the general path's ids.
  static constexpr int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  // Rows of cells: the candidate range [clo, chi] from the four lines' crossings.
  std::vector<std::size_t> cand(rows + 1, 0);
  parallel_for_range(rows, 1024, [&](std::size_t r0, std::size_t r1) {
    for (std::size_t r = r0; r < r1; ++r) {
      const std::size_t j = r % cy, k = r / cy, l = j + ny * k;
      const Line* q[4] = {&line[l], &line[l + 1], &line[l + ny], &line[l + ny + 1]};
      bool s0 = false, s1 = false;
      std::int32_t a = nx, b = -1;
      for (const Line* L : q) {
        s0 |= L->s0 != q[0]->s0, s1 |= L->s1 != q[0]->s1;
        a = std::min(a, L->xl), b = std::max(b, L->xr);
      }
      clo[r] = s0 ? 0 : a;
      chi[r] = std::min(s1 ? nx - 2 : b, nx - 2);
      cand[r + 1] = clo[r] <= chi[r] ? static_cast<std::size_t>(chi[r] - clo[r] + 1) : 0;
    }
  });
  for (std::size_t r = 0; r < rows; ++r) cand[r + 1] += cand[r];
  // The sign case of every candidate cell (bit q: local point q above), found once.
  std::vector<std::uint8_t> cases_of(cand[rows]);
  const HexCases& cases = hex_cases();
  // Calls polygon(cell, i, line, cut, start, end) for every polygon of row r, in cell order;
  // returns the number of cells cut. `fill` computes the cases first (from the values of the
  // row's four lines), else they are read.
  auto cell_pass = [&](std::size_t r, bool fill, std::vector<double>& row, auto&& polygon) {
    const std::size_t j = r % cy, k = r / cy;
    const std::size_t l = j + ny * k;
    if (clo[r] > chi[r]) return std::size_t{0};
    const auto w = static_cast<std::size_t>(chi[r] - clo[r] + 1);
    std::uint8_t* mask = cases_of.data() + cand[r];
    if (fill) {
      row.resize(4 * (w + 1));
      for (std::size_t t = 0; t < 4; ++t) {
        const std::size_t p0 = (l + (t & 1) + ny * (t >> 1)) * unx + static_cast<std::size_t>(clo[r]);
        for (std::size_t x = 0; x <= w; ++x) row[t * (w + 1) + x] = F.at(p0 + x);
      }
      for (std::size_t x = 0; x < w; ++x) {
        unsigned m = 0;
        for (int q = 0; q < 8; ++q) {
          const auto t = static_cast<std::size_t>(kCorner[q][1] + 2 * kCorner[q][2]);
          m |= static_cast<unsigned>(row[t * (w + 1) + x + static_cast<std::size_t>(kCorner[q][0])] >= c) << q;
        }
        mask[x] = static_cast<std::uint8_t>(m);
      }
    }
    std::size_t cut = 0;
    double vals[8];
    bool above[8];
    PolyhedronCut own;
    for (std::size_t x = 0; x < w; ++x) {
      const unsigned m = mask[x];
      if (m == 0 || m == 255) continue;
      ++cut;
      const auto i = clo[r] + static_cast<std::int32_t>(x);
      const PolyhedronCut* pcp = &cases.cut[m];
      if (cases.ambiguous[m]) {  // a saddle face: the values decide
        const std::size_t p = l * unx + static_cast<std::size_t>(i);
        for (int q = 0; q < 8; ++q) {
          const std::size_t id = p + static_cast<std::size_t>(kCorner[q][0]) +
                                 dy * static_cast<std::size_t>(kCorner[q][1]) +
                                 dz * static_cast<std::size_t>(kCorner[q][2]);
          vals[q] = F.at(id) - c;
          above[q] = vals[q] >= 0;
        }
        cut_polyhedron(cell_faces(CellType::Hexahedron), above, vals, own);
        pcp = &own;
      }
      const PolyhedronCut& pc = *pcp;
      int start = 0;
      for (int lp = 0; lp < pc.loops; ++lp) {
        const int end = pc.loop_end[static_cast<std::size_t>(lp)];
        polygon(static_cast<std::size_t>(i) + cx * r, i, l, pc, start, end);
        start = end;
      }
    }
    return cut;
  };
  parallel_for_range(rows, 64, [&](std::size_t r0, std::size_t r1) {
    std::vector<double> row;
    for (std::size_t r = r0; r < r1; ++r) {
      std::size_t polys = 0, ids = 0;
      row_cut[r + 1] = cell_pass(r, true, row, [&](std::size_t, std::int32_t, std::size_t,
                                                   const PolyhedronCut&, int start, int end) {
        const auto n = static_cast<std::size_t>(end - start);
        if (options.triangulate) polys += n - 2, ids += 3 * (n - 2);
        else ++polys, ids += n;
      });
      row_polys[r + 1] = polys, row_ids[r + 1] = ids;
    }
  });
  for (std::size_t r = 0; r < rows; ++r) {
    row_polys[r + 1] += row_polys[r], row_ids[r + 1] += row_ids[r], row_cut[r + 1] += row_cut[r];
  }
  const std::size_t npolys = row_polys[rows];

  AttributeInterpolator interp;
  if (options.interpolate_attributes) {
    interp = AttributeInterpolator(sg.point_data, sg.cell_data, np, npolys);
  }
  parallel_for_range(
      lines, 256,
      [&](std::size_t l0, std::size_t l1) {
        for (std::size_t l = l0; l < l1; ++l) {
          const std::size_t j = l % ny, k = l / ny, p0 = l * unx;
          std::size_t id = count[l], slot = slots[l];
          for (std::int32_t i = lo[l]; i <= hi[l]; ++i, ++slot) {
            const std::size_t p = p0 + static_cast<std::size_t>(i);
            const std::size_t ends[3] = {i + 1 < nx ? p + 1 : p, j + 1 < ny ? p + dy : p,
                                         k + 1 < nz ? p + dz : p};
            for (int axis = 0; axis < 3; ++axis) {
              const std::size_t q = ends[axis];
              edge_id[slot][static_cast<std::size_t>(axis)] = -1;
              if (q == p || !crossed(p, q)) continue;
              check_invariant(id < count[l + 1], "cut: more crossed edges than counted");
              const double ga = F.at(p) - c, gb = F.at(q) - c;
              const double t = std::clamp(ga / (ga - gb), 0.0, 1.0);
              const Vec3 pa = sg.points[p], pb = sg.points[q];
              result.points.set(id, pa + (pb - pa) * t);
              interp.interpolate(id, p, q, t);
              edge_id[slot][static_cast<std::size_t>(axis)] = static_cast<std::int32_t>(id - count[l]);
              ++id;
            }
          }
        }
      },
      progress_range(options.progress, 0.6, 0.8), "cut");

  // (4) Polygons, every row at its offsets.
  Buffer<Index> offsets(npolys + 1), conn(row_ids[rows]);
  offsets[0] = 0;
  parallel_for_range(
      rows, 64,
      [&](std::size_t r0, std::size_t r1) {
        std::vector<double> row;
        for (std::size_t r = r0; r < r1; ++r) {
          std::size_t poly = row_polys[r], at = row_ids[r];
          cell_pass(r, false, row, [&](std::size_t cell, std::int32_t i, std::size_t l, const PolyhedronCut& pc,
                           int start, int end) {
            // The output id of local edge e of cell (i, row r): its lower point's line and
            // index, and its axis.
            auto id_of = [&](const LocalEdge& e) -> Index {
              const int* u = kCorner[e.a];
              const int* w = kCorner[e.b];
              const int* m = u[0] + u[1] + u[2] <= w[0] + w[1] + w[2] ? u : w;
              const int axis = u[0] != w[0] ? 0 : (u[1] != w[1] ? 1 : 2);
              const std::size_t ll = l + static_cast<std::size_t>(m[1]) + ny * static_cast<std::size_t>(m[2]);
              const std::int32_t ii = i + m[0];
              check_invariant(ii >= lo[ll] && ii <= hi[ll], "cut: an edge outside its line's range");
              const std::int32_t local =
                  edge_id[slots[ll] + static_cast<std::size_t>(ii - lo[ll])][static_cast<std::size_t>(axis)];
              check_invariant(local >= 0, "cut: a crossed edge without its point");
              return static_cast<Index>(count[ll] + static_cast<std::size_t>(local));
            };
            const auto& edges = pc.edges;
            if (options.triangulate) {
              const Index a = id_of(edges[static_cast<std::size_t>(start)]);
              for (int t = start + 1; t + 1 < end; ++t) {
                conn[at++] = a;
                conn[at++] = id_of(edges[static_cast<std::size_t>(t)]);
                conn[at++] = id_of(edges[static_cast<std::size_t>(t + 1)]);
                offsets[++poly] = static_cast<Index>(at);
                interp.copy_cell(poly - 1, cell);
              }
            } else {
              for (int t = start; t < end; ++t) conn[at++] = id_of(edges[static_cast<std::size_t>(t)]);
              offsets[++poly] = static_cast<Index>(at);
              interp.copy_cell(poly - 1, cell);
            }
          });
        }
      },
      progress_range(options.progress, 0.8, 1.0), "cut");
  result.polys = CellArray(std::move(offsets), std::move(conn));
  interp.move_into(result.point_data, result.cell_data);
  DataArray value_index("CutValueIndex", ScalarType::Int32, 1, np);  // one value: all 0
  result.point_data.add(std::move(value_index));
  stats.cells_cut += row_cut[rows];
  stats.points = np;
  stats.polygons = npolys;
  return result;
}

}  // namespace isoforge::cutting
