#pragma once
/// \file
/// The four dataset types of the chapter's data model and the `Dataset` variant.
///
/// Every dataset has `point_data` (one tuple per point), `cell_data` (one tuple per cell) and
/// `field_data` (arrays of any length describing the whole dataset). Datasets are plain value
/// types; `validate()` checks their invariants and throws `Error` naming what is wrong.

#include <array>
#include <cstddef>
#include <initializer_list>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

#include "isoforge/core/attributes.hpp"
#include "isoforge/core/cell_array.hpp"
#include "isoforge/core/cell_type.hpp"
#include "isoforge/core/points.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge {

/// Structured dimensions (points along i, j, k; each >= 1).
using Dims = std::array<Index, 3>;

/// Number of points of structured dims, or throws Error (naming `what`) if a dimension is < 1
/// or the product overflows 64 bits.
[[nodiscard]] std::size_t checked_point_count(const Dims& dims, std::string_view what);
/// Number of cells of structured dims: product of (d - 1) over dims with d > 1 (1 if none).
[[nodiscard]] std::size_t structured_cell_count(const Dims& dims);
/// Topological dimension of structured dims: the count of dims > 1.
[[nodiscard]] int structured_dimension(const Dims& dims);

/// Uniform rectilinear grid: point (i, j, k) is at origin + (i, j, k) * spacing.
/// Point ids run i fastest: id = i + dims[0] * (j + dims[1] * k). Cells are voxels (3D),
/// pixels (2D), lines (1D) or one vertex (a single point), with VTK's voxel point order.
struct ImageData {
  Dims dims{1, 1, 1};
  Vec3 origin{0, 0, 0};
  Vec3 spacing{1, 1, 1};
  Attributes point_data;
  Attributes cell_data;
  Attributes field_data;

  [[nodiscard]] std::size_t num_points() const;
  [[nodiscard]] std::size_t num_cells() const { return structured_cell_count(dims); }
  [[nodiscard]] Index point_id(Index i, Index j, Index k) const {
    return i + dims[0] * (j + dims[1] * k);
  }
  [[nodiscard]] Vec3 point(Index i, Index j, Index k) const {
    return {origin.x + static_cast<double>(i) * spacing.x,
            origin.y + static_cast<double>(j) * spacing.y,
            origin.z + static_cast<double>(k) * spacing.z};
  }
  [[nodiscard]] Vec3 point(Index id) const;
  [[nodiscard]] Bounds bounds() const;
  /// \throw Error on dims < 1, overflow, non-finite origin/spacing, zero spacing, or
  /// attributes of the wrong length.
  void validate() const;
  friend bool operator==(const ImageData&, const ImageData&) = default;
};

/// Curvilinear grid: structured topology (like `ImageData`) with explicit point coordinates.
/// Cells are hexahedra (3D; VTK hexahedron order), quads (2D), lines (1D).
struct StructuredGrid {
  Dims dims{1, 1, 1};
  Points points;
  Attributes point_data;
  Attributes cell_data;
  Attributes field_data;

  [[nodiscard]] std::size_t num_points() const { return points.size(); }
  [[nodiscard]] std::size_t num_cells() const { return structured_cell_count(dims); }
  [[nodiscard]] Index point_id(Index i, Index j, Index k) const {
    return i + dims[0] * (j + dims[1] * k);
  }
  [[nodiscard]] Bounds bounds() const { return points.bounds(); }
  /// \throw Error if points.size() != product of dims, or attributes have the wrong length.
  void validate() const;
  friend bool operator==(const StructuredGrid&, const StructuredGrid&) = default;
};

/// Polygonal data: points plus four cell arrays. Cell ids run verts, then lines, then polys,
/// then strips (VTK's order), which is the order of `cell_data` tuples.
struct PolyData {
  Points points;
  CellArray verts;   ///< vertex (1 id) or poly-vertex (n ids) cells
  CellArray lines;   ///< line (2 ids) or polyline (n ids) cells
  CellArray polys;   ///< triangle, quad or polygon cells (>= 3 ids)
  CellArray strips;  ///< triangle strips (>= 3 ids)
  Attributes point_data;
  Attributes cell_data;
  Attributes field_data;

  [[nodiscard]] std::size_t num_points() const { return points.size(); }
  [[nodiscard]] std::size_t num_cells() const {
    return verts.size() + lines.size() + polys.size() + strips.size();
  }
  [[nodiscard]] Bounds bounds() const { return points.bounds(); }
  /// \throw Error on out-of-range ids, too-short cells, or attributes of the wrong length.
  void validate() const;
  friend bool operator==(const PolyData&, const PolyData&) = default;
};

/// Unstructured grid: points plus cells of any linear type.
struct UnstructuredGrid {
  Points points;
  std::vector<CellType> types;  ///< one per cell
  CellArray cells;              ///< point ids of each cell, in VTK order for its type
  Attributes point_data;
  Attributes cell_data;
  Attributes field_data;

  [[nodiscard]] std::size_t num_points() const { return points.size(); }
  [[nodiscard]] std::size_t num_cells() const { return types.size(); }
  [[nodiscard]] Bounds bounds() const { return points.bounds(); }
  void add_cell(CellType type, std::span<const Index> ids);
  void add_cell(CellType type, std::initializer_list<Index> ids) {
    add_cell(type, std::span<const Index>(ids.begin(), ids.size()));
  }
  /// \throw Error on mismatched sizes, unknown types, wrong point counts for fixed-size
  /// types, out-of-range ids, or attributes of the wrong length.
  void validate() const;
  friend bool operator==(const UnstructuredGrid&, const UnstructuredGrid&) = default;
};

/// Any dataset. Algorithms that accept any dataset take `const Dataset&` and `std::visit`.
using Dataset = std::variant<ImageData, StructuredGrid, PolyData, UnstructuredGrid>;

/// "image data", "structured grid", "polygonal data", "unstructured grid".
[[nodiscard]] std::string_view dataset_type_name(const Dataset& ds);

[[nodiscard]] std::size_t num_points(const Dataset& ds);
[[nodiscard]] std::size_t num_cells(const Dataset& ds);
[[nodiscard]] Bounds bounds(const Dataset& ds);
[[nodiscard]] Vec3 point(const Dataset& ds, Index id);
[[nodiscard]] const Attributes& point_data(const Dataset& ds);
[[nodiscard]] Attributes& point_data(Dataset& ds);
[[nodiscard]] const Attributes& cell_data(const Dataset& ds);
[[nodiscard]] Attributes& cell_data(Dataset& ds);
[[nodiscard]] const Attributes& field_data(const Dataset& ds);
[[nodiscard]] Attributes& field_data(Dataset& ds);
void validate(const Dataset& ds);

/// Type of cell `cell` of any dataset (voxel/pixel/line/vertex for image data).
[[nodiscard]] CellType cell_type(const Dataset& ds, Index cell);
/// Point ids of cell `cell`, written into `ids` (cleared first), in VTK order for its type.
void cell_point_ids(const Dataset& ds, Index cell, std::vector<Index>& ids);

/// Converts any dataset to an unstructured grid with the same points, cells and attributes.
[[nodiscard]] UnstructuredGrid to_unstructured(const Dataset& ds);

}  // namespace isoforge
