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

// (Inline: readers and validate() ask these of every cell.)

/// Whether `id` is a supported VTK linear cell type id.
[[nodiscard]] constexpr bool is_valid_cell_type(int id) {
  return id >= 1 && id <= 14;
}
/// Topological dimension (0 vertex, 1 line, 2 surface, 3 volume).
[[nodiscard]] int cell_dimension(CellType type);
/// Fixed number of points, or -1 for variable-size types (poly-vertex, polyline, strip,
/// polygon).
[[nodiscard]] constexpr int cell_fixed_size(CellType type) {
  switch (type) {
    case CellType::Vertex:
      return 1;
    case CellType::Line:
      return 2;
    case CellType::Triangle:
      return 3;
    case CellType::Pixel:
    case CellType::Quad:
    case CellType::Tetra:
      return 4;
    case CellType::Pyramid:
      return 5;
    case CellType::Wedge:
      return 6;
    case CellType::Voxel:
    case CellType::Hexahedron:
      return 8;
    case CellType::Empty:
      return 0;
    case CellType::PolyVertex:
    case CellType::PolyLine:
    case CellType::TriangleStrip:
    case CellType::Polygon:
      return -1;
  }
  return -1;
}
/// Minimum number of points a cell of this type needs (e.g. 3 for a polygon).
[[nodiscard]] constexpr int cell_min_size(CellType type) {
  switch (type) {
    case CellType::PolyVertex:
      return 1;
    case CellType::PolyLine:
      return 2;
    case CellType::TriangleStrip:
    case CellType::Polygon:
      return 3;
    default:
      return cell_fixed_size(type);
  }
}
/// Human readable name ("hexahedron").
[[nodiscard]] std::string_view cell_type_name(CellType type);

}  // namespace isoforge
