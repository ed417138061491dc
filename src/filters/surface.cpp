// Surface extraction (VTK's vtkGeometryFilter / vtkDataSetSurfaceFilter): the faces of 3D cells
// used by exactly one cell, plus every lower-dimensional cell, as polygonal data.
//
// Method (docs/algorithms/threshold.md):
// - Unstructured input: each face of a 3D cell is keyed by its sorted point ids and filed under
//   its smallest id (a counting pass, prefix sums over the points, and a filling pass with
//   atomic cursors: a CSR table of faces by smallest vertex). Each vertex's few faces are then
//   sorted by the remaining ids; a face whose key appears once is a boundary face and sets its
//   bit in its cell's face mask. Since the decision depends only on the keys, the order in which
//   the threads filed the faces does not matter. A block-wise pass over the cells then counts
//   the output (verts, lines, polys, strips) and marks the used points, and a second one writes
//   it with renumbered ids: cells in increasing owner id, faces in the order of the cell's face
//   table, which lists them with outward right-hand normals.
// - 3D image data and structured grids: the boundary cells are enumerated slab by slab and their
//   outer faces written directly, the output points numbered in closed form (the points of the
//   first and last k-planes and of the rings between them); no hashing. Same output as the
//   unstructured method on the converted grid.

#include "isoforge/filters/surface.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <type_traits>

#include "extract_common.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {

using namespace extract_impl;

enum Category { kOutVerts = 0, kOutLines = 1, kOutPolys = 2, kOutStrips = 3 };

struct Counts {
  std::size_t cells[4] = {0, 0, 0, 0};
  std::size_t ids[4] = {0, 0, 0, 0};
  std::size_t faces3d = 0;  // of cells[kOutPolys]: faces of 3D cells
};

// ---- faces of 3D cells used once ----

template <class U>
struct FaceRecord {
  U key[3];  // the sorted ids after the smallest; a triangle's third is the maximum U
  U cell_face;  // cell * 8 + local face
};

template <class U>
bool key_less(const FaceRecord<U>& a, const FaceRecord<U>& b) {
  if (a.key[0] != b.key[0]) return a.key[0] < b.key[0];
  if (a.key[1] != b.key[1]) return a.key[1] < b.key[1];
  return a.key[2] < b.key[2];
}
template <class U>
bool key_equal(const FaceRecord<U>& a, const FaceRecord<U>& b) {
  return a.key[0] == b.key[0] && a.key[1] == b.key[1] && a.key[2] == b.key[2];
}

// The global ids of face `f` of a cell, sorted; returns the count.
inline int sorted_face(const CellFace& f, std::span<const Index> ids, Index* s) {
  const int n = f.size;
  for (int i = 0; i < n; ++i) s[i] = ids[static_cast<std::size_t>(f.ids[static_cast<std::size_t>(i)])];
  for (int i = 1; i < n; ++i) {  // insertion sort of 3 or 4 ids
    const Index v = s[i];
    int j = i - 1;
    while (j >= 0 && s[j] > v) {
      s[j + 1] = s[j];
      --j;
    }
    s[j + 1] = v;
  }
  return n;
}

// Sets in mask[c] the bit of every face of cell c used by no other cell.
template <class U>
void boundary_faces(const TopologyView& cells, std::size_t np, Buffer<std::uint8_t>& mask,
                    const ProgressCallback& progress) {
  const std::size_t nc = cells.size();
  Buffer<U> start(np + 1, U{0});
  // The local point each face of a tetrahedron leaves out: its key is the sorted other three.
  int tet_skip[4];
  {
    const auto tf = cell_faces(CellType::Tetra);
    for (std::size_t f = 0; f < 4; ++f) {
      tet_skip[f] = 6 - tf[f].ids[0] - tf[f].ids[1] - tf[f].ids[2];
    }
  }
  const auto for_faces = [&](auto&& fn, const ProgressCallback& p) {
    for_blocks(
        nc,
        [&](std::size_t, std::size_t begin, std::size_t end) {
          Index buf[8], s[4];
          for (std::size_t c = begin; c < end; ++c) {
            const CellType t = cells.type(c);
            if (t == CellType::Tetra) {  // sort the 4 ids once; each face drops one
              const auto ids = cells.ids(c, buf);
              Index v[4] = {ids[0], ids[1], ids[2], ids[3]};
              int l[4] = {0, 1, 2, 3};
              const auto swap_if = [&](int a, int b) {
                if (v[b] < v[a]) {
                  std::swap(v[a], v[b]);
                  std::swap(l[a], l[b]);
                }
              };
              swap_if(0, 1), swap_if(2, 3), swap_if(0, 2), swap_if(1, 3), swap_if(1, 2);
              for (std::size_t f = 0; f < 4; ++f) {
                int n = 0;
                for (int i = 0; i < 4; ++i)
                  if (l[i] != tet_skip[f]) s[n++] = v[i];
                fn(c, f, s, 3);
              }
              continue;
            }
            if (cell_dimension(t) != 3) continue;
            const auto ids = cells.ids(c, buf);
            const auto faces = cell_faces(t);
            for (std::size_t f = 0; f < faces.size(); ++f) {
              const int n = sorted_face(faces[f], ids, s);
              fn(c, f, s, n);
            }
          }
        },
        p, "surface");
  };
  for_faces(
      [&](std::size_t, std::size_t, const Index* s, int) {
        std::atomic_ref<U>(start[static_cast<std::size_t>(s[0])]).fetch_add(1, std::memory_order_relaxed);
      },
      progress_range(progress, 0, 0.3));
  U total = 0;
  for (std::size_t v = 0; v <= np; ++v) {
    const U c = start[v];
    start[v] = total;
    total += c;
  }
  Buffer<U> cursor(start.begin(), start.end() - 1);
  // The bucket of each vertex holds only cell * 8 + face (4 bytes for most meshes): the keys are
  // recomputed from the cell when the bucket is matched, which costs less than writing and
  // first-touching 16-byte records scattered over memory.
  Buffer<U> faces_of(total);
  for_faces(
      [&](std::size_t c, std::size_t f, const Index* s, int) {
        const U at = std::atomic_ref<U>(cursor[static_cast<std::size_t>(s[0])])
                         .fetch_add(1, std::memory_order_relaxed);
        faces_of[at] = static_cast<U>(c * 8 + f);
      },
      progress_range(progress, 0.3, 0.7));
  cursor = {};
  constexpr U kNone = std::numeric_limits<U>::max();
  parallel_for_range(
      np, 4096,
      [&](std::size_t v0, std::size_t v1) {
        std::vector<FaceRecord<U>> local;
        Index buf[8], s[4];
        for (std::size_t v = v0; v < v1; ++v) {
          local.clear();
          for (U at = start[v]; at < start[v + 1]; ++at) {
            const U cf = faces_of[at];
            const std::size_t c = static_cast<std::size_t>(cf >> 3);
            const CellType t = cells.type(c);
            const auto ids = cells.ids(c, buf);
            const int n = sorted_face(cell_faces(t)[cf & 7], ids, s);
            local.push_back({{static_cast<U>(s[1]), static_cast<U>(s[2]),
                              n == 4 ? static_cast<U>(s[3]) : kNone},
                             cf});
          }
          FaceRecord<U>* b = local.data();
          FaceRecord<U>* e = b + local.size();
          if (e - b <= 24) {
            for (FaceRecord<U>* i = b + 1; i < e; ++i) {
              const FaceRecord<U> x = *i;
              FaceRecord<U>* j = i;
              while (j > b && key_less(x, j[-1])) {
                *j = j[-1];
                --j;
              }
              *j = x;
            }
          } else {
            std::sort(b, e, key_less<U>);
          }
          for (FaceRecord<U>* i = b; i < e;) {
            FaceRecord<U>* j = i + 1;
            while (j < e && key_equal(*i, *j)) ++j;
            if (j - i == 1) {
              const U cf = i->cell_face;
              std::atomic_ref<std::uint8_t>(mask[static_cast<std::size_t>(cf >> 3)])
                  .fetch_or(static_cast<std::uint8_t>(1u << (cf & 7)), std::memory_order_relaxed);
            }
            i = j;
          }
        }
      },
      progress_range(progress, 0.7, 1.0), "surface");
}

// The category and output point order of a cell of dimension < 3.
Category category_of(CellType t) {
  switch (t) {
    case CellType::Vertex:
    case CellType::PolyVertex:
      return kOutVerts;
    case CellType::Line:
    case CellType::PolyLine:
      return kOutLines;
    case CellType::TriangleStrip:
      return kOutStrips;
    default:
      return kOutPolys;
  }
}

PolyData assemble(DatasetRef input, std::array<CellArray, 4> arrays,
                  std::array<Buffer<Index>, 4> owners, Buffer<Index> kept_points,
                  const SurfaceOptions& o) {
  PolyData out;
  out.verts = std::move(arrays[kOutVerts]);
  out.lines = std::move(arrays[kOutLines]);
  out.polys = std::move(arrays[kOutPolys]);
  out.strips = std::move(arrays[kOutStrips]);
  // The owners of all output cells in cell-data order (verts, lines, polys, strips).
  Buffer<Index> all;
  if (owners[kOutVerts].empty() && owners[kOutLines].empty() && owners[kOutStrips].empty()) {
    all = std::move(owners[kOutPolys]);
  } else {
    all.reserve(owners[0].size() + owners[1].size() + owners[2].size() + owners[3].size());
    for (const auto& w : owners) all.insert(all.end(), w.begin(), w.end());
  }
  out.points = gather_points(input, kept_points);
  out.point_data = gather_attributes(point_data(input), kept_points);
  out.cell_data = gather_attributes(cell_data(input), all);
  out.field_data = field_data(input);
  // Index is std::int64_t: the id lists become the Int64 arrays without a copy.
  static_assert(std::is_same_v<Index, std::int64_t>);
  if (o.original_cell_ids) {
    out.cell_data.add(DataArray::from_buffer<std::int64_t>("OriginalCellIds", 1, std::move(all)));
  }
  if (o.original_point_ids) {
    out.point_data.add(
        DataArray::from_buffer<std::int64_t>("OriginalPointIds", 1, std::move(kept_points)));
  }
  return out;
}

SurfaceResult general_surface(DatasetRef input, const SurfaceOptions& o) {
  const TopologyView cells(input);
  const std::size_t nc = cells.size();
  const std::size_t np = num_points(input);
  Buffer<std::uint8_t> mask(nc, 0);
  bool any3d = false;
  if (const auto* ug = input.get_if<UnstructuredGrid>()) {
    for (CellType t : ug->types) {
      if (cell_dimension(t) == 3) {
        any3d = true;
        break;
      }
    }
  }
  if (any3d) {
    if (np < std::numeric_limits<std::uint32_t>::max() && nc < (std::size_t{1} << 29)) {
      boundary_faces<std::uint32_t>(cells, np, mask, progress_range(o.progress, 0, 0.7));
    } else {
      boundary_faces<std::uint64_t>(cells, np, mask, progress_range(o.progress, 0, 0.7));
    }
  }
  // Pass 1: count the output per block, mark the used points.
  std::vector<Counts> counts(block_count(nc));
  std::vector<std::uint8_t> used(np, 0);
  for_blocks(
      nc,
      [&](std::size_t b, std::size_t begin, std::size_t end) {
        Index buf[8];
        Counts k;
        for (std::size_t c = begin; c < end; ++c) {
          const CellType t = cells.type(c);
          const auto ids = cells.ids(c, buf);
          if (cell_dimension(t) == 3) {
            if (!mask[c]) continue;
            const auto faces = cell_faces(t);
            for (std::size_t f = 0; f < faces.size(); ++f) {
              if (!(mask[c] >> f & 1)) continue;
              ++k.cells[kOutPolys];
              ++k.faces3d;
              k.ids[kOutPolys] += static_cast<std::size_t>(faces[f].size);
              for (int i : faces[f].points()) mark_used(used.data(), ids[static_cast<std::size_t>(i)]);
            }
          } else {
            const Category g = category_of(t);
            ++k.cells[g];
            k.ids[g] += ids.size();
            for (Index id : ids) mark_used(used.data(), id);
          }
        }
        counts[b] = k;
      },
      progress_range(o.progress, 0.7, 0.8), "surface");
  Counts total;
  for (auto& k : counts) {
    total.faces3d += k.faces3d;
    for (int g = 0; g < 4; ++g) {
      const std::size_t c = k.cells[g], i = k.ids[g];
      k.cells[g] = total.cells[g];
      k.ids[g] = total.ids[g];
      total.cells[g] += c;
      total.ids[g] += i;
    }
  }
  Buffer<Index> map, kept_points;
  renumber_used(used, map, kept_points);
  used = {};
  // Pass 2: write.
  std::array<Buffer<Index>, 4> offsets, conn, owners;
  for (int g = 0; g < 4; ++g) {
    offsets[g].resize(total.cells[g] + 1);
    offsets[g][total.cells[g]] = static_cast<Index>(total.ids[g]);
    conn[g].resize(total.ids[g]);
    owners[g].resize(total.cells[g]);
  }
  for_blocks(
      nc,
      [&](std::size_t b, std::size_t begin, std::size_t end) {
        Index buf[8];
        Counts at = counts[b];
        const auto emit = [&](int g, std::size_t c) {
          offsets[g][at.cells[g]] = static_cast<Index>(at.ids[g]);
          owners[g][at.cells[g]++] = static_cast<Index>(c);
        };
        for (std::size_t c = begin; c < end; ++c) {
          const CellType t = cells.type(c);
          if (cell_dimension(t) == 3 && !mask[c]) continue;
          const auto ids = cells.ids(c, buf);
          const auto put = [&](int g, Index id) {
            conn[g][at.ids[g]++] = map[static_cast<std::size_t>(id)];
          };
          if (cell_dimension(t) == 3) {
            const auto faces = cell_faces(t);
            for (std::size_t f = 0; f < faces.size(); ++f) {
              if (!(mask[c] >> f & 1)) continue;
              emit(kOutPolys, c);
              for (int i : faces[f].points()) put(kOutPolys, ids[static_cast<std::size_t>(i)]);
            }
          } else if (t == CellType::Pixel) {  // voxel order -> polygon order
            emit(kOutPolys, c);
            for (int i : {0, 1, 3, 2}) put(kOutPolys, ids[static_cast<std::size_t>(i)]);
          } else {
            const Category g = category_of(t);
            emit(g, c);
            for (Index id : ids) put(g, id);
          }
        }
      },
      progress_range(o.progress, 0.8, 0.9), "surface");
  std::array<CellArray, 4> arrays;
  for (int g = 0; g < 4; ++g) arrays[g] = CellArray(std::move(offsets[g]), std::move(conn[g]));
  SurfaceStats stats;
  stats.points = kept_points.size();
  stats.boundary_faces = total.faces3d;
  stats.passed_cells = total.cells[kOutVerts] + total.cells[kOutLines] + total.cells[kOutStrips] +
                       total.cells[kOutPolys] - total.faces3d;
  PolyData out = assemble(input, std::move(arrays), std::move(owners), std::move(kept_points), o);
  report_progress(o.progress, 1.0, "surface");
  return {std::move(out), stats};
}

// ---- the outer faces of a 3D structured grid ----

SurfaceResult structured_surface(DatasetRef input, const Dims& dims, const SurfaceOptions& o) {
  const bool voxel = input.get_if<ImageData>() != nullptr;
  const CellType type = voxel ? CellType::Voxel : CellType::Hexahedron;
  const auto faces = cell_faces(type);
  const auto pp = parametric_points(type);
  const Index Px = dims[0], Py = dims[1], Pz = dims[2];
  const Index nx = Px - 1, ny = Py - 1, nz = Pz - 1;
  // Local corners (0/1 along each axis) and the side (2 axis + 0/1) of each face of the table.
  Index corner[8][3];
  for (int l = 0; l < 8; ++l) {
    const Vec3 p = pp[static_cast<std::size_t>(l)];
    corner[l][0] = static_cast<Index>(p.x);
    corner[l][1] = static_cast<Index>(p.y);
    corner[l][2] = static_cast<Index>(p.z);
  }
  int side[6];
  for (std::size_t f = 0; f < 6; ++f) {
    side[f] = -1;
    for (int a = 0; a < 3; ++a) {
      for (int d = 0; d < 2; ++d) {
        bool all = true;
        for (int i : faces[f].points()) all = all && pp[static_cast<std::size_t>(i)][a] == d;
        if (all) side[f] = 2 * a + d;
      }
    }
    check_invariant(side[f] >= 0, "every face of a voxel/hexahedron lies on one side");
  }
  // Output point numbering in closed form: full first and last planes, rings between them.
  const Index full = Px * Py, ring = 2 * Px + 2 * (Py - 2);
  const auto rank = [&](Index i, Index j, Index k) -> Index {
    if (k == 0) return j * Px + i;
    const Index before = full + (k - 1) * ring;
    if (k == Pz - 1) return before + j * Px + i;
    if (j == 0) return before + i;
    if (j == Py - 1) return before + Px + 2 * (Py - 2) + i;
    return before + Px + 2 * (j - 1) + (i == 0 ? 0 : 1);
  };
  const std::size_t npoints = static_cast<std::size_t>(2 * full + (Pz - 2) * ring);
  Buffer<Index> kept_points(npoints);
  parallel_for_range(static_cast<std::size_t>(Pz), 1, [&](std::size_t k0, std::size_t k1) {
    for (auto k = static_cast<Index>(k0); k < static_cast<Index>(k1); ++k) {
      auto at = static_cast<std::size_t>(k == 0 ? 0 : full + (k - 1) * ring);
      const bool whole = k == 0 || k == Pz - 1;
      for (Index j = 0; j < Py; ++j) {
        const Index row = Px * (j + Py * k);
        if (whole || j == 0 || j == Py - 1) {
          for (Index i = 0; i < Px; ++i) kept_points[at++] = row + i;
        } else {
          kept_points[at++] = row;
          kept_points[at++] = row + Px - 1;
        }
      }
    }
  });
  // Boundary cells of slab k in cell order, calling fn(cell id, i, j, side mask).
  const auto for_slab = [&](Index k, auto&& fn) {
    const unsigned kbits = (k == 0 ? 16u : 0u) | (k == nz - 1 ? 32u : 0u);
    for (Index j = 0; j < ny; ++j) {
      const unsigned jbits = kbits | (j == 0 ? 4u : 0u) | (j == ny - 1 ? 8u : 0u);
      const auto cell = [&](Index i) {
        const unsigned bits = jbits | (i == 0 ? 1u : 0u) | (i == nx - 1 ? 2u : 0u);
        fn(i + nx * (j + ny * k), i, j, bits);
      };
      if (jbits != 0) {
        for (Index i = 0; i < nx; ++i) cell(i);
      } else {
        cell(0);
        if (nx > 1) cell(nx - 1);
      }
    }
  };
  std::vector<std::size_t> slab(static_cast<std::size_t>(nz));
  parallel_for_range(static_cast<std::size_t>(nz), 1, [&](std::size_t k0, std::size_t k1) {
    for (std::size_t k = k0; k < k1; ++k) {
      std::size_t n = 0;
      for_slab(static_cast<Index>(k), [&](Index, Index, Index, unsigned bits) {
        n += static_cast<std::size_t>(std::popcount(bits));
      });
      slab[k] = n;
    }
  });
  const std::size_t nfaces = exclusive_scan(slab);
  Buffer<Index> offsets(nfaces + 1), conn(4 * nfaces), owner(nfaces);
  parallel_for_range(
      static_cast<std::size_t>(nz), 1,
      [&](std::size_t k0, std::size_t k1) {
        for (std::size_t k = k0; k < k1; ++k) {
          std::size_t at = slab[k];
          const auto kk = static_cast<Index>(k);
          for_slab(kk, [&](Index c, Index i, Index j, unsigned bits) {
            for (std::size_t f = 0; f < 6; ++f) {
              if (!(bits >> side[f] & 1)) continue;
              offsets[at] = static_cast<Index>(4 * at);
              owner[at] = c;
              for (int l = 0; l < 4; ++l) {
                const Index* d = corner[faces[f].ids[static_cast<std::size_t>(l)]];
                conn[4 * at + static_cast<std::size_t>(l)] = rank(i + d[0], j + d[1], kk + d[2]);
              }
              ++at;
            }
          });
        }
      },
      progress_range(o.progress, 0, 0.8), "surface");
  offsets[nfaces] = static_cast<Index>(4 * nfaces);
  std::array<CellArray, 4> arrays;
  arrays[kOutPolys] = CellArray(std::move(offsets), std::move(conn));
  std::array<Buffer<Index>, 4> owners;
  owners[kOutPolys] = std::move(owner);
  PolyData out = assemble(input, std::move(arrays), std::move(owners), std::move(kept_points), o);
  SurfaceStats stats;
  stats.boundary_faces = nfaces;
  stats.points = npoints;
  report_progress(o.progress, 1.0, "surface");
  return {std::move(out), stats};
}

}  // namespace

SurfaceResult extract_surface(DatasetRef input, const SurfaceOptions& options) {
  validate(input);
  const Dims* dims = input.visit([](const auto& d) -> const Dims* {
    if constexpr (requires { d.dims; }) {
      return &d.dims;
    } else {
      return nullptr;
    }
  });
  if (dims && structured_dimension(*dims) == 3) return structured_surface(input, *dims, options);
  return general_surface(input, options);
}

}  // namespace isoforge
