#pragma once
/// \file
/// Glyphs (VTK's vtkGlyph3D and vtkHedgeHog): a copy of a source shape at each (masked) input
/// point, turned to the point's vector or normal and scaled by a scalar or the vector's length.
/// See docs/algorithms/glyph.md.

#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/filters/mask_points.hpp"

namespace isoforge {

/// The built-in glyph shapes. All are about one unit long, centred on the origin (the arrow and
/// the line start there) and point along +x; each has outward point normals "Normals" except
/// the line.
enum class GlyphShape : std::uint8_t {
  Cone,    ///< apex (0.5, 0, 0), base of radius 0.5 at x = -0.5, capped
  Arrow,   ///< shaft radius 0.03 from 0 to 0.65, tip radius 0.1 from 0.65 to 1, capped
  Sphere,  ///< radius 0.5 (UV sphere: `resolution` slices, resolution/2 stacks)
  Cube,    ///< edge 1, axis-aligned, 24 points (4 per face), 12 triangles
  Line,    ///< (0, 0, 0) to (1, 0, 0): the hedgehog, one line per point
};

/// A built-in glyph shape as a polydata (triangles, or one line). `resolution` is the number of
/// sides of the cone and arrow and of slices of the sphere. \throw Error if resolution < 3.
[[nodiscard]] PolyData glyph_source(GlyphShape shape, int resolution = 6);

enum class GlyphOrient : std::uint8_t {
  Auto,     ///< the active vectors if any, else the active normals, else none
  Vectors,  ///< `vectors` (or the active vectors)
  Normals,  ///< `normals` (or the active normals)
  None,     ///< every glyph keeps the source's axis
};

enum class GlyphScale : std::uint8_t {
  None,    ///< size `factor` everywhere
  Scalar,  ///< `factor` × |scalar| (`scalars` or the active scalars)
  Vector,  ///< `factor` × |orientation vector| (the vectors used by orient, or `vectors`)
};

enum class GlyphColor : std::uint8_t {
  None,       ///< no colour array
  Scalar,     ///< the scale scalar (`scalars` or the active scalars) of each glyph's point
  Magnitude,  ///< the length of the vector (`vectors` or the active vectors)
  Index,      ///< the glyph's number 0, 1, 2, ... in the output
};

struct GlyphOptions {
  GlyphOrient orient = GlyphOrient::Auto;
  GlyphScale scale = GlyphScale::None;
  GlyphColor color = GlyphColor::None;
  double factor = 1;                  ///< size multiplier (data units per source unit), finite
  bool clamp = false;                 ///< map the scale value through `range` to [0, 1] first
  std::optional<std::array<double, 2>> range;  ///< clamp range (default: the data's range)
  std::string vectors;                ///< point array of vectors ("" = active vectors)
  std::string normals;                ///< point array of normals ("" = active normals)
  std::string scalars;                ///< point array of scale/colour scalars ("" = active)
  MaskOptions mask;                   ///< which input points get a glyph
  bool point_ids = true;              ///< add the point array "InputPointIds" (Int64)
  bool carry_point_data = true;       ///< copy the input's point arrays to each glyph's points
  ProgressCallback progress{};
};

struct GlyphStats {
  std::size_t glyphs = 0;         ///< number of glyphs placed
  std::size_t source_points = 0;  ///< points per glyph
  std::size_t source_cells = 0;   ///< cells per glyph
  std::string orient_array;       ///< the array that turned the glyphs ("" = none)
  std::string scale_array;        ///< the array that sized them ("" = none)
  double min_scale = 0, max_scale = 0;  ///< the range of the glyph sizes used
};

/// A copy of `source` at each masked input point p: each source point s becomes
/// p + size · R s, where R is the rotation that takes +x to the orientation direction (the
/// half-turn about the bisector of +x and the direction; none without orientation or for a zero
/// or non-finite vector)
/// and size = factor × (scale value, or its clamped position in `range`), taken in absolute
/// value (a non-finite value gives size 0). The source's point normals are turned by R. Output:
/// one polydata, glyph g's points at [g·m, (g+1)·m) for an m-point source and its cells in the
/// source's order, with point arrays "Normals" (if the source has them), "InputPointIds" (the
/// input point of each output point), "GlyphColor" (Float32, by `color`) and the input's point
/// arrays. The same input gives the same output bytes for any thread count.
/// \throw Error naming the option if an array is missing or of the wrong shape, factor is not
/// finite, the range is not increasing, or the masks contradict each other.
[[nodiscard]] Result<PolyData, GlyphStats> glyph(DatasetRef input, const PolyData& source,
                                                 const GlyphOptions& options = {});

/// glyph() with a built-in shape; GlyphShape::Line takes the hedgehog path (two points and one
/// line per glyph, no normals).
[[nodiscard]] Result<PolyData, GlyphStats> glyph(DatasetRef input, GlyphShape shape,
                                                 const GlyphOptions& options = {},
                                                 int resolution = 6);

}  // namespace isoforge
