#pragma once
/// \file
/// Tubes and ribbons around lines (VTK's vtkTubeFilter and vtkRibbonFilter): each polyline
/// becomes a triangulated tube of `sides` sides, optionally capped, with outward point normals,
/// radius constant or varying with a point scalar; or a flat ribbon oriented by the lines'
/// normals (streamlines' rotation). See docs/algorithms/glyph.md.

#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

struct TubeOptions {
  double radius = 0.5;        ///< data units, > 0: the radius (the smallest with radius_array)
  int sides = 12;             ///< sides of each tube, >= 3
  std::string radius_array;   ///< point array (1 component, or a vector's length) varying the
                              ///< radius; "" = constant radius
  double max_radius = 0;      ///< radius at the array's maximum (0 = 10 × radius, as VTK)
  std::optional<std::array<double, 2>> scalar_range;  ///< values mapped to radius..max_radius
                                                      ///< (default: the array's range), clamped
  bool capping = true;        ///< close each end with a flat disc
  ProgressCallback progress{};
};

struct TubeStats {
  std::size_t tubes = 0;           ///< polylines turned into tubes
  std::size_t skipped_lines = 0;   ///< polylines with fewer than two distinct points
  double min_radius = 0, max_radius = 0;  ///< radii used
};

/// Tubes around the lines of `lines` (its `lines` cells; other cells are ignored). Each line
/// point with a distinct predecessor gets a ring of `sides` points in the plane normal to the
/// line's mean direction there, turned along the line by parallel transport (rotation
/// minimising, so tubes do not twist); rings are joined by 2 × sides triangles per segment, and
/// caps are discs of sides − 2 triangles on their own copies of the end rings (normals along
/// the line). Point data of the line's points is carried to their rings, cell data of each line
/// to its triangles; "Normals" is the point normal (active). Capped tubes are closed (once
/// coincident points are merged) with outward triangles.
/// \throw Error if radius or max_radius is not positive and finite, sides < 3, the range is not
/// increasing, or radius_array is missing or has 2 or more than 3 components.
[[nodiscard]] Result<PolyData, TubeStats> tube(const PolyData& lines, const TubeOptions& options = {});

struct RibbonOptions {
  double width = 0.1;       ///< data units, > 0: the ribbon's full width
  /// Point vector array orienting the ribbon: its surface normal at each point is this vector
  /// made perpendicular to the line. "" = the lines' active normals if they have any (the
  /// "Normals" of `streamlines`, turned by the flow's rotation), else a frame carried along
  /// each line without twisting.
  std::string normals;
  double angle = 0;         ///< degrees: the ribbon turned about the line by this much
  ProgressCallback progress{};
};

struct RibbonStats {
  std::size_t ribbons = 0;        ///< polylines turned into ribbons
  std::size_t skipped_lines = 0;  ///< polylines with fewer than two distinct points
  bool oriented = false;          ///< a normals array oriented the ribbons
};

/// Ribbons along the lines of `lines` (its `lines` cells): at each distinct point of a line,
/// two points width/2 either side of it, perpendicular to the line and to the (projected,
/// turned) normal; 2(n − 1) triangles per line of n points. Point data is carried to both
/// points, cell data to the line's triangles; "Normals" (active) is the ribbon's normal.
/// 	hrow Error if width is not positive and finite, angle is not finite, or `normals` names
/// no 3-component point array.
[[nodiscard]] Result<PolyData, RibbonStats> ribbon(const PolyData& lines,
                                                   const RibbonOptions& options = {});

}  // namespace isoforge
