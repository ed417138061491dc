#pragma once
/// \file
/// Cell machinery shared by probing, cutting and contouring: parametric coordinates, shape
/// functions and their derivatives, world <-> parametric mapping, world-space derivatives, and
/// edge/face tables, for every linear cell type of `CellType`.
///
/// References implemented:
/// - W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit* (4th ed.), chapter 8
///   "Advanced Data Representation": the linear cell types, their point orderings, parametric
///   coordinates and isoparametric interpolation functions, and the Newton iteration for
///   parametric coordinates of a world point (the definitions VTK's vtkCell subclasses use).
/// - M. S. Floater, "Mean value coordinates", CAGD 20 (2003), and K. Hormann, M. S. Floater,
///   "Mean value coordinates for arbitrary planar polygons", ACM TOG 25 (2006): polygon weights.
/// - C. Ericson, *Real-Time Collision Detection* (2005), 5.1: closest point on a triangle.
///
/// ## Conventions
/// Point orderings and parametric coordinates (r, s, t) follow VTK:
///
/// | type | points (parametric coordinates) | shape functions |
/// |---|---|---|
/// | vertex | 0:(0,0,0) | 1 |
/// | line | 0:(0), 1:(1) | 1-r, r |
/// | triangle | 0:(0,0), 1:(1,0), 2:(0,1) | 1-r-s, r, s |
/// | pixel | 0:(0,0), 1:(1,0), 2:(0,1), 3:(1,1) (voxel order) | bilinear |
/// | quad | 0:(0,0), 1:(1,0), 2:(1,1), 3:(0,1) (counter-clockwise) | bilinear |
/// | tetra | 0:(0,0,0), 1:(1,0,0), 2:(0,1,0), 3:(0,0,1) | 1-r-s-t, r, s, t |
/// | voxel | point i at (i&1, (i>>1)&1, (i>>2)&1) | trilinear |
/// | hexahedron | base 0-3 as the quad at t=0, top 4-7 above them at t=1 | trilinear |
/// | wedge | base triangle 0-2 at t=0, top 3-5 at t=1 | triangle(r,s) x linear(t) |
/// | pyramid | base quad 0-3 at t=0, apex 4 at (0.5,0.5,1) | (quad weights)(1-t), t |
///
/// The parametric domain is the unit interval / square / cube, except for the simplices
/// (r,s,t >= 0, r+s+t <= 1) and the wedge (r,s >= 0, r+s <= 1, 0 <= t <= 1). The pyramid's
/// domain is the unit cube collapsed at t = 1 (VTK's definition: every (r,s,1) is the apex).
/// VTK's valid wedge has its base (0,1,2) ordered so that the right-hand normal points *away*
/// from (3,4,5), so its Jacobian determinant is negative; every other type has a positive one.
/// Nothing here depends on the sign.
///
/// Composite cells are handled through sub-cells, addressed by `sub_id`:
/// - poly-vertex: sub-cell i is vertex i;
/// - polyline: sub-cell i is the line (i, i+1);
/// - triangle strip: sub-cell i is the triangle (i, i+1, i+2) for even i and (i+1, i, i+2) for
///   odd i (consistently oriented; VTK's strip uses (i, i+1, i+2) for parametric purposes).
/// Parametric coordinates of a composite cell are those of its sub-cell `sub_id`.
///
/// A polygon has one parametric system: the rectangle bounding the polygon in its own plane
/// (normal by Newell's method, r axis along the first non-degenerate edge from point 0), scaled
/// to [0,1]^2 (t = 0). Its interpolation weights at a point are the mean value coordinates of
/// the point with respect to the polygon projected into that plane (well defined for non-convex
/// polygons, reproduce linear functions exactly for planar polygons).
///
/// Derivative arrays (`interpolation_derivatives`) use VTK's layout: all d/dr first, then all
/// d/ds, then all d/dt: `derivs[d * n + i]` is d N_i / d p_d, with n the number of points.
/// Field values are point-major: `values[i * components + c]` (the `DataArray` layout).
///
/// Every function throws `isoforge::Error` for `CellType::Empty`, a wrong number of points for
/// the type, a non-finite point / parametric coordinate / world point / value / tolerance, or
/// an out-of-range `sub_id`, edge or face index.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "isoforge/core/cell_type.hpp"
#include "isoforge/core/vec.hpp"

namespace isoforge {

/// Largest number of points of a fixed-size cell type (voxel, hexahedron).
inline constexpr int kMaxCellPoints = 8;

/// Default parametric tolerance of `locate_in_cell`.
inline constexpr double kDefaultCellTolerance = 1e-9;

/// Interpolation weights of the points of one cell: a small vector that stores up to
/// `kMaxCellPoints` values inline (no allocation for fixed-size cells) and grows on the heap
/// for longer polygons, polylines, strips and poly-vertices.
class CellWeights {
 public:
  CellWeights() = default;
  /// `n` zero weights.
  explicit CellWeights(std::size_t n) { resize(n); }

  /// Resizes to `n` weights, all zero.
  void resize(std::size_t n);
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] double* data() { return size_ <= inline_.size() ? inline_.data() : heap_.data(); }
  [[nodiscard]] const double* data() const {
    return size_ <= inline_.size() ? inline_.data() : heap_.data();
  }
  [[nodiscard]] double& operator[](std::size_t i) { return data()[i]; }
  [[nodiscard]] double operator[](std::size_t i) const { return data()[i]; }
  [[nodiscard]] std::span<double> span() { return {data(), size_}; }
  [[nodiscard]] std::span<const double> span() const { return {data(), size_}; }
  [[nodiscard]] double* begin() { return data(); }
  [[nodiscard]] double* end() { return data() + size_; }
  [[nodiscard]] const double* begin() const { return data(); }
  [[nodiscard]] const double* end() const { return data() + size_; }

 private:
  std::size_t size_ = 0;
  std::array<double, kMaxCellPoints> inline_{};
  std::vector<double> heap_;
};

// ---------------------------------------------------------------------------------------------
// Parametric space of fixed-size types
// ---------------------------------------------------------------------------------------------

/// Parametric coordinates of the points of a fixed-size type, in point order (unused
/// coordinates are 0). \throw Error for variable-size types (poly-vertex, polyline, strip,
/// polygon) and `Empty`.
[[nodiscard]] std::span<const Vec3> parametric_points(CellType type);

/// Parametric center of a type: the parametric point that maps to the centroid of the cell's
/// points for an affine-shaped cell, e.g. (1/3, 1/3, 0) for a triangle, (0.5, 0.5, 0.5) for a
/// hexahedron, (0.5, 0.5, 0.2) for a pyramid (VTK uses (0.4, 0.4, 0.2)). Composite types give
/// the center of their sub-cell type (vertex, line, triangle); a polygon (0.5, 0.5, 0).
/// \throw Error for `Empty`.
[[nodiscard]] Vec3 parametric_center(CellType type);

/// How far `pcoords` lies outside the parametric domain of `type` (0 if inside or on the
/// boundary): the largest violation of a domain inequality, e.g. max(-r, -s, -t, r+s+t-1) for
/// a tetra. Composite types use their sub-cell's domain, a polygon [0,1]^2 (a rectangle
/// containing the polygon: only an approximate test for polygons). \throw Error for `Empty` or
/// non-finite pcoords.
[[nodiscard]] double parametric_distance(CellType type, const Vec3& pcoords);

/// Shape functions of a fixed-size type at `pcoords`, written to `weights` (size must equal the
/// type's point count). They sum to 1 and are the Kronecker delta at the cell's points.
/// \throw Error for variable-size types, a wrong `weights` size, non-finite pcoords.
void interpolation_weights(CellType type, const Vec3& pcoords, std::span<double> weights);
/// Same, returned by value.
[[nodiscard]] CellWeights interpolation_weights(CellType type, const Vec3& pcoords);

/// Derivatives d N_i / d(r,s,t) of the shape functions of a fixed-size type at `pcoords`,
/// written to `derivs` (size must be 3 * points) in VTK's layout `derivs[d * n + i]`.
/// Derivatives with respect to coordinates a type does not use (s and t of a line) are 0.
/// \throw Error for variable-size types, a wrong `derivs` size, non-finite pcoords.
void interpolation_derivatives(CellType type, const Vec3& pcoords, std::span<double> derivs);

// ---------------------------------------------------------------------------------------------
// Geometry: any type, given the cell's points in its VTK order
// ---------------------------------------------------------------------------------------------

/// World position of parametric point `pcoords` of (sub-cell `sub_id` of) a cell with the given
/// points. For a polygon, the point of its plane with those coordinates in its bounding
/// rectangle (see the file comment). \throw Error on a wrong point count, non-finite input,
/// or `sub_id` out of range (it must be 0 for non-composite types).
[[nodiscard]] Vec3 evaluate_location(CellType type, std::span<const Vec3> points,
                                     const Vec3& pcoords, int sub_id = 0);

/// Interpolation weights of all the cell's points at parametric point `pcoords` of sub-cell
/// `sub_id` (weights of points outside the sub-cell are 0; a polygon uses mean value
/// coordinates of `evaluate_location(...)`). `weights` is resized to `points.size()`.
/// \throw Error as `evaluate_location`.
void evaluate_weights(CellType type, std::span<const Vec3> points, const Vec3& pcoords, int sub_id,
                      CellWeights& weights);

/// Mean value coordinates (Hormann & Floater) of `x` with respect to a polygon, after projecting
/// `x` and the polygon into the polygon's plane; `weights` is resized to `points.size()`. The
/// weights sum to 1, reproduce linear functions on planar polygons (sum w_i p_i = projection of
/// x), are the Kronecker delta at the vertices and linear along the edges. Non-convex polygons
/// may give negative weights. \throw Error on fewer than 3 points or non-finite input.
void polygon_weights(std::span<const Vec3> points, const Vec3& x, CellWeights& weights);

/// Where a world point lies relative to one cell (the result of `locate_in_cell`).
struct CellPosition {
  /// x lies in the cell (within the parametric tolerance). For 1D and 2D cells this refers to
  /// the projection of x onto the cell (x may lie off the line / surface; see `dist2`); a
  /// projection onto a curved quad that is farther from x than the quad's boundary (a local
  /// minimum of the distance only) does not count.
  bool inside = false;
  /// The parametric coordinates of x were determined (closed form, or Newton converged). False
  /// for degenerate cells (zero length/area/volume, singular Jacobian) and when the Newton
  /// iteration diverged or hit its iteration cap; `pcoords` and `weights` are then those of
  /// `closest_point` when they could be found (else the parametric center), and `inside` is
  /// false.
  bool converged = true;
  /// Sub-cell of a composite cell (poly-vertex, polyline, strip) that is closest to x; else 0.
  int sub_id = 0;
  /// Parametric coordinates of x (of its projection for 1D/2D cells), relative to sub-cell
  /// `sub_id`. Not clamped: outside points get coordinates outside the domain (extrapolation).
  Vec3 pcoords{};
  /// Interpolation weights of all the cell's points at `pcoords` (size = number of points).
  CellWeights weights;
  /// The point of the cell closest to x: x itself if a 3D cell contains it, its projection onto
  /// the cell's line/surface for an inside 1D/2D cell, otherwise the exact closest point of the
  /// boundary (faces, edges or vertices; curved bilinear faces are solved by Newton too).
  Vec3 closest_point{};
  /// Squared distance from x to `closest_point` (0 when a 3D cell contains x).
  double dist2 = 0;
};

/// Finds the parametric coordinates and interpolation weights of world point `x` in a cell,
/// whether x is inside, and its squared distance to the cell.
///
/// Methods: closed form for vertex, line, triangle, tetra, pixel and voxel (pixel/voxel may be
/// any rectangle/box: their edges from point 0 define the axes); Newton iteration on the
/// Jacobian for hexahedron, wedge and pyramid, started at the parametric center, with step
/// halving when the residual grows, divergence detection and an iteration cap (so degenerate
/// cells return instead of hanging). A quad (planar or not) is solved for the orthogonal
/// projection of x onto its bilinear surface: Newton on the squared distance, whose
/// Gauss-Newton form is the square system [dX/dr, dX/ds, n] (dr, ds, dw) = x - X(r, s) (n the
/// unit normal) that VTK uses, with the exact Hessian near the solution, step halving, and
/// restarts from four more points when the first solution is not inside. For outside points
/// the closest point of the cell is computed exactly as the minimum over its faces (3D) or
/// edges (2D), bilinear faces being solved by the same quad projection. Polygons use mean value
/// coordinates in their plane; composite cells pick the sub-cell closest to x (ties: an inside
/// one first, then the lowest sub_id).
///
/// \param type        the cell type
/// \param points      the cell's points, in VTK order for the type
/// \param x           the world point
/// \param tolerance   parametric tolerance (>= 0): x counts as inside if
///                    `parametric_distance(type, pcoords) <= tolerance`; for a polygon, if the
///                    projection is in the polygon or within `tolerance` times the polygon's
///                    extent of its boundary; vertices need dist2 == 0.
/// \throw Error on a wrong point count, non-finite points or x, a negative or non-finite
///        tolerance.
[[nodiscard]] CellPosition locate_in_cell(CellType type, std::span<const Vec3> points,
                                          const Vec3& x, double tolerance = kDefaultCellTolerance);

/// World-space gradient of each component of a field given at the cell's points, at
/// parametric point `pcoords` of sub-cell `sub_id`: `gradients[c]` = grad of component c.
/// Uses the inverse Jacobian; for 2D cells the gradient lies in the tangent plane (the Jacobian
/// is completed with the unit normal), for 1D cells along the line, 0D cells give 0. A polygon
/// gives the least-squares linear fit of the values in its plane (constant over the polygon,
/// exact for linear fields on planar polygons). At a pyramid's apex (t = 1, where the Jacobian
/// is singular) the limit t -> 1 is used. A degenerate cell (singular Jacobian) gives 0.
/// \param values      point-major: `values[i * components + c]`, size points * components
/// \param components  number of components (>= 1)
/// \param gradients   output, size `components`
/// \throw Error on wrong sizes, non-finite input, a bad `sub_id`.
void derivatives(CellType type, std::span<const Vec3> points, const Vec3& pcoords,
                 std::span<const double> values, int components, std::span<Vec3> gradients,
                 int sub_id = 0);
/// Same, returning the `components` gradients.
[[nodiscard]] std::vector<Vec3> derivatives(CellType type, std::span<const Vec3> points,
                                            const Vec3& pcoords, std::span<const double> values,
                                            int components, int sub_id = 0);

// ---------------------------------------------------------------------------------------------
// Topology tables
// ---------------------------------------------------------------------------------------------

/// An edge: two local point ids.
using CellEdge = std::array<int, 2>;

/// A face of a 3D cell: 3 or 4 local point ids, ordered so that the right-hand normal points
/// out of a valid cell (VTK's face tables).
struct CellFace {
  std::array<int, 4> ids{};
  int size = 0;
  [[nodiscard]] std::span<const int> points() const {
    return {ids.data(), static_cast<std::size_t>(size)};
  }
};

/// Edge table of a fixed-size type, VTK's numbering (e.g. hexahedron edges 0-3 bottom, 4-7
/// top, 8-11 vertical; quad {0,1},{1,2},{3,2},{0,3}). Vertex and line have no edges (VTK).
/// \throw Error for variable-size types (use `polygon_edge` / `sub_cell`) and `Empty`.
[[nodiscard]] std::span<const CellEdge> cell_edges(CellType type);

/// Face table of a fixed-size type (3D cells only; lower-dimensional types have none).
/// \throw Error for variable-size types and `Empty`.
[[nodiscard]] std::span<const CellFace> cell_faces(CellType type);

/// Edge `edge` of a polygon with `num_points` points: (edge, (edge + 1) % num_points).
/// \throw Error if num_points < 3 or edge is out of range.
[[nodiscard]] CellEdge polygon_edge(std::size_t num_points, int edge);

/// Whether `type` is composite (poly-vertex, polyline, triangle strip): made of sub-cells.
[[nodiscard]] bool is_composite_cell(CellType type);

/// Triangle `k` of a triangle strip (k + 2 < strip.size()): (k, k+1, k+2) for even k,
/// (k+1, k, k+2) for odd k, so that every triangle keeps the strip's orientation.
template <class Id>
[[nodiscard]] constexpr std::array<Id, 3> strip_triangle(std::span<const Id> strip, std::size_t k) {
  const std::size_t odd = k % 2;
  return {strip[k + odd], strip[k + 1 - odd], strip[k + 2]};
}

/// One sub-cell of a composite cell: its type and local point ids.
struct SubCell {
  CellType type = CellType::Empty;
  std::array<int, 3> ids{};
  int size = 0;
  [[nodiscard]] std::span<const int> points() const {
    return {ids.data(), static_cast<std::size_t>(size)};
  }
};

/// Number of sub-cells of a composite cell with `num_points` points (n, n-1, n-2 for
/// poly-vertex, polyline, strip); 1 for any other type. \throw Error on too few points.
[[nodiscard]] int num_sub_cells(CellType type, std::size_t num_points);

/// Sub-cell `sub_id` of a composite cell (see the file comment for the strip's orientation).
/// \throw Error for non-composite types, too few points, `sub_id` out of range.
[[nodiscard]] SubCell sub_cell(CellType type, std::size_t num_points, int sub_id);

}  // namespace isoforge
