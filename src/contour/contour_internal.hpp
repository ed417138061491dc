#pragma once
// Private pieces shared by the contouring implementations (image, sparse, cells, polydata).

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "isoforge/contour/contour.hpp"

namespace isoforge::contour_detail {

/// Checks the options (values present and finite) and returns the scalar array to contour
/// (`options.array` or the active scalars; one component). \throw Error naming `who`.
const DataArray& contour_scalars(const Attributes& point_data, const ContourOptions& options,
                                 const char* who);

/// Output attribute arrays of a contour: every input point array interpolated along crossed
/// edges, every cell array copied to the output cells, and optional normals. Thread-safe for
/// writes to distinct output indices.
class InterpolatedArrays {
 public:
  InterpolatedArrays() = default;
  InterpolatedArrays(const Attributes& point_data, const Attributes& cell_data, std::size_t points,
                     std::size_t cells, bool attributes, bool normals);

  /// Output point `out` = lerp(input point a, input point b, t) for every point array.
  void interpolate(std::size_t out, std::size_t a, std::size_t b, double t) const;
  /// A weighted input point (id, weight).
  using Term = std::pair<std::size_t, double>;
  /// Output point `out` = sum of weight * input point over `terms`, for every point array.
  void combine(std::size_t out, std::span<const Term> terms) const;
  /// Output cell `out` takes input cell `in`'s tuple of every cell array.
  void copy_cell(std::size_t out, std::size_t in) const;
  /// Moves the arrays (and "Normals" if requested) into the output's attributes.
  void move_into(Attributes& point_data, Attributes& cell_data);

  [[nodiscard]] bool has_point_arrays() const { return !interp_.empty(); }

  float* normals = nullptr;  ///< 3 floats per output point when normals were requested
  bool cell_data = false;    ///< whether there are cell arrays to copy

 private:
  using InterpFn = void (*)(const DataArray&, DataArray&, std::size_t, std::span<const Term>);
  using CopyFn = void (*)(const DataArray&, DataArray&, std::size_t, std::size_t);
  const Attributes* src_points_ = nullptr;
  const Attributes* src_cells_ = nullptr;
  Attributes points_, cells_;
  std::vector<InterpFn> interp_;
  std::vector<CopyFn> copy_;
  DataArray normal_array_;
  bool has_normals_ = false;
};

/// Adds the Int32 point array "IsovalueIndex" filled with `index`.
void add_isovalue_index(PolyData& pd, int index);

/// Concatenates polydata with the same point/cell array layout (ids offset; cell data in the
/// verts, lines, polys order of the result).
[[nodiscard]] PolyData append_polydata(std::vector<PolyData> parts);

/// Reverses cells when options.flip is set, then computes "Normals" from the triangles when
/// options ask for ContourNormals::Triangles.
void finish_output(PolyData& pd, const ContourOptions& options);

/// A triangle mesh of `points` float points and `triangles` triangles, all uninitialized (the
/// parallel passes write every point, offset and id, and are the first to touch the memory).
[[nodiscard]] inline PolyData triangle_output(std::size_t points, std::size_t triangles) {
  PolyData pd;
  pd.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, points));
  pd.polys.offsets().resize(triangles + 1);
  pd.polys.connectivity().resize(3 * triangles);
  return pd;
}

/// The driver every contour shares: part(v) contours isovalue options.values[v]; each part's
/// points are tagged with IsovalueIndex v, progress is reported after each, and the parts come
/// back appended and finished (finish_output).
template <class Part>
[[nodiscard]] PolyData contour_each_value(const ContourOptions& options, Part&& part) {
  const std::size_t n = options.values.size();
  std::vector<PolyData> parts;
  parts.reserve(n);
  for (std::size_t v = 0; v < n; ++v) {
    parts.push_back(part(v));
    add_isovalue_index(parts.back(), static_cast<int>(v));
    report_progress(options.progress, static_cast<double>(v + 1) / static_cast<double>(n), "contour");
  }
  PolyData out = append_polydata(std::move(parts));
  finish_output(out, options);
  return out;
}

/// Marching squares on images with fewer than three dimensions > 1 (contour_lines.cpp):
/// polylines joined into continuous lines (1D images give vertices).
[[nodiscard]] PolyData contour_image_2d(const ImageData& input, const ContourOptions& options,
                                        ContourStats* stats);

/// Marching cells on structured and unstructured grids (contour_cells.cpp): 3D cells give
/// triangles, 2D cells polylines, 1D cells vertices; points merged by cell edge.
[[nodiscard]] PolyData contour_cells(DatasetRef input, const ContourOptions& options,
                                     ContourStats* stats);

/// Isolines of polygons and crossing points of lines of polygonal data (contour_lines.cpp).
[[nodiscard]] PolyData contour_polydata(const PolyData& input, const ContourOptions& options,
                                        ContourStats* stats);

}  // namespace isoforge::contour_detail
