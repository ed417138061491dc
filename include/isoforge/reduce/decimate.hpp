#pragma once
/// \file
/// Decimation of triangle meshes: the three operations of the chapter's Fig. 1.37 — quadric edge
/// collapse (Garland–Heckbert), vertex removal (Schroeder's vertex deletion with hole
/// triangulation) and cell collapse (a triangle collapsed to one vertex) — behind one function.
///
/// **Guarantees** (every method): the output never has a face whose normal turns by more than
/// `max_normal_turn` degrees in one operation, and never gains a self-intersection: every new
/// face is tested against the faces near it with exact predicates on the stored coordinates
/// (core/predicates.hpp). With `preserve_topology` (the default) operations that would make a
/// non-manifold edge or vertex, change the genus or close a border loop are refused. Vertices of
/// non-manifold edges and vertices of the input are locked (never moved or removed), so
/// non-manifold input stays as valid as it was. Every point array is carried: the survivors keep
/// theirs, a vertex placed by a collapse gets values interpolated on the collapsed edge.
/// Method and measurements: docs/algorithms/decimation.md.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

enum class DecimateMethod {
  Quadric,        ///< edge collapse ordered by the quadric error, optimal placement
  VertexRemoval,  ///< Schroeder: remove a vertex, triangulate the hole (vtkDecimatePro's family)
  CellCollapse,   ///< collapse a whole triangle to one vertex (cell deletion)
};

struct DecimateOptions {
  DecimateMethod method = DecimateMethod::Quadric;
  /// Stop at this many triangles or just below (0 = not set): an edge collapse removes two
  /// faces (one on a border), so an even target is hit exactly on closed manifold input and an
  /// odd one ends one below; a cell collapse removes up to four, a vertex removal two. A
  /// guarantee or `max_error` may stop earlier (reported in the stats).
  std::size_t target_triangles = 0;
  /// Or stop after removing this fraction of the triangles, in [0, 1) (0 = not set).
  double target_reduction = 0;
  /// Or stop before an operation whose error exceeds this (0 = not set): a distance in data units,
  /// or a fraction of the bounding-box diagonal when `max_error_relative`.
  double max_error = 0;
  bool max_error_relative = false;
  bool preserve_topology =
      true;  ///< link condition: no non-manifold edges/vertices, no genus change
  bool preserve_boundary = true;  ///< constraint planes along border edges (quadric method)
  /// Quadric method: place each merged vertex where the faces around the edge enclose the same
  /// volume as before (Lindstrom–Turk's volume constraint), minimising the quadric on that
  /// plane. Lower RMS distance (a surface does not shrink where it curves); `false`: the
  /// quadric's unconstrained minimum (Garland–Heckbert), the lowest maximum distance on some
  /// shapes.
  bool preserve_volume = true;
  /// Weight of the border (and feature) constraint planes, × the edge length squared (≥ 0).
  /// 10 keeps borders in place as well as 1000 does on the verify cases, with lower errors.
  double boundary_weight = 10;
  /// Edges whose dihedral angle exceeds this (degrees, in (0, 180]) are features: their vertices
  /// get constraint planes (quadric) or are not removed (vertex removal). 180 = no features.
  double feature_angle = 180;
  double max_normal_turn = 90;  ///< refuse operations turning a face normal by more (degrees)
  bool check_self_intersections = true;  ///< exact test of every new face (the guarantee above)
  /// Point array (one component, any type) whose non-zero entries lock a vertex; "" = none.
  std::string lock_array;
  /// Weight of point-array differences in the collapse cost (quadric method; 0 =
  /// geometry only, as vtkQuadricDecimation's default): each array is scaled by its range, and a
  /// full-range difference across an edge costs like moving its faces by this fraction of the
  /// bounding-box diagonal. Arrays are carried either way.
  double attribute_weight = 0;
  ProgressCallback progress;  ///< fraction done; false cancels
};

/// Why decimation stopped.
enum class DecimateStop {
  Target,     ///< the requested count was reached
  MaxError,   ///< the next operation would exceed `max_error`
  Exhausted,  ///< every remaining operation is refused by a guarantee (see the counters)
};

struct DecimateStats {
  std::size_t input_triangles = 0;
  std::size_t output_triangles = 0;
  std::size_t output_points = 0;
  std::size_t operations = 0;  ///< collapses or removals done
  double max_error = 0;        ///< largest error of an accepted operation (data units)
  DecimateStop stop = DecimateStop::Target;
  std::size_t locked_vertices = 0;       ///< by mask or non-manifold input
  std::size_t refused_topology = 0;      ///< candidates refused by the link condition / topology
  std::size_t refused_flip = 0;          ///< refused for turning a normal too far
  std::size_t refused_intersection = 0;  ///< refused for creating a self-intersection
  /// Runs redone because the test of the finished mesh found an intersection made by a merge
  /// whose test had been deferred (each tests more merges as they are made).
  std::size_t intersection_reruns = 0;
};

using DecimateResult = Result<PolyData, DecimateStats>;

/// Decimates the triangles of `input` (polygons are fan-triangulated first; strips split; lines
/// and vertices are dropped) to the first stop that `options` sets. The output is triangles with
/// the survivors' points compacted and every point array carried; cell data is dropped. \throw
/// Error if no stop is set, an option is out of range or not finite, the input has no triangle
/// or an invalid cell, or `lock_array` is missing or not a one-component point array.
[[nodiscard]] DecimateResult decimate(const PolyData& input, const DecimateOptions& options = {});

/// Name of a method ("quadric", "vertex-removal", "cell-collapse") and of a stop reason.
[[nodiscard]] const char* to_string(DecimateMethod method);
[[nodiscard]] const char* to_string(DecimateStop stop);

}  // namespace isoforge
