#pragma once
// Accuracy checks of the verification suite: side of an implicit function within float storage
// tolerance, distance to analytic truth (one-sided Hausdorff both ways and RMS), mesh-to-mesh
// distance, relative errors, observed order of convergence, borders on the domain boundary and
// exact identity of two surfaces.
//
// Hausdorff sampling method. mesh -> surface: every triangle is sampled on a barycentric grid
// of n subdivisions (n = max(min_subdivisions, ceil(longest edge / spacing)) rounded up to even,
// so the edge midpoints are samples) plus its centroid, the grid nodes weighted by the area they
// stand for (composite vertex rule: corner 1/3, edge 1, interior 2 small-triangle areas; the
// centroid counts in the maxima only), so RMS values are area integrals that favour neither
// corners nor edges; the distance of a sample to an analytic
// surface is |F| of the surface's exact signed distance function, so only the sampling (not the
// distance) is approximate. surface -> mesh: area-uniform deterministic points on the analytic
// surface (Fibonacci lattice on the sphere, inverse-CDF grid on the torus) about `spacing` apart,
// each measured to the mesh with an exact closest-triangle search in CGAL's AABB tree
// (mesh_distance.hpp). mesh <-> mesh: the first mesh's barycentric-grid samples against the
// second's AABB tree, and the other way.

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/implicit/function.hpp"

namespace isoforge::verify {

// ---- side of an implicit function -------------------------------------------------------------

enum class Side {
  Inside,   ///< F <= tol
  Outside,  ///< F >= -tol
  On,       ///< |F| <= tol
};

/// Per-point tolerance of the side check: `ulps` units in the last place, in the points' storage
/// type (float32 or float64), of max(largest |coordinate| of p, `scale`), times |grad F| at p.
/// Rounding a point computed in double to its storage moves it by at most half an ulp per
/// coordinate, which moves F by at most |grad F| (sqrt(3) / 2) ulp. `scale` is the magnitude of
/// the coordinates the point was computed from (e.g. the largest |coordinate| of the input of a
/// cut): a point interpolated between grid points carries their rounding, not its own.
[[nodiscard]] double side_tolerance(const Vec3& p, ScalarType storage, const Vec3& gradient,
                                    double ulps, double scale = 0);

struct SideReport {
  std::size_t points = 0;
  std::size_t violations = 0;  ///< points on the wrong side beyond their tolerance
  /// Points on the wrong side of F = 0 (for On: off it) but within their tolerance: what the
  /// exact test would reject and float storage explains.
  std::size_t within_tolerance = 0;
  /// Largest (F / tol) for Inside, (-F / tol) for Outside, |F| / tol for On, over all points
  /// (<= 1 passes; negative when every point is strictly on the required side).
  double worst_ratio = -1e300;
  double worst_value = 0;  ///< F at the worst point
  std::size_t worst_point = 0;
};

/// Checks that every point lies on `side` of `f` (F < 0 inside) within `side_tolerance`.
[[nodiscard]] SideReport check_side(const Points& points, const ImplicitFunction& f, Side side,
                                    double ulps = 4, double scale = 0);

// ---- sampling -------------------------------------------------------------------------------

/// Points with weights (each weight: the area a sample stands for).
struct Samples {
  std::vector<Vec3> points;
  std::vector<double> weights;
};

/// Barycentric-grid samples of the polygons and strips of `mesh` (see the file comment).
/// Collinear (zero-area) triangles contribute their corners only.
[[nodiscard]] Samples sample_mesh(const PolyData& mesh, double spacing, int min_subdivisions = 2);

/// Mean length of the triangle edges of `mesh` (each triangle's three edges; 0 without faces).
[[nodiscard]] double mean_edge_length(const PolyData& mesh);

/// An analytic closed surface: its exact signed distance function (negative inside), area,
/// enclosed volume and an area-uniform sampler.
struct AnalyticSurface {
  std::string name;
  ImplicitFunction sdf;
  double area = 0;
  double volume = 0;
  /// Area-uniform points on the surface about `spacing` apart (deterministic).
  std::function<std::vector<Vec3>(double spacing)> sample;
};

[[nodiscard]] AnalyticSurface sphere_surface(const Vec3& center, double radius);
/// Torus around `axis` (any non-zero vector) through `center`, ring radius `major`, tube `minor`.
[[nodiscard]] AnalyticSurface torus_surface(const Vec3& center, const Vec3& axis, double major,
                                            double minor);

// ---- distances ------------------------------------------------------------------------------

/// One-sided distances both ways between two surfaces A (the mesh) and B.
struct DistanceReport {
  double max_a_to_b = 0;  ///< one-sided Hausdorff A -> B (max over A's samples)
  double rms_a_to_b = 0;  ///< area-weighted RMS over A's samples
  double max_b_to_a = 0;
  double rms_b_to_a = 0;
  std::size_t samples_a = 0;
  std::size_t samples_b = 0;
  [[nodiscard]] double hausdorff() const {
    return max_a_to_b > max_b_to_a ? max_a_to_b : max_b_to_a;
  }
};

/// Mesh (A) against an analytic surface (B): mesh -> surface by |F| at `sample_mesh(mesh,
/// mesh_spacing)`, surface -> mesh by `surface.sample(surface_spacing)` and the AABB tree.
/// \throw Error if the mesh has no non-degenerate triangle.
[[nodiscard]] DistanceReport distance_to_surface(const PolyData& mesh,
                                                 const AnalyticSurface& surface,
                                                 double mesh_spacing, double surface_spacing);

/// Approximate Hausdorff distance both ways between two meshes: each mesh's `sample_mesh`
/// samples at `spacing` against the other's AABB tree. The sampled maxima are lower bounds of
/// the one-sided Hausdorff distances, approaching them as the spacing shrinks.
[[nodiscard]] DistanceReport mesh_to_mesh_distance(const PolyData& a, const PolyData& b,
                                                   double spacing);

// ---- errors and convergence -----------------------------------------------------------------

struct AreaVolume {
  double area = 0;
  double volume = 0;  ///< signed (divergence theorem): positive for outward closed surfaces
};

/// Area and signed enclosed volume of the polygons and strips of `mesh`, in double.
[[nodiscard]] AreaVolume area_and_volume(const PolyData& mesh);

/// |measured - truth| / |truth|.
[[nodiscard]] double relative_error(double measured, double truth);

/// Observed order of convergence: the least-squares slope of log(error) against log(h).
/// \throw Error unless there are at least two pairs, sizes match and all values are > 0.
[[nodiscard]] double convergence_order(std::span<const double> h, std::span<const double> error);

// ---- borders and identity ---------------------------------------------------------------------

struct BorderReport {
  std::size_t border_edges = 0;
  std::size_t off_boundary = 0;  ///< border edges not lying in one face plane of the domain
};

/// Border edges (edges of exactly one triangle) and those of them that do not have both ends
/// within `tol` of the same face plane of `domain` (a surface cut by the domain boundary may
/// only have borders there).
[[nodiscard]] BorderReport check_borders(const PolyData& mesh, const Bounds& domain, double tol);

struct SurfaceComparison {
  std::size_t points_a = 0, points_b = 0;  ///< points used by a triangle
  std::size_t triangles_a = 0, triangles_b = 0;
  bool same_points = false;     ///< identical sets of coordinates (exactly, as stored)
  bool same_triangles = false;  ///< identical sets of oriented triangles (as coordinate triples)
  [[nodiscard]] bool identical() const { return same_points && same_triangles; }
};

/// Compares two triangle surfaces up to the numbering of points and triangles and the cyclic
/// order of each triangle's corners (orientation must match).
[[nodiscard]] SurfaceComparison compare_surfaces(const PolyData& a, const PolyData& b);

}  // namespace isoforge::verify
