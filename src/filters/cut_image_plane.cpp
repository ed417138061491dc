// The plane fast path of cutting 3D image data (filters/cut.hpp, docs/algorithms/cut.md).
//
// Reference: W. Schroeder, R. Maynard, B. Geveci, "Flying edges: A high-performance scalable
// isocontouring algorithm", IEEE LDAV 2015 — the organisation in passes over grid lines with
// prefix sums, so every output is written in place by independent rows. A plane crosses each
// grid line at most once, so here the passes visit lines (O(n²)) and only the voxels the plane
// crosses, never the whole volume.
//
// The value at grid point (i, j, k) is computed as ((X[i] + Y[j]) + Z[k]) in that order, a
// fixed rounding that is monotone along each axis: every grid line is crossed at most once and
// no quad face can have the ambiguous diagonal pattern.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <vector>

#include "cut_cells.hpp"
#include "cut_internal.hpp"
#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/prefetch.hpp"

namespace isoforge::cutting {

namespace {

/// Per voxel case: its polygons as voxel edges (built once from the face walker). An edge is
/// coded axis * 4 + the offsets of its first point along the two other axes (lower axis first).
struct VoxelTable {
  std::array<std::array<std::uint8_t, 16>, 256> edges{};
  std::array<std::array<std::uint8_t, 4>, 256> sizes{};
  std::array<std::uint8_t, 256> loops{};
  VoxelTable() {
    const auto faces = cell_faces(CellType::Voxel);
    for (int cs = 1; cs < 255; ++cs) {
      bool above[8];
      double values[8];
      for (int n = 0; n < 8; ++n) {
        above[n] = (cs >> n) & 1;
        values[n] = above[n] ? 1 : -1;
      }
      PolyhedronCut pc;
      cut_polyhedron(faces, above, values, pc);
      int start = 0;
      const auto c = static_cast<std::size_t>(cs);
      for (int l = 0; l < pc.loops; ++l) {
        const int end = pc.loop_end[static_cast<std::size_t>(l)];
        for (int e = start; e < end; ++e) {
          const LocalEdge le = pc.edges[static_cast<std::size_t>(e)];
          const int lo = std::min(le.a, le.b), bit = le.a ^ le.b;
          const int di = lo & 1, dj = (lo >> 1) & 1, dk = (lo >> 2) & 1;
          const int code = bit == 1 ? 0 * 4 + dj + 2 * dk : (bit == 2 ? 1 * 4 + di + 2 * dk : 2 * 4 + di + 2 * dj);
          edges[c][static_cast<std::size_t>(e)] = static_cast<std::uint8_t>(code);
        }
        sizes[c][static_cast<std::size_t>(l)] = static_cast<std::uint8_t>(end - start);
        start = end;
      }
      loops[c] = static_cast<std::uint8_t>(pc.loops);
    }
  }
};

const VoxelTable& voxel_table() {
  static const VoxelTable table;
  return table;
}

}  // namespace

std::optional<PolyData> cut_image_plane(const ImageData& image, const LinearField& field,
                                        double c, int value_index, const CutOptions& options) {
  const Index nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  if (std::max({nx * ny, ny * nz, nx * nz}) >= (Index{1} << 29) || std::max({nx, ny, nz}) >= (Index{1} << 30)) {
    return std::nullopt;  // beyond the 32-bit line data: the general path
  }
  const Vec3 o = image.origin, s = image.spacing;
  const double A = field.a + dot(field.g, o) - c;
  const double dx = field.g.x * s.x, dy = field.g.y * s.y, dz = field.g.z * s.z;
  std::vector<double> X(static_cast<std::size_t>(nx)), Y(static_cast<std::size_t>(ny)),
      Z(static_cast<std::size_t>(nz));
  for (Index i = 0; i < nx; ++i) X[static_cast<std::size_t>(i)] = A + static_cast<double>(i) * dx;
  for (Index j = 0; j < ny; ++j) Y[static_cast<std::size_t>(j)] = static_cast<double>(j) * dy;
  for (Index k = 0; k < nz; ++k) Z[static_cast<std::size_t>(k)] = static_cast<double>(k) * dz;
  auto G = [&](Index i, Index j, Index k) {
    return (X[static_cast<std::size_t>(i)] + Y[static_cast<std::size_t>(j)]) +
           Z[static_cast<std::size_t>(k)];
  };

  // Pass 1: where the plane crosses each grid row along x (row r = j + ny k). `lead[r]`: the
  // number of leading points of the row, those on the side it starts from in the direction of
  // increase (below, G < 0, when dx >= 0; above otherwise). Every side of every grid point
  // follows from these numbers, since G is monotone along x: point i of row r is above iff
  // i >= lead[r] (rising) or i < lead[r] (falling). 32-bit: memory traffic is most of the cost.
  const bool rising = dx >= 0;
  const std::size_t grid_rows = static_cast<std::size_t>(ny * nz);
  Buffer<std::int32_t> lead(grid_rows);
  std::atomic<bool> exact{false};
  const double inv_dx = dx != 0 ? 1 / dx : 0;
  parallel_for_range(grid_rows, 4096, [&](std::size_t r0, std::size_t r1) {
    bool zero = false;
    for (std::size_t r = r0; r < r1; ++r) {
      const Index j = static_cast<Index>(r) % ny, k = static_cast<Index>(r) / ny;
      const double yz = Y[static_cast<std::size_t>(j)], zk = Z[static_cast<std::size_t>(k)];
      auto value = [&](Index i) { return (X[static_cast<std::size_t>(i)] + yz) + zk; };
      auto leading = [&](Index i) { return rising ? value(i) < 0 : value(i) >= 0; };
      // From the real crossing -G(0) / dx, stepped to where the rounded values switch.
      Index lo = 0;
      if (dx != 0) {
        const double t = std::ceil(-value(0) * inv_dx);
        lo = t <= 0 ? 0 : (t >= static_cast<double>(nx) ? nx : static_cast<Index>(t));
      } else {
        lo = leading(0) ? nx : 0;
      }
      while (lo > 0 && !leading(lo - 1)) --lo;
      while (lo < nx && leading(lo)) ++lo;
      lead[r] = static_cast<std::int32_t>(lo);
      // Zeros of a monotone row sit next to its switch: at lo (rising) or lo - 1 (falling).
      zero = zero || (lo < nx && value(lo) == 0) || (lo > 0 && value(lo - 1) == 0);
    }
    if (zero) exact.store(true, std::memory_order_relaxed);
  });
  if (exact.load()) return std::nullopt;

  // The output points are the crossed grid edges, owned by grid rows: row r owns its x edge
  // crossing (if any), then the y edges (i, j, k)-(i, j + 1, k) and the z edges
  // (i, j, k)-(i, j, k + 1) it starts, for i in a range given by two leads.
  auto x_points = [&](std::size_t r) -> Index { return lead[r] > 0 && lead[r] < nx ? 1 : 0; };
  auto span_of = [&](std::size_t r, std::size_t q) {  // edges between rows r and q: [lo, hi)
    const Index a = lead[r], b = lead[q];
    return std::pair<Index, Index>{std::min(a, b), std::max(a, b)};
  };
  // The prefix counts of grid rows (points) and voxel rows (polygons, ids) share one block: on
  // small pages each array would be first touched with hundreds of page faults.
  const Index cx = nx - 1, cy = ny - 1, cz = nz - 1;
  const std::size_t rows = static_cast<std::size_t>(cy * cz);
  Buffer<std::size_t> counts(grid_rows + 1 + 2 * (rows + 1));
  std::size_t* const row_points = counts.data();
  std::size_t* const row_polys = row_points + grid_rows + 1;
  std::size_t* const row_ids = row_polys + rows + 1;
  row_points[0] = 0;
  parallel_for_range(grid_rows, 4096, [&](std::size_t r0, std::size_t r1) {
    for (std::size_t r = r0; r < r1; ++r) {
      const Index j = static_cast<Index>(r) % ny, k = static_cast<Index>(r) / ny;
      Index count = x_points(r);
      if (j + 1 < ny) {
        const auto [lo, hi] = span_of(r, r + 1);
        count += hi - lo;
      }
      if (k + 1 < nz) {
        const auto [lo, hi] = span_of(r, r + static_cast<std::size_t>(ny));
        count += hi - lo;
      }
      row_points[r + 1] = static_cast<std::size_t>(count);
    }
  });
  for (std::size_t r = 0; r < grid_rows; ++r) row_points[r + 1] += row_points[r];
  const std::size_t np = row_points[grid_rows];

  // Pass 2: count the polygons of each voxel row (j, k), over its active range only.
  const VoxelTable& table = voxel_table();
  row_polys[0] = row_ids[0] = 0;
  // The grid rows of voxel row (j, k)'s corners q = di + 2 dj + 4 dk (without di).
  auto corner_rows = [&](Index j, Index k, std::size_t (&g)[4]) {
    for (int q = 0; q < 4; ++q) {
      g[q] = static_cast<std::size_t>((j + (q & 1)) + ny * (k + (q >> 1)));
    }
  };
  // Case of voxel i: bit di + 2 dj + 4 dk set when that corner is above.
  auto voxel_case = [&](Index i, const Index (&b)[4]) {
    int cs = 0;
    for (int q = 0; q < 4; ++q) {
      const bool a0 = rising ? i >= b[q] : i < b[q];
      const bool a1 = rising ? i + 1 >= b[q] : i + 1 < b[q];
      const int bit = (q & 1) * 2 + (q >> 1) * 4;
      cs |= (a0 ? 1 << bit : 0) | (a1 ? 2 << bit : 0);
    }
    return cs;
  };
  // The voxels of a row with corners on both sides: between the switches of its 4 grid rows.
  auto active = [&](const Index (&b)[4]) {
    const Index lo = std::min({b[0], b[1], b[2], b[3]}), hi = std::max({b[0], b[1], b[2], b[3]});
    return std::pair<Index, Index>{std::max<Index>(lo - 1, 0), std::min<Index>(hi - 1, cx - 1)};
  };
  auto leads_of = [&](std::size_t r, std::size_t (&g)[4], Index (&b)[4]) {
    const Index j = static_cast<Index>(r) % cy, k = static_cast<Index>(r) / cy;
    corner_rows(j, k, g);
    for (int q = 0; q < 4; ++q) b[q] = lead[g[q]];
  };
  parallel_for_range(rows, 1024, [&](std::size_t r0, std::size_t r1) {
    std::size_t g[4];
    Index b[4];
    for (std::size_t r = r0; r < r1; ++r) {
      leads_of(r, g, b);
      const auto [i0, i1] = active(b);
      std::size_t polys = 0, vids = 0;
      for (Index i = i0; i <= i1; ++i) {
        const auto cs = static_cast<std::size_t>(voxel_case(i, b));
        for (int l = 0; l < table.loops[cs]; ++l) {
          const std::size_t sz = table.sizes[cs][static_cast<std::size_t>(l)];
          polys += options.triangulate ? sz - 2 : 1;
          vids += options.triangulate ? 3 * (sz - 2) : sz;
        }
      }
      row_polys[r + 1] = polys, row_ids[r + 1] = vids;
    }
  });
  for (std::size_t r = 0; r < rows; ++r) {
    row_polys[r + 1] += row_polys[r];
    row_ids[r + 1] += row_ids[r];
  }
  const std::size_t npolys = row_polys[rows], nids = row_ids[rows];

  PolyData out;
  out.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, np));
  Buffer<Index> offsets(npolys + 1), conn(nids);
  offsets[0] = 0;
  AttributeInterpolator interp;
  if (options.interpolate_attributes) {
    interp = AttributeInterpolator(image.point_data, image.cell_data, np, npolys);
  }
  // Pass 3: the polygons, written in place. The point of a voxel edge is found in the grid row
  // that owns it (see above).
  const bool cell_arrays = interp.has_cell_arrays();
  parallel_for_range(rows, 1024, [&](std::size_t r0, std::size_t r1) {
    Index loop[16];
    std::size_t g[4];
    Index b[4];
    for (std::size_t r = r0; r < r1; ++r) {
      if (row_polys[r + 1] == row_polys[r]) continue;
      leads_of(r, g, b);
      const Index j = static_cast<Index>(r) % cy, k = static_cast<Index>(r) / cy;
      std::size_t p = row_polys[r], at = row_ids[r];
      // Per edge code: the owning grid row's first point id and the start of its range, so
      // that id = base + (i + di) - start (x edges: the row's single crossing, start = i).
      Index base[12], start[12];
      for (int q = 0; q < 4; ++q) {
        const auto e = static_cast<std::size_t>(q);
        // x edges: code dj + 2 dk, grid row g[code].
        base[e] = static_cast<Index>(row_points[g[e]]);
        // y edges: code 4 + di + 2 dk, grid row (j, k + dk) = g[2 dk]; y points follow x's.
        const std::size_t gy = g[(q >> 1) * 2];
        base[4 + e] = static_cast<Index>(row_points[gy]) + x_points(gy);
        start[4 + e] = span_of(gy, gy + 1).first - (q & 1);
        // z edges: code 8 + di + 2 dj, grid row (j + dj, k) = g[dj]; z points follow y's.
        const std::size_t gz = g[q >> 1];
        Index before = x_points(gz);
        if (j + (q >> 1) + 1 < ny) {
          const auto [lo, hi] = span_of(gz, gz + 1);
          before += hi - lo;
        }
        base[8 + e] = static_cast<Index>(row_points[gz]) + before;
        start[8 + e] = span_of(gz, gz + static_cast<std::size_t>(ny)).first - (q & 1);
      }
      const auto [i0, i1] = active(b);
      for (Index i = i0; i <= i1; ++i) {
        const auto cs = static_cast<std::size_t>(voxel_case(i, b));
        const int loops = table.loops[cs];
        if (loops == 0) continue;
        const Index cell = i + cx * (j + cy * k);
        std::size_t e = 0;
        for (int l = 0; l < loops; ++l) {
          const int sz = table.sizes[cs][static_cast<std::size_t>(l)];
          // Polygons are written straight into the connectivity (a copy through `loop` became
          // a `rep movs`, slow for 3 to 6 ids); triangles fan out of `loop`.
          Index* const ids = options.triangulate ? loop : conn.data() + at;
          for (int q = 0; q < sz; ++q, ++e) {
            const auto code = static_cast<std::size_t>(table.edges[cs][e]);
            ids[q] = code < 4 ? base[code] : base[code] + i - start[code];
          }
          if (options.triangulate) {
            for (int t = 1; t + 1 < sz; ++t) {
              conn[at++] = loop[0], conn[at++] = loop[t], conn[at++] = loop[t + 1];
              offsets[++p] = static_cast<Index>(at);
              if (cell_arrays) interp.copy_cell(p - 1, static_cast<std::size_t>(cell));
            }
          } else {
            at += static_cast<std::size_t>(sz);
            offsets[++p] = static_cast<Index>(at);
            if (cell_arrays) interp.copy_cell(p - 1, static_cast<std::size_t>(cell));
          }
        }
      }
    }
  });
  out.polys = CellArray(std::move(offsets), std::move(conn));

  // Pass 4: the points, by grid row (consecutive rows read neighbouring memory), interpolated
  // along their edges. The input values at the ends of a row's edges are scattered over three
  // grid rows, cache misses by the time they are read: some rows ahead, their cache lines are
  // prefetched.
  float* xyz = out.points.floats().data();
  const bool point_arrays = interp.has_point_arrays();
  std::vector<std::pair<const std::byte*, std::size_t>> sources;  // each point array: base, tuple bytes
  if (point_arrays) {
    for (const DataArray& a : image.point_data) {
      sources.emplace_back(a.bytes(), scalar_size(a.type()) * static_cast<std::size_t>(a.components()));
    }
  }
  auto prefetch_row = [&](std::size_t r) {
    if (row_points[r] == row_points[r + 1]) return;
    const Index j = static_cast<Index>(r) % ny, k = static_cast<Index>(r) / ny;
    Index lo = lead[r] > 0 ? lead[r] - 1 : 0;
    if (j + 1 < ny) lo = std::min<Index>(lo, lead[r + 1]);
    if (k + 1 < nz) lo = std::min<Index>(lo, lead[r + static_cast<std::size_t>(ny)]);
    for (const auto& [base, bytes] : sources) {
      prefetch(base + bytes * static_cast<std::size_t>(image.point_id(lo, j, k)));
      if (j + 1 < ny) prefetch(base + bytes * static_cast<std::size_t>(image.point_id(lo, j + 1, k)));
      if (k + 1 < nz) prefetch(base + bytes * static_cast<std::size_t>(image.point_id(lo, j, k + 1)));
    }
  };
  constexpr std::size_t kPrefetchRows = 8;
  parallel_for_range(grid_rows, 1024, [&](std::size_t r0, std::size_t r1) {
    if (!sources.empty()) {
      for (std::size_t r = r0; r < std::min(r1, r0 + kPrefetchRows); ++r) prefetch_row(r);
    }
    for (std::size_t r = r0; r < r1; ++r) {
      if (!sources.empty() && r + kPrefetchRows < r1) prefetch_row(r + kPrefetchRows);
      std::size_t id = row_points[r];
      if (id == row_points[r + 1]) continue;
      const Index j = static_cast<Index>(r) % ny, k = static_cast<Index>(r) / ny;
      // The point on edge (i, j, k) + t (unit step along `axis`).
      auto emit = [&](Index i, Index j1, Index k1, int axis, double g0, double g1) {
        const double t = g0 / (g0 - g1);
        Vec3 q = image.point(i, j, k);
        q[axis] += t * s[axis];
        float* w = xyz + 3 * id;
        w[0] = static_cast<float>(q.x), w[1] = static_cast<float>(q.y), w[2] = static_cast<float>(q.z);
        if (point_arrays) {
          const Index i1 = axis == 0 ? i + 1 : i;
          interp.interpolate(id, static_cast<std::size_t>(image.point_id(i, j, k)),
                             static_cast<std::size_t>(image.point_id(i1, j1, k1)), t);
        }
        ++id;
      };
      if (x_points(r) != 0) {
        const Index i = lead[r] - 1;
        emit(i, j, k, 0, G(i, j, k), G(i + 1, j, k));
      }
      if (j + 1 < ny) {
        const auto [lo, hi] = span_of(r, r + 1);
        for (Index i = lo; i < hi; ++i) emit(i, j + 1, k, 1, G(i, j, k), G(i, j + 1, k));
      }
      if (k + 1 < nz) {
        const auto [lo, hi] = span_of(r, r + static_cast<std::size_t>(ny));
        for (Index i = lo; i < hi; ++i) emit(i, j, k + 1, 2, G(i, j, k), G(i, j, k + 1));
      }
    }
  });
  DataArray value_ids = DataArray::uninitialized("CutValueIndex", ScalarType::Int32, 1, np);
  auto vids = value_ids.values<std::int32_t>();
  std::fill(vids.begin(), vids.end(), value_index);
  interp.move_into(out.point_data, out.cell_data);
  out.point_data.add(std::move(value_ids));
  return out;
}

}  // namespace isoforge::cutting
