#pragma once
/// \file
/// The implicit modeller (section 1.5.3; VTK's vtkImplicitModeller): the distance from polygonal
/// data — points, lines, polygons — sampled on a volume, so that contouring it at a distance d
/// gives the offset surface at d ("thickening" a stroked font, Fig. 1.28). Defaults and
/// conventions are VTK's, so a pipeline ported from VTK gives the same volume:
///
/// - **Sample dimensions** 50³ (spacing may differ per axis: HELLO uses 110 × 40 × 20).
/// - **Model bounds**: the input's bounds unless given; with `adjust_bounds` (default) they are
///   grown on every side by `adjust_distance` (0.0125) × the largest side of those bounds —
///   also when given explicitly, as VTK does. Samples run from corner to corner
///   (`GridSpec::from_bounds`).
/// - **Maximum distance**: `maximum_distance` (0.1) × the largest side of the bounds *before*
///   adjustment. Distances are exact below it (distance.hpp); samples farther away get
///   `far_value` (VTK: VTK_FLOAT_MAX = 1e38 for Float32), or the maximum distance itself with
///   `clamp`.
/// - **Capping** (on): the samples on the six faces of the volume are set to `cap_value` (by
///   default VTK's: the output type's maximum), so that every offset surface closes at the
///   boundary of the volume.
/// - **Output**: one point array ("ImageScalars", as VTK), the active scalars of the returned
///   image, of any scalar type (VTK's OutputScalarType): Float32 (default) or Float64 hold the
///   distances; an integer type holds trunc(distance × scale) — scale 1, or with
///   `scale_to_maximum_distance` the type's maximum / the maximum distance, so that the band
///   spans the type's positive range (VTK's ScaleToMaximumDistance) — clamped to the type's
///   range. The cap and far values default to the type's VTK maximum: 1e38 (VTK_FLOAT_MAX) for
///   Float32, 1e299 (VTK_DOUBLE_MAX) for Float64, the largest value of an integer type.
///
/// Multiple offset surfaces are one contour call with several values (`offset_surfaces` in
/// csg.hpp). Booleans of offset solids are min/max of fields (csg.hpp), and a concave generator
/// gives several surfaces that `connectivity` separates (Fig. 1.29).

#include <limits>
#include <optional>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/model/distance.hpp"

namespace isoforge {

/// VTK_FLOAT_MAX: vtkImplicitModeller's value beyond the maximum distance and default cap
/// (Float32 output).
inline constexpr double kVtkFloatMax = 1.0e38;
/// VTK_DOUBLE_MAX: the same for Float64 output.
inline constexpr double kVtkDoubleMax = 1.0e299;

/// vtkImplicitModeller's default cap and far value for an output type: kVtkFloatMax,
/// kVtkDoubleMax, or the largest value of an integer type.
[[nodiscard]] double vtk_type_max(ScalarType type);

struct ImplicitModellerOptions {
  Dims sample_dimensions{50, 50, 50};  ///< samples per axis (each ≥ 2)
  Bounds model_bounds;                 ///< sampled box; empty (default) = the input's bounds
  bool adjust_bounds = true;           ///< grow the box (VTK's AdjustBounds)
  double adjust_distance = 0.0125;     ///< growth per side, fraction of the largest side
  double maximum_distance = 0.1;       ///< band, fraction of the largest side (0, 1]
  bool capping = true;                 ///< set the volume's boundary samples to `cap_value`
  /// Value of the capped samples, in the output's units (unset: `vtk_type_max(output_type)`).
  std::optional<double> cap_value;
  /// Value beyond the maximum distance, in the output's units (unset: the type's VTK maximum).
  std::optional<double> far_value;
  bool clamp = false;  ///< beyond the maximum distance: the maximum distance (scaled if integer)
  ScalarType output_type = ScalarType::Float32;  ///< any type (see the file comment)
  /// Integer output: distances × (type max / maximum distance) instead of × 1.
  bool scale_to_maximum_distance = false;
  std::string name = "ImageScalars";             ///< output point array (VTK's name)
  bool signed_distance = false;  ///< negative inside a closed triangle mesh (see distance.hpp)
  std::string radius_array;      ///< vertex radii (point-data array; distance.hpp)
  DistanceStrategy strategy = DistanceStrategy::Auto;
  ProgressCallback progress;
};

/// The sampling grid and absolute maximum distance the options give for input bounds `bounds`.
struct ModellerGrid {
  GridSpec grid;
  double max_distance = 0;  ///< world units
};

/// Computes the grid and maximum distance as VTK does (see the file comment).
/// \throw Error on empty or non-finite bounds, a sample dimension < 2, adjust_distance < 0 or
/// maximum_distance outside (0, 1], or bounds of zero extent along every axis.
[[nodiscard]] ModellerGrid implicit_modeller_grid(const Bounds& input_bounds,
                                                  const ImplicitModellerOptions& options = {});

using ImplicitModellerResult = Result<ImageData, DistanceStats>;

/// The vtkImplicitModeller volume of `input` (see the file comment).
/// \throw Error on an empty input, non-finite points, bad options (as implicit_modeller_grid,
/// cap/far values that are NaN or do not fit the output type, signed distances into an unsigned
/// type, scale_to_maximum_distance with a floating type), and everything `distance_image`
/// rejects.
[[nodiscard]] ImplicitModellerResult implicit_modeller(const PolyData& input,
                                                       const ImplicitModellerOptions& options = {});

/// Sets the samples on the six faces of a 3D image's active scalars (1 component, any type) to
/// `value` — the capping step of the modeller, for fields computed otherwise.
/// \throw Error if the image has no 1-component active scalars, or `value` is NaN or does not
/// fit their type.
void cap_boundary(ImageData& image, double value);

}  // namespace isoforge
