#include "isoforge/core/cell_type.hpp"

namespace isoforge {

int cell_dimension(CellType type) {
  switch (type) {
    case CellType::Vertex:
    case CellType::PolyVertex: return 0;
    case CellType::Line:
    case CellType::PolyLine: return 1;
    case CellType::Triangle:
    case CellType::TriangleStrip:
    case CellType::Polygon:
    case CellType::Pixel:
    case CellType::Quad: return 2;
    case CellType::Tetra:
    case CellType::Voxel:
    case CellType::Hexahedron:
    case CellType::Wedge:
    case CellType::Pyramid: return 3;
    case CellType::Empty: return -1;
  }
  return -1;
}

std::string_view cell_type_name(CellType type) {
  switch (type) {
    case CellType::Empty: return "empty";
    case CellType::Vertex: return "vertex";
    case CellType::PolyVertex: return "poly-vertex";
    case CellType::Line: return "line";
    case CellType::PolyLine: return "polyline";
    case CellType::Triangle: return "triangle";
    case CellType::TriangleStrip: return "triangle strip";
    case CellType::Polygon: return "polygon";
    case CellType::Pixel: return "pixel";
    case CellType::Quad: return "quad";
    case CellType::Tetra: return "tetra";
    case CellType::Voxel: return "voxel";
    case CellType::Hexahedron: return "hexahedron";
    case CellType::Wedge: return "wedge";
    case CellType::Pyramid: return "pyramid";
  }
  return "unknown";
}

}  // namespace isoforge
