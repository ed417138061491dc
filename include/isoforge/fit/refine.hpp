#pragma once
/// \file
/// Mesh refinement after Hoppe et al.: the vertices of a simplified triangle mesh are moved to
/// fit the original surface better, by alternating closest-point correspondences with sparse
/// linear least-squares solves, and interior edges are flipped where that lowers the error (the
/// same triangle count on the same points; optional). Moves that would flip a face or create a
/// self-intersection are undone, flips that would fold or intersect are not made, and a step
/// that would make the error worse is not taken. Method and measurements:
/// docs/algorithms/fitting.md.

#include <cstddef>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/fit/fit_primitive.hpp"

namespace isoforge {

struct RefineOptions {
  /// Area samples of the original (0 = automatic: every vertex of the original's faces, plus
  /// area-distributed samples up to 10 per simplified triangle). An explicit count gives that
  /// many area-distributed samples and no vertices.
  std::size_t samples = 0;
  int outer_iterations = 8;  ///< solves, each after recomputing the correspondences (≥ 1)
  /// Spring weight κ relative to the data (≥ 0): each edge adds κ (samples / edges) |vi − vj|²
  /// to the energy, which keeps the solve well posed where no sample reaches a vertex.
  double spring = 1e-3;
  /// Robust loss on the sample distances, as weights recomputed each outer iteration
  /// (iteratively reweighted least squares); scale from the median distance as in FitOptions.
  RobustLoss loss = RobustLoss::None;
  /// Border vertices (of edges with one face) and vertices of non-manifold edges do not move,
  /// so the border stays exactly where it was; false lets them move like the others.
  bool keep_boundary = true;
  /// Point array of `simplified` (one component, any type) whose non-zero entries lock a vertex
  /// in place; "" = none.
  std::string lock_array;
  /// Between solves, flip interior edges where the two faces' error falls (Hoppe et al.'s edge
  /// swap; never folding, never intersecting): the output's triangles may then differ from
  /// `simplified`'s, the same count on the same points. Off when `simplified` has cell arrays.
  bool flip_edges = true;
  ProgressCallback progress;  ///< fraction done; false cancels
};

struct RefineStats {
  /// Error between the surfaces, before and after, measured the same way (data units): the
  /// distances from the original's samples to the simplified mesh and from about as many
  /// samples of the simplified mesh (the same stratified points in every triangle) to the
  /// original, RMS over both sets and the largest of them (a sampled symmetric Hausdorff
  /// distance).
  double rms_before = 0, rms_after = 0, hausdorff_before = 0, hausdorff_after = 0;
  std::size_t moved_vertices = 0;  ///< vertices whose position changed
  std::size_t rejected_moves = 0;  ///< vertex moves shortened or undone (flip, intersection)
  int solves = 0;                  ///< least-squares solves made
  int flip_passes = 0;             ///< passes of edge flips kept
  std::size_t flips = 0;           ///< triangles that differ from `simplified`'s at the end
  double seconds = 0;              ///< wall time of the solves alone
  double total_seconds = 0;        ///< wall time of the whole refinement
};

using RefineResult = Result<PolyData, RefineStats>;

/// Moves the points of `simplified` (a triangle mesh) to fit the surface of `original` (its
/// polygons, fan-triangulated, and strips). The output is `simplified` with new coordinates
/// (same point type) and every attribute array unchanged; its triangles are `simplified`'s,
/// except those rewritten by edge flips (`RefineOptions::flip_edges`: as many, in the same
/// order, the flipped pairs in their slots). Its RMS and Hausdorff
/// error are never above the input's. \throw Error naming the mesh and the problem: no
/// triangles, a simplified polygon that is not a triangle or repeats a point, a strip in
/// `simplified`, a non-finite point, an option out of range, or `lock_array` missing or not a
/// one-component point array.
[[nodiscard]] RefineResult refine_mesh(const PolyData& original, const PolyData& simplified,
                                       const RefineOptions& options = {});

}  // namespace isoforge
