#pragma once
/// \file
/// Clipping (VTK's vtkClipDataSet / vtkTableBasedClipDataSet): the part of a dataset on one side
/// of F(x) = c, cells split along the surface. Method and measurements: docs/algorithms/cut.md.
///
/// A point is *above* when F ≥ c. Cells entirely on the kept side are kept unchanged; cells with
/// points on both sides are decomposed into simplices (tetrahedra, triangles, lines; quad faces
/// split along the diagonal from their smallest point id; voxels and hexahedra into 6 tetrahedra
/// around their main diagonal where their faces allow it, else, like wedges, around an added
/// centre point, a quad face wholly on one side as one pyramid) and each piece is clipped.
/// Neighbouring cells share their cut points (one per crossed edge), and a quad face wholly kept
/// stays one quad in the cut cell too (the base of a pyramid or hexahedron piece), so faces
/// conform. Point arrays are interpolated, cell arrays copied from the cell each piece came from.

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/implicit/function.hpp"

namespace isoforge {

struct ClipOptions {
  double value = 0;                    ///< clip value c, units of F
  bool inside_out = false;             ///< false: keep F ≥ c (outside); true: keep F < c (inside)
  bool interpolate_attributes = true;  ///< interpolate point data, copy cell data
  ProgressCallback progress;           ///< fraction done; false cancels
};

struct ClipStats {
  std::size_t points = 0;      ///< output points
  std::size_t cells = 0;       ///< output cells
  std::size_t cells_kept = 0;  ///< input cells kept whole
  std::size_t cells_split = 0; ///< input cells split by the surface
};

/// Clip of polygonal data (stays polygonal) and of the other types (an unstructured grid).
using ClipPolyResult = Result<PolyData, ClipStats>;
using ClipResult = Result<UnstructuredGrid, ClipStats>;

/// Clips any dataset (polygonal data is returned as an unstructured grid here; use `clip_polydata`
/// to keep it polygonal). \throw Error if the value is not finite or the dataset is invalid.
[[nodiscard]] ClipResult clip(DatasetRef input, const ImplicitFunction& f,
                              const ClipOptions& options = {});

/// Clips polygonal data: vertices, lines, polygons and strips are clipped (strips as triangles).
/// \throw Error as `clip`.
[[nodiscard]] ClipPolyResult clip_polydata(const PolyData& input, const ImplicitFunction& f,
                                           const ClipOptions& options = {});

}  // namespace isoforge
