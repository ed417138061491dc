#pragma once
/// \file
/// Contouring (isosurfaces and isolines) of every dataset type: marching cubes on volumes,
/// marching squares on images and slices, marching cells on structured and unstructured grids,
/// and isolines/points on polygonal data.
///
/// **Conventions** (the same for every input type):
/// - A sample counts as *above* when value ≥ isovalue. NaN is undefined (as outside a probed
///   dataset): an edge with a NaN end gives no crossing, and the cells that would use one are
///   left out, so the surface ends at the defined samples.
/// - Crossings are interpolated linearly along cell edges and kept at least 1/1024 of the edge
///   length away from its ends, so a value equal to the isovalue never produces duplicate points
///   or zero-area triangles (the surface passes just beside such a sample).
/// - Ambiguous quad faces are resolved by the asymptotic decider, identically in the two cells
///   sharing the face, so surfaces are watertight and 2-manifold wherever they do not leave the
///   domain.
/// - Orientation: triangle normals (right-hand rule) and computed normals point toward
///   **increasing** values, i.e. out of the region below the isovalue. For implicit functions and
///   distance fields (negative inside) surfaces are therefore outward-oriented. Set `flip` for
///   data whose objects have high values (CT densities, visit counts) to orient them outward.
/// - Points are shared: one point per crossed grid/cell edge (merged by edge, never by
///   coordinates). Every point array of the input is interpolated onto the output points, and
///   cell data is copied to the triangles (or lines) made from each cell.

#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

enum class ContourNormals {
  None,       ///< no normals
  Gradient,   ///< from the scalar gradient (central differences at samples, interpolated)
  Triangles,  ///< area-weighted average of the incident triangles' normals
};

struct ContourOptions {
  std::vector<double> values{0.0};  ///< isovalues (at least one, finite)
  std::string array;                ///< scalar point array to contour; "" = the active scalars
  ContourNormals normals = ContourNormals::None;
  bool interpolate_attributes = true;  ///< interpolate point data, copy cell data
  bool flip = false;                   ///< orient toward decreasing values instead
  ProgressCallback progress;           ///< fraction done; false cancels
};

/// Statistics of a contouring run.
struct ContourStats {
  std::size_t points = 0;
  std::size_t cells = 0;         ///< triangles (3D), line segments (2D) or vertices (1D)
  std::size_t ambiguous_faces = 0;  ///< face decisions made by the asymptotic decider
};

using ContourResult = Result<PolyData, ContourStats>;

/// Contours any dataset: 3D image data, structured and unstructured grids give triangles; 2D
/// images (one dimension of 1) and polygons give polylines joined into continuous lines; lines
/// give vertices. The output holds the point array "IsovalueIndex" (Int32: which of
/// `options.values` each point belongs to), the interpolated input point arrays and, with
/// normals, "Normals". \throw Error if the array is missing or has more than one component, the
/// values are empty or not finite, normals from triangles are asked of an input without 3D cells
/// (its contour has no triangles), or the dataset is invalid.
[[nodiscard]] ContourResult contour(DatasetRef input, const ContourOptions& options = {});

/// `contour` of image data: marching cubes on 3D images (Flying Edges' multi-pass organisation
/// on bit planes, docs/algorithms/contour.md), marching squares on 2D ones. Deterministic: the
/// output is identical for any number of threads. \throw Error as `contour`.
[[nodiscard]] ContourResult contour_image(const ImageData& input, const ContourOptions& options = {});

}  // namespace isoforge
