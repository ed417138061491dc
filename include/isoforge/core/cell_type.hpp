#pragma once
/// \file
/// Linear cell types, numbered as VTK numbers them (so files map one to one).

#include <cstdint>
#include <string_view>

namespace isoforge {

/// Linear cell types. Values equal VTK's type ids. Point orderings follow VTK's
/// conventions (documented per type in docs/architecture.md and core/cell.hpp).
enum class CellType : std::uint8_t {
  Empty = 0,
  Vertex = 1,
  PolyVertex = 2,
  Line = 3,
  PolyLine = 4,
  Triangle = 5,
  TriangleStrip = 6,
  Polygon = 7,
  Pixel = 8,
  Quad = 9,
  Tetra = 10,
  Voxel = 11,
  Hexahedron = 12,
  Wedge = 13,
  Pyramid = 14,
};

/// Whether `id` is a supported VTK linear cell type id.
[[nodiscard]] bool is_valid_cell_type(int id);
/// Topological dimension (0 vertex, 1 line, 2 surface, 3 volume).
[[nodiscard]] int cell_dimension(CellType type);
/// Fixed number of points, or -1 for variable-size types (poly-vertex, polyline, strip,
/// polygon).
[[nodiscard]] int cell_fixed_size(CellType type);
/// Minimum number of points a cell of this type needs (e.g. 3 for a polygon).
[[nodiscard]] int cell_min_size(CellType type);
/// Human readable name ("hexahedron").
[[nodiscard]] std::string_view cell_type_name(CellType type);

}  // namespace isoforge
