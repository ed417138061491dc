#include "isoforge/core/dataset.hpp"

#include <cmath>
#include <string>

#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {


// Axes along which structured dims have more than one point, in i, j, k order.
int varying_axes(const Dims& dims, int axes[3]) {
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] > 1) axes[n++] = a;
  }
  return n;
}

// Point ids of a structured cell. `voxel_order` selects VTK's voxel/pixel order (image data)
// instead of the hexahedron/quad order (structured grid).
void structured_cell_ids(const Dims& dims, Index cell, bool voxel_order, std::vector<Index>& ids) {
  ids.clear();
  int axes[3];
  const int d = varying_axes(dims, axes);
  if (d == 0) {
    ids.push_back(0);
    return;
  }
  // Decompose the cell id over the varying axes (first varying axis fastest).
  Index ijk[3] = {0, 0, 0};
  Index rest = cell;
  for (int a = 0; a < d; ++a) {
    Index n = dims[axes[a]] - 1;
    ijk[axes[a]] = rest % n;
    rest /= n;
  }
  auto id = [&](Index di, Index dj, Index dk) {
    Index off[3] = {0, 0, 0};
    const Index local[3] = {di, dj, dk};
    for (int a = 0; a < d; ++a) off[axes[a]] = local[a];
    return (ijk[0] + off[0]) + dims[0] * ((ijk[1] + off[1]) + dims[1] * (ijk[2] + off[2]));
  };
  if (d == 1) {
    ids = {id(0, 0, 0), id(1, 0, 0)};
  } else if (d == 2) {
    if (voxel_order) {
      ids = {id(0, 0, 0), id(1, 0, 0), id(0, 1, 0), id(1, 1, 0)};
    } else {
      ids = {id(0, 0, 0), id(1, 0, 0), id(1, 1, 0), id(0, 1, 0)};
    }
  } else if (voxel_order) {
    ids = {id(0, 0, 0), id(1, 0, 0), id(0, 1, 0), id(1, 1, 0),
           id(0, 0, 1), id(1, 0, 1), id(0, 1, 1), id(1, 1, 1)};
  } else {
    ids = {id(0, 0, 0), id(1, 0, 0), id(1, 1, 0), id(0, 1, 0),
           id(0, 0, 1), id(1, 0, 1), id(1, 1, 1), id(0, 1, 1)};
  }
}

CellType structured_cell_type(const Dims& dims, bool voxel_order) {
  switch (structured_dimension(dims)) {
    case 0: return CellType::Vertex;
    case 1: return CellType::Line;
    case 2: return voxel_order ? CellType::Pixel : CellType::Quad;
    default: return voxel_order ? CellType::Voxel : CellType::Hexahedron;
  }
}

void validate_attributes(const Attributes& pd, const Attributes& cd, std::size_t np,
                         std::size_t nc) {
  pd.validate(np, "point data");
  cd.validate(nc, "cell data");
}

}  // namespace

std::size_t checked_point_count(const Dims& dims, std::string_view what) {
  std::uint64_t n = 1;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] < 1) {
      throw Error(std::string(what) + ": dimension " + std::to_string(a) + " is " +
                  std::to_string(dims[a]) + ", must be >= 1");
    }
    if (__builtin_mul_overflow(n, static_cast<std::uint64_t>(dims[a]), &n) ||
        n > static_cast<std::uint64_t>(INT64_MAX)) {
      throw Error(std::string(what) + ": dimensions " + std::to_string(dims[0]) + " x " +
                  std::to_string(dims[1]) + " x " + std::to_string(dims[2]) +
                  " overflow a 64-bit point count");
    }
  }
  return static_cast<std::size_t>(n);
}

std::size_t structured_cell_count(const Dims& dims) {
  std::size_t n = 1;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] > 1) n *= static_cast<std::size_t>(dims[a] - 1);
    if (dims[a] < 1) return 0;
  }
  return n;
}

int structured_dimension(const Dims& dims) {
  int d = 0;
  for (int a = 0; a < 3; ++a) d += dims[a] > 1 ? 1 : 0;
  return d;
}

// ---- ImageData ----

std::size_t ImageData::num_points() const {
  std::size_t n = 1;
  for (int a = 0; a < 3; ++a) n *= static_cast<std::size_t>(dims[a] < 0 ? 0 : dims[a]);
  return n;
}

Vec3 ImageData::point(Index id) const {
  const Index i = id % dims[0];
  const Index j = (id / dims[0]) % dims[1];
  const Index k = id / (dims[0] * dims[1]);
  return point(i, j, k);
}

Bounds ImageData::bounds() const {
  Bounds b;
  if (num_points() == 0) return b;
  b.extend(point(0, 0, 0));
  b.extend(point(dims[0] - 1, dims[1] - 1, dims[2] - 1));
  return b;
}

void ImageData::validate() const {
  const std::size_t np = checked_point_count(dims, "image data");
  if (!is_finite(origin)) throw Error("image data: origin is not finite");
  if (!is_finite(spacing)) throw Error("image data: spacing is not finite");
  for (int a = 0; a < 3; ++a) {
    if (spacing[a] == 0.0 && dims[a] > 1) {
      throw Error("image data: spacing along axis " + std::to_string(a) + " is zero");
    }
  }
  validate_attributes(point_data, cell_data, np, num_cells());
}

// ---- StructuredGrid ----

void StructuredGrid::validate() const {
  const std::size_t np = checked_point_count(dims, "structured grid");
  if (points.size() != np) {
    throw Error("structured grid: " + std::to_string(points.size()) + " points for dimensions " +
                std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                std::to_string(dims[2]) + " (expected " + std::to_string(np) + ")");
  }
  validate_attributes(point_data, cell_data, np, num_cells());
}

// ---- PolyData ----

void PolyData::validate() const {
  const std::size_t np = points.size();
  verts.validate(np, "verts");
  lines.validate(np, "lines");
  polys.validate(np, "polys");
  strips.validate(np, "strips");
  if (const std::size_t c = verts.first_smaller_than(1); c < verts.size()) {
    throw Error("verts: cell " + std::to_string(c) + " is empty");
  }
  if (const std::size_t c = lines.first_smaller_than(2); c < lines.size()) {
    throw Error("lines: cell " + std::to_string(c) + " has fewer than 2 points");
  }
  if (const std::size_t c = polys.first_smaller_than(3); c < polys.size()) {
    throw Error("polys: cell " + std::to_string(c) + " has fewer than 3 points");
  }
  if (const std::size_t c = strips.first_smaller_than(3); c < strips.size()) {
    throw Error("strips: cell " + std::to_string(c) + " has fewer than 3 points");
  }
  validate_attributes(point_data, cell_data, np, num_cells());
}

// ---- UnstructuredGrid ----

void UnstructuredGrid::add_cell(CellType type, std::span<const Index> ids) {
  types.push_back(type);
  cells.add(ids);
}

void UnstructuredGrid::validate() const {
  if (types.size() != cells.size()) {
    throw Error("unstructured grid: " + std::to_string(types.size()) + " cell types for " +
                std::to_string(cells.size()) + " cells");
  }
  cells.validate(points.size(), "cells");
  // The first cell of an unknown type or of a wrong size, in a flat pass on all threads.
  const auto bad = [&](std::size_t c) {
    if (!is_valid_cell_type(static_cast<int>(types[c]))) return true;
    const int fixed = cell_fixed_size(types[c]);
    const auto n = static_cast<int>(cells.cell_size(c));
    return (fixed > 0 && n != fixed) || n < cell_min_size(types[c]);
  };
  const std::size_t c =
      parallel_find_first(types.size(), std::size_t{1} << 16, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (bad(i)) return i;
        }
        return e;
      });
  if (c < types.size()) {
    const int t = static_cast<int>(types[c]);
    if (!is_valid_cell_type(t)) {
      throw Error("unstructured grid: cell " + std::to_string(c) + " has unknown type " +
                  std::to_string(t));
    }
    throw Error("unstructured grid: cell " + std::to_string(c) + " (" +
                std::string(cell_type_name(types[c])) + ") has " +
                std::to_string(cells.cell_size(c)) + " points");
  }
  validate_attributes(point_data, cell_data, points.size(), types.size());
}

// ---- Dataset ----

std::string_view dataset_type_name(DatasetRef ds) {
  return ds.visit(Overloaded{[](const ImageData&) { return std::string_view("image data"); },
                               [](const StructuredGrid&) { return std::string_view("structured grid"); },
                               [](const PolyData&) { return std::string_view("polygonal data"); },
                               [](const UnstructuredGrid&) {
                                 return std::string_view("unstructured grid");
                               }});
}

std::size_t num_points(DatasetRef ds) {
  return ds.visit([](const auto& d) { return d.num_points(); });
}
std::size_t num_cells(DatasetRef ds) {
  return ds.visit([](const auto& d) { return d.num_cells(); });
}
Bounds bounds(DatasetRef ds) {
  return ds.visit([](const auto& d) { return d.bounds(); });
}
Vec3 point(DatasetRef ds, Index id) {
  return ds.visit(Overloaded{[id](const ImageData& d) { return d.point(id); },
                               [id](const auto& d) { return d.points[static_cast<std::size_t>(id)]; }});
}
const Attributes& point_data(DatasetRef ds) {
  return ds.visit([](const auto& d) -> const Attributes& { return d.point_data; });
}
Attributes& point_data(Dataset& ds) {
  return std::visit([](auto& d) -> Attributes& { return d.point_data; }, ds);
}
const Attributes& cell_data(DatasetRef ds) {
  return ds.visit([](const auto& d) -> const Attributes& { return d.cell_data; });
}
Attributes& cell_data(Dataset& ds) {
  return std::visit([](auto& d) -> Attributes& { return d.cell_data; }, ds);
}
const Attributes& field_data(DatasetRef ds) {
  return ds.visit([](const auto& d) -> const Attributes& { return d.field_data; });
}
Attributes& field_data(Dataset& ds) {
  return std::visit([](auto& d) -> Attributes& { return d.field_data; }, ds);
}
void validate(DatasetRef ds) {
  ds.visit([](const auto& d) { d.validate(); });
}

namespace {
// PolyData cell lookup: which array and local index a global cell id falls in.
const CellArray& poly_locate(const PolyData& pd, Index& cell, int& which) {
  const CellArray* arrays[4] = {&pd.verts, &pd.lines, &pd.polys, &pd.strips};
  for (which = 0; which < 4; ++which) {
    const auto n = static_cast<Index>(arrays[which]->size());
    if (cell < n) return *arrays[which];
    cell -= n;
  }
  throw Error("polygonal data: cell id out of range");
}
}  // namespace

CellType poly_cell_type(int section, std::size_t size) {
  switch (section) {
    case 0:
      return size == 1 ? CellType::Vertex : CellType::PolyVertex;
    case 1:
      return size == 2 ? CellType::Line : CellType::PolyLine;
    case 2:
      return size == 3 ? CellType::Triangle : (size == 4 ? CellType::Quad : CellType::Polygon);
    default:
      return CellType::TriangleStrip;
  }
}

CellType cell_type(DatasetRef ds, Index cell) {
  return ds.visit(Overloaded{[](const ImageData& d) { return structured_cell_type(d.dims, true); },
                 [](const StructuredGrid& d) { return structured_cell_type(d.dims, false); },
                 [cell](const PolyData& d) {
                   Index local = cell;
                   int which = 0;
                   const CellArray& ca = poly_locate(d, local, which);
                   return poly_cell_type(which, ca.cell_size(static_cast<std::size_t>(local)));
                 },
                 [cell](const UnstructuredGrid& d) { return d.types[static_cast<std::size_t>(cell)]; }});
}

void cell_point_ids(DatasetRef ds, Index cell, std::vector<Index>& ids) {
  ds.visit(Overloaded{[&](const ImageData& d) { structured_cell_ids(d.dims, cell, true, ids); },
                        [&](const StructuredGrid& d) {
                          structured_cell_ids(d.dims, cell, false, ids);
                        },
                        [&](const PolyData& d) {
                          Index local = cell;
                          int which = 0;
                          auto c = poly_locate(d, local, which).cell(static_cast<std::size_t>(local));
                          ids.assign(c.begin(), c.end());
                        },
                        [&](const UnstructuredGrid& d) {
                          auto c = d.cells.cell(static_cast<std::size_t>(cell));
                          ids.assign(c.begin(), c.end());
                        }});
}

UnstructuredGrid to_unstructured(DatasetRef ds) {
  if (const auto* ug = ds.get_if<UnstructuredGrid>()) return *ug;
  UnstructuredGrid out;
  const std::size_t np = num_points(ds);
  if (const auto* img = ds.get_if<ImageData>()) {
    out.points = Points(np);
    for (std::size_t i = 0; i < np; ++i) out.points.set(i, img->point(static_cast<Index>(i)));
  } else {
    out.points = ds.visit(Overloaded{[](const ImageData&) { return Points(); },
                                       [](const auto& d) { return d.points; }});
  }
  const std::size_t nc = num_cells(ds);
  out.types.reserve(nc);
  std::vector<Index> ids;
  for (std::size_t c = 0; c < nc; ++c) {
    cell_point_ids(ds, static_cast<Index>(c), ids);
    out.add_cell(cell_type(ds, static_cast<Index>(c)), ids);
  }
  out.point_data = point_data(ds);
  out.cell_data = cell_data(ds);
  out.field_data = field_data(ds);
  return out;
}

}  // namespace isoforge
