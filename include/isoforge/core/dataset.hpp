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

/// Any dataset (owning). Readers return it; algorithms that accept any dataset take a
/// `DatasetRef`, which binds to a `Dataset` or to any concrete dataset without copying it.
using Dataset = std::variant<ImageData, StructuredGrid, PolyData, UnstructuredGrid>;

/// A visitor made of several lambdas, one per dataset type (or `auto` for the rest):
/// `ds.visit(Overloaded{[](const ImageData& d) {...}, [](const auto& d) {...}})`.
template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

/// A non-owning reference to any dataset: constructible (implicitly, for free) from
/// `ImageData`, `StructuredGrid`, `PolyData`, `UnstructuredGrid` or `Dataset`. Passing a concrete
/// dataset where a `const Dataset&` was expected would copy it into a temporary variant; a
/// `DatasetRef` never copies. The referenced dataset must outlive the reference.
class DatasetRef {
 public:
  DatasetRef(const ImageData& d) : p_(&d) {}         // NOLINT(google-explicit-constructor)
  DatasetRef(const StructuredGrid& d) : p_(&d) {}    // NOLINT(google-explicit-constructor)
  DatasetRef(const PolyData& d) : p_(&d) {}          // NOLINT(google-explicit-constructor)
  DatasetRef(const UnstructuredGrid& d) : p_(&d) {}  // NOLINT(google-explicit-constructor)
  DatasetRef(const Dataset& d)                       // NOLINT(google-explicit-constructor)
      : p_(std::visit([](const auto& x) -> Pointer { return &x; }, d)) {}

  /// 0 image data, 1 structured grid, 2 polygonal data, 3 unstructured grid (as `Dataset`).
  [[nodiscard]] std::size_t index() const { return p_.index(); }
  /// The dataset if it is a T, else nullptr.
  template <class T>
  [[nodiscard]] const T* get_if() const {
    const T* const* p = std::get_if<const T*>(&p_);
    return p ? *p : nullptr;
  }
  /// Calls f(const T&) with the concrete dataset.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit([&f](const auto* p) -> decltype(auto) { return f(*p); }, p_);
  }
  /// A copy as an owning `Dataset`.
  [[nodiscard]] Dataset copy() const {
    return visit([](const auto& d) { return Dataset(d); });
  }

 private:
  using Pointer = std::variant<const ImageData*, const StructuredGrid*, const PolyData*,
                               const UnstructuredGrid*>;
  Pointer p_;
};

/// "image data", "structured grid", "polygonal data", "unstructured grid".
[[nodiscard]] std::string_view dataset_type_name(DatasetRef ds);

[[nodiscard]] std::size_t num_points(DatasetRef ds);
[[nodiscard]] std::size_t num_cells(DatasetRef ds);
[[nodiscard]] Bounds bounds(DatasetRef ds);
[[nodiscard]] Vec3 point(DatasetRef ds, Index id);
[[nodiscard]] const Attributes& point_data(DatasetRef ds);
[[nodiscard]] Attributes& point_data(Dataset& ds);
[[nodiscard]] const Attributes& cell_data(DatasetRef ds);
[[nodiscard]] Attributes& cell_data(Dataset& ds);
[[nodiscard]] const Attributes& field_data(DatasetRef ds);
[[nodiscard]] Attributes& field_data(Dataset& ds);
void validate(DatasetRef ds);

/// The type of a polygonal data cell of `size` points in `section` (0 verts, 1 lines, 2 polys,
/// 3 strips): vertex or poly vertex, line or polyline, triangle, quad or polygon, strip.
[[nodiscard]] CellType poly_cell_type(int section, std::size_t size);
/// Type of cell `cell` of any dataset (voxel/pixel/line/vertex for image data).
[[nodiscard]] CellType cell_type(DatasetRef ds, Index cell);
/// Point ids of cell `cell`, written into `ids` (cleared first), in VTK order for its type.
void cell_point_ids(DatasetRef ds, Index cell, std::vector<Index>& ids);

/// Converts any dataset to an unstructured grid with the same points, cells and attributes.
[[nodiscard]] UnstructuredGrid to_unstructured(DatasetRef ds);

}  // namespace isoforge
