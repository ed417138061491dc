#pragma once
/// \file
/// Marching cubes directly on a sparse OpenVDB float grid, with exactly the conventions and
/// results of the dense contour (`contour_image`, see contour.hpp). This is the one contour
/// header that includes OpenVDB.

#include <cstddef>

#include <openvdb/openvdb.h>

#include "isoforge/contour/contour.hpp"

namespace isoforge {

/// Statistics of a sparse contouring run: the common ones plus what was visited.
struct VdbContourStats : ContourStats {
  std::size_t leaves = 0;  ///< leaf nodes of the grid's tree
  std::size_t blocks = 0;  ///< 8³ blocks of cells visited: the leaves and their -x/-y/-z neighbours
  /// Cells left out because the isosurface crosses one of their edges between two voxels that
  /// both lie outside leaf nodes (tiles or background on opposite sides of the isovalue: the
  /// assumption below does not hold). 0 for well-formed narrow-band level sets.
  std::size_t skipped_cells = 0;
};

using VdbContourResult = Result<PolyData, VdbContourStats>;

/// Contours a float grid on its sparse tree: only the cells (cubes of 8 voxels) that touch a
/// voxel of a leaf node are visited, i.e. the cells whose min corner lies in a leaf or in one of
/// the -x/-y/-z neighbouring 8³ blocks; corner values are read through a value accessor, so
/// inactive voxels and tiles contribute their stored values (for level sets, ±background).
///
/// **Assumption:** tiles and background regions do not straddle the isovalue, neither within
/// themselves (a tile has one value) nor against each other: wherever the surface passes, the
/// voxels are stored in leaf nodes. This holds for narrow-band level sets and for fog volumes
/// whose regions at or above the isovalue are surrounded by leaves. Cells where it fails are
/// left out (counted in `VdbContourStats::skipped_cells`), leaving a hole.
///
/// Conventions and output are those of `contour_image` applied to the same samples: voxel
/// (i, j, k) is the sample at world position translation + (i, j, k) * voxel size, above means
/// value ≥ isovalue, crossings are clamped to [1/1024, 1 − 1/1024] of the edge, ambiguous faces
/// use the asymptotic decider, cell-interior points and triangle orientation come from the same
/// case table. So for a grid whose values equal an image's samples on every cell the surface
/// touches, the points (coordinates and values), triangles and orientation are identical; only
/// their order differs (here by leaf block, sorted by origin).
///
/// Options: `values` are isovalues in the grid's value units; `array` must be empty or the
/// grid's name; `normals` Gradient (central differences through the accessor, interpolated) and
/// Triangles are supported; `flip`; `interpolate_attributes` adds the grid values interpolated
/// onto the points as the active scalars named after the grid ("Scalars" if unnamed), like the
/// dense contour of `vdb_to_image(grid)`. The output always has the Int32 point array
/// "IsovalueIndex".
///
/// Multi-threaded (TBB: a count pass, prefix sums, a generate pass; no locks), deterministic: the
/// output is identical for any number of threads. Memory: a few hundred bytes per visited block
/// plus the output; nothing proportional to the index bounding box.
/// \throw Error if the transform is not a uniform scale + translation, the values are empty or
/// not finite, or `array` names another array.
[[nodiscard]] VdbContourResult contour_vdb(const openvdb::FloatGrid& grid,
                                           const ContourOptions& options = {});

}  // namespace isoforge
