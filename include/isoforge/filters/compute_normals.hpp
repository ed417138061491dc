#pragma once
/// \file
/// Surface normals (VTK's vtkPolyDataNormals): polygons oriented consistently over each
/// connected surface (outward on closed ones), optional splitting of points along sharp edges,
/// then cell normals and area-weighted point normals (core/normals.hpp).
/// See docs/algorithms/glyph.md.

#include <cstddef>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

struct NormalsOptions {
  bool point_normals = true;   ///< add the point array "Normals" (Float32, unit)
  bool cell_normals = true;    ///< add the cell array "Normals" (Float32, unit; 0 on verts/lines)
  bool consistency = true;     ///< reorder polygons so neighbours across an edge agree
  bool auto_orient = true;     ///< closed surfaces: outward (positive volume); open ones: the
                               ///< orientation most of their polygons had (needs consistency)
  bool flip = false;           ///< reverse every polygon (after the above)
  bool split = true;           ///< duplicate points along edges sharper than feature_angle
  double feature_angle = 30;   ///< degrees, in [0, 180]: edges whose polygons' normals differ
                               ///< by more are sharp
  ProgressCallback progress{};
};

struct NormalsStats {
  std::size_t surfaces = 0;         ///< connected components of polygons (across shared edges)
  std::size_t closed_surfaces = 0;  ///< of which closed (every edge in exactly two polygons)
  std::size_t flipped_polygons = 0; ///< polygons whose order was reversed
  std::size_t split_points = 0;     ///< points added by splitting
  std::size_t non_manifold_edges = 0;   ///< edges of three or more polygons (never crossed)
  std::size_t inconsistent_edges = 0;   ///< manifold edges left disagreeing (Möbius-like)
};

/// `input` with its polygons oriented and, if `split`, points duplicated along sharp edges
/// (new points at the end, copying the point data; the first group of polygons around a point
/// keeps it), with "Normals" point and cell arrays (active roles). Triangle strips become
/// triangles (their cell data repeated); verts and lines are kept.
/// \throw Error if the feature angle is outside [0, 180] or the input is invalid.
[[nodiscard]] Result<PolyData, NormalsStats> compute_normals(const PolyData& input,
                                                             const NormalsOptions& options = {});

}  // namespace isoforge
