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

  // Pass 1: the crossing of every grid line, by bisection on the monotone values. For axis a,
  // line (u, v) holds the points along a with the other two indices (u, v) (i fastest first).
  // `first[a][line]`: the number of leading points on the side the line starts from in the
  // direction of increase (below when the slope is >= 0); cross = that count - 1 if the line
  // changes side, else -1.
  const std::array<Index, 3> n{nx, ny, nz};
  const std::array<double, 3> slope{dx, dy, dz};
  // 32-bit line data (memory traffic is most of the cost): lines and points stay below 2^31.
  std::array<std::vector<std::int32_t>, 3> lead;
  std::array<std::vector<std::int32_t>, 3> ids;  // point id of each line's crossing, or -1
  std::atomic<bool> exact{false};
  for (int a = 0; a < 3; ++a) {
    const int ua = a == 0 ? 1 : 0, va = a == 2 ? 1 : 2;
    const Index nu = n[static_cast<std::size_t>(ua)], nv = n[static_cast<std::size_t>(va)];
    const Index len = n[static_cast<std::size_t>(a)];
    const bool rising = slope[static_cast<std::size_t>(a)] >= 0;
    auto& L = lead[static_cast<std::size_t>(a)];
    L.resize(static_cast<std::size_t>(nu * nv));
    parallel_for_range(static_cast<std::size_t>(nu * nv), 4096, [&](std::size_t l0, std::size_t l1) {
      for (std::size_t l = l0; l < l1; ++l) {
        const Index u = static_cast<Index>(l) % nu, v = static_cast<Index>(l) / nu;
        auto value = [&](Index t) {
          std::array<Index, 3> ijk{};
          ijk[static_cast<std::size_t>(a)] = t;
          ijk[static_cast<std::size_t>(ua)] = u;
          ijk[static_cast<std::size_t>(va)] = v;
          return G(ijk[0], ijk[1], ijk[2]);
        };
        // Leading side: below (G < 0) when rising, above (G >= 0) otherwise.
        auto leading = [&](Index t) { return rising ? value(t) < 0 : value(t) >= 0; };
        // The first index not on the leading side, in [0, len]: from the real crossing
        // t = -G(0) / slope, then stepped to where the (monotone) rounded values switch.
        const double sl = slope[static_cast<std::size_t>(a)];
        Index lo = 0;
        if (sl != 0) {
          const double t = std::ceil(-value(0) / sl);
          lo = t <= 0 ? 0 : (t >= static_cast<double>(len) ? len : static_cast<Index>(t));
        } else {
          lo = leading(0) ? len : 0;
        }
        while (lo > 0 && !leading(lo - 1)) --lo;
        while (lo < len && leading(lo)) ++lo;
        L[l] = static_cast<std::int32_t>(lo);
        if (lo > 0 && lo < len && (value(lo - 1) == 0 || value(lo) == 0)) {
          exact.store(true, std::memory_order_relaxed);
        }
      }
    });
    if (exact.load()) return std::nullopt;
  }
  // Point ids: x-line crossings first, then y, then z, each in line order.
  std::size_t np = 0;
  std::array<std::size_t, 3> first_id{};
  for (int a = 0; a < 3; ++a) {
    const Index len = n[static_cast<std::size_t>(a)];
    auto& L = lead[static_cast<std::size_t>(a)];
    auto& I = ids[static_cast<std::size_t>(a)];
    I.resize(L.size());
    first_id[static_cast<std::size_t>(a)] = np;
    for (std::size_t l = 0; l < L.size(); ++l) {
      I[l] = (L[l] > 0 && L[l] < len) ? static_cast<std::int32_t>(np++) : -1;
    }
  }

  // Pass 2: count the polygons of each voxel row (j, k), over its active range only.
  const Index cx = nx - 1, cy = ny - 1, cz = nz - 1;
  const std::size_t rows = static_cast<std::size_t>(cy * cz);
  const VoxelTable& table = voxel_table();
  std::vector<std::size_t> row_polys(rows + 1), row_ids(rows + 1);
  row_polys[0] = row_ids[0] = 0;
  const auto& LX = lead[0];
  auto voxel_case = [&](Index i, Index j, Index k) {
    int cs = 0;
    for (int q = 0; q < 8; ++q) {
      if (G(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1)) >= 0) cs |= 1 << q;
    }
    return cs;
  };
  // The voxels of row (j, k) with points on both sides: between the crossings of its 4 lines.
  auto active = [&](Index j, Index k) {
    Index lo = nx, hi = 0;
    for (int q = 0; q < 4; ++q) {
      const Index b = LX[static_cast<std::size_t>((j + (q & 1)) + ny * (k + (q >> 1)))];
      lo = std::min(lo, b), hi = std::max(hi, b);
    }
    return std::pair<Index, Index>{std::max<Index>(lo - 1, 0), std::min<Index>(hi - 1, cx - 1)};
  };
  parallel_for_range(rows, 256, [&](std::size_t r0, std::size_t r1) {
    for (std::size_t r = r0; r < r1; ++r) {
      const Index j = static_cast<Index>(r) % cy, k = static_cast<Index>(r) / cy;
      const auto [i0, i1] = active(j, k);
      std::size_t polys = 0, vids = 0;
      for (Index i = i0; i <= i1; ++i) {
        const auto cs = static_cast<std::size_t>(voxel_case(i, j, k));
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
  // Pass 3: the polygons, written in place.
  std::array<Index, 12> off{};  // offset of each edge code's line from the voxel's base line
  for (int o = 0; o < 4; ++o) {
    off[static_cast<std::size_t>(o)] = (o & 1) + ny * (o >> 1);
    off[static_cast<std::size_t>(4 + o)] = (o & 1) + nx * (o >> 1);
    off[static_cast<std::size_t>(8 + o)] = (o & 1) + nx * (o >> 1);
  }
  const bool cell_arrays = interp.has_cell_arrays();
  parallel_for_range(rows, 256, [&](std::size_t r0, std::size_t r1) {
    Index loop[16];
    for (std::size_t r = r0; r < r1; ++r) {
      if (row_polys[r + 1] == row_polys[r]) continue;
      const Index j = static_cast<Index>(r) % cy, k = static_cast<Index>(r) / cy;
      std::size_t p = row_polys[r], at = row_ids[r];
      const auto [i0, i1] = active(j, k);
      const std::int32_t* line[3] = {ids[0].data() + j + ny * k, ids[1].data() + nx * k,
                                     ids[2].data() + nx * j};
      for (Index i = i0; i <= i1; ++i) {
        const auto cs = static_cast<std::size_t>(voxel_case(i, j, k));
        const int loops = table.loops[cs];
        if (loops == 0) continue;
        const Index cell = i + cx * (j + cy * k);
        const Index shift[3] = {0, i, i};
        std::size_t e = 0;
        for (int l = 0; l < loops; ++l) {
          const int sz = table.sizes[cs][static_cast<std::size_t>(l)];
          for (int q = 0; q < sz; ++q, ++e) {
            const int code = table.edges[cs][e];
            loop[q] = line[code >> 2][shift[code >> 2] + off[static_cast<std::size_t>(code)]];
          }
          if (options.triangulate) {
            for (int t = 1; t + 1 < sz; ++t) {
              conn[at++] = loop[0], conn[at++] = loop[t], conn[at++] = loop[t + 1];
              offsets[++p] = static_cast<Index>(at);
              if (cell_arrays) interp.copy_cell(p - 1, static_cast<std::size_t>(cell));
            }
          } else {
            for (int q = 0; q < sz; ++q) conn[at++] = loop[q];
            offsets[++p] = static_cast<Index>(at);
            if (cell_arrays) interp.copy_cell(p - 1, static_cast<std::size_t>(cell));
          }
        }
      }
    }
  });
  out.polys = CellArray(std::move(offsets), std::move(conn));

  // Pass 4: the points, interpolated along their lines.
  DataArray value_ids = DataArray::uninitialized("CutValueIndex", ScalarType::Int32, 1, np);
  auto vids = value_ids.values<std::int32_t>();
  std::fill(vids.begin(), vids.end(), value_index);
  for (int a = 0; a < 3; ++a) {
    const int ua = a == 0 ? 1 : 0, va = a == 2 ? 1 : 2;
    const Index nu = n[static_cast<std::size_t>(ua)];
    const auto& L = lead[static_cast<std::size_t>(a)];
    const auto& I = ids[static_cast<std::size_t>(a)];
    parallel_for_range(L.size(), 4096, [&](std::size_t l0, std::size_t l1) {
      for (std::size_t l = l0; l < l1; ++l) {
        if (I[l] < 0) continue;
        const Index u = static_cast<Index>(l) % nu, v = static_cast<Index>(l) / nu;
        std::array<Index, 3> p0{}, p1{};
        p0[static_cast<std::size_t>(a)] = L[l] - 1;
        p0[static_cast<std::size_t>(ua)] = u;
        p0[static_cast<std::size_t>(va)] = v;
        p1 = p0;
        ++p1[static_cast<std::size_t>(a)];
        const double g0 = G(p0[0], p0[1], p0[2]), g1 = G(p1[0], p1[1], p1[2]);
        const double t = g0 / (g0 - g1);
        Vec3 q = image.point(p0[0], p0[1], p0[2]);
        q[a] += t * s[a];
        const auto out_id = static_cast<std::size_t>(I[l]);
        out.points.set(out_id, q);
        interp.interpolate(out_id, static_cast<std::size_t>(image.point_id(p0[0], p0[1], p0[2])),
                           static_cast<std::size_t>(image.point_id(p1[0], p1[1], p1[2])), t);
      }
    });
  }
  interp.move_into(out.point_data, out.cell_data);
  out.point_data.add(std::move(value_ids));
  return out;
}

}  // namespace isoforge::cutting
