#pragma once
/// \file
/// Connectivity segmentation of polygonal data (section 1.5.3, Fig. 1.29): contouring a concave
/// generator gives several separate surfaces; labeling the connected components of the result
/// separates them, so each can be colored, measured or extracted on its own. The peer is VTK's
/// vtkPolyDataConnectivityFilter.
///
/// **Components.** Two cells (verts, lines, polys, strips alike) are *connected* when they share
/// a point (`ConnectedBy::Point`, the default, as VTK) or an edge (`ConnectedBy::Edge`); a
/// component is a maximal set of cells connected through chains of such neighbours. Points used
/// by no cell belong to no component.
///
/// **Numbering.** Components are numbered by decreasing size, ties broken by the smallest cell
/// id in the component, so component 0 is the largest and the numbering does not depend on
/// anything but the input. The size is the number of cells (`ComponentSize::Cells`, default) or
/// the total area of the component's polygons and strips (`ComponentSize::Area`).
///
/// **Output.** The cells of the selected components, in their input order (cell ids still run
/// verts, lines, polys, strips), with only the points they use, renumbered in increasing input
/// id (all input points, unrenumbered, with `keep_unused_points`). Point data, cell data and
/// field data are carried, and the Int32 arrays "ComponentId" are added to the cell data and to
/// the point data (replacing arrays of that name; active attribute roles are unchanged).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

/// Which components `connectivity` extracts.
enum class ConnectivityMode {
  All,             ///< every component (the input, labeled)
  Largest,         ///< component 0 (none if the input has no cells)
  LargestN,        ///< components 0 .. count − 1 (all of them if there are fewer)
  ClosestToPoint,  ///< the component of the used point nearest to `point`
  Specified,       ///< the components whose ids are listed in `components`
  PointSeeded,     ///< the components of the cells that use any of the points `seeds`
  CellSeeded,      ///< the components of the cells `seeds`
};

/// When two cells are neighbours.
enum class ConnectedBy {
  Point,  ///< they share a point (VTK's criterion); a bow-tie is one component
  Edge,   ///< they share an edge: two points consecutive in both (polygon sides, polyline
          ///< segments, strip triangle sides); a bow-tie is two components, a vertex cell is
          ///< always alone
};

/// The size that orders components (component 0 is the largest).
enum class ComponentSize {
  Cells,  ///< number of cells of any kind
  Area,   ///< total area of the polygons (vector area) and strips; verts and lines add 0
};

struct ConnectivityOptions {
  ConnectivityMode mode = ConnectivityMode::All;
  std::size_t count = 1;                ///< LargestN: how many (≥ 1)
  Vec3 point{0, 0, 0};                  ///< ClosestToPoint: the query point (finite)
  std::vector<std::size_t> components;  ///< Specified: component ids (< component count)
  std::vector<Index> seeds;             ///< PointSeeded / CellSeeded: point or cell ids
  ConnectedBy connected_by = ConnectedBy::Point;
  ComponentSize size_by = ComponentSize::Cells;
  /// Keep every input point with its input id (default: only the points of the output cells,
  /// renumbered in increasing input id).
  bool keep_unused_points = false;
  bool component_ids = true;  ///< add the "ComponentId" arrays
  ProgressCallback progress;  ///< called with the fraction done; false cancels
};

/// What labelling found.
struct ConnectivityStats {
  std::size_t components = 0;  ///< number of components of the input
  /// Cells of each component, by component id (non-increasing with ComponentSize::Cells).
  std::vector<std::size_t> sizes;
  /// Area of each component, by component id; filled only with ComponentSize::Area.
  std::vector<double> areas;
  std::vector<std::size_t> selected;  ///< ids of the components in the output, increasing
  std::vector<std::int32_t> cell_component;  ///< the component of every input cell
};

/// The selected components (see `connectivity`) and the labelling's statistics.
using ConnectivityResult = Result<PolyData, ConnectivityStats>;

/// Labels the connected components of `input` and extracts those `options.mode` selects.
///
/// "ComponentId" on cells is the cell's component. On points it is the point's component; with
/// `ConnectedBy::Edge` a point where components touch only at that point gets the smallest id
/// among the output cells using it (points kept only by `keep_unused_points` get the smallest
/// id among all cells using them, or −1 if no cell uses them). ClosestToPoint considers only
/// points used by a cell (ties: the smallest point id; non-finite points never match); an
/// input without cells gives an empty output in every mode.
///
/// Near-linear time, linear memory, one thread, deterministic: union-find over the points (by
/// edge: over the cells, after bucketing edge uses by their smaller point; 8 bytes per use).
///
/// \throw Error if `input` is invalid, `count` is 0 in LargestN, `point` is not finite in
/// ClosestToPoint, a Specified component id or a seed id is out of range (naming it), or the
/// number of cells exceeds the Int32 range of "ComponentId"; `Cancelled` if `progress` says so.
[[nodiscard]] ConnectivityResult connectivity(const PolyData& input,
                                              const ConnectivityOptions& options = {});

/// The same, reusing the arrays of `input` (points, cell arrays, attributes) wherever the output
/// keeps them whole instead of copying them, e.g. in mode All on a contour output:
/// `connectivity(contour_image(volume))`. `input` is left empty, also when the call throws.
[[nodiscard]] ConnectivityResult connectivity(PolyData&& input,
                                              const ConnectivityOptions& options = {});

}  // namespace isoforge
