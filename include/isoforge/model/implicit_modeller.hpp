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
///   `far_value` (VTK: VTK_FLOAT_MAX = 1e38), or the maximum distance itself with `clamp`.
/// - **Capping** (on): the samples on the six faces of the volume are set to `cap_value` (1e38,
///   VTK's default), so that every offset surface closes at the boundary of the volume.
/// - **Output**: one point array ("ImageScalars", as VTK) of Float32 (default) or Float64 — the
///   active scalars of the returned image.
///
/// Multiple offset surfaces are one contour call with several values (`offset_surfaces` in
/// csg.hpp). Booleans of offset solids are min/max of fields (csg.hpp), and a concave generator
/// gives several surfaces that `connectivity` separates (Fig. 1.29).

#include <limits>
#include <string>

#include <openvdb/openvdb.h>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/model/distance.hpp"

namespace isoforge {

/// VTK_FLOAT_MAX: vtkImplicitModeller's value beyond the maximum distance and default cap.
inline constexpr double kVtkFloatMax = 1.0e38;

struct ImplicitModellerOptions {
  Dims sample_dimensions{50, 50, 50};  ///< samples per axis (each ≥ 2)
  Bounds model_bounds;                 ///< sampled box; empty (default) = the input's bounds
  bool adjust_bounds = true;           ///< grow the box (VTK's AdjustBounds)
  double adjust_distance = 0.0125;     ///< growth per side, fraction of the largest side
  double maximum_distance = 0.1;       ///< band, fraction of the largest side (0, 1]
  bool capping = true;                 ///< set the volume's boundary samples to `cap_value`
  double cap_value = kVtkFloatMax;     ///< value of the capped samples (world units)
  double far_value = kVtkFloatMax;     ///< value beyond the maximum distance (world units)
  bool clamp = false;                  ///< beyond the maximum distance: the maximum distance
  ScalarType output_type = ScalarType::Float32;  ///< Float32 or Float64
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

/// The vtkImplicitModeller volume of `input` (see the file comment).
/// \throw Error on an empty input, non-finite points, bad options (as implicit_modeller_grid,
/// and cap/far values that are NaN, an output type other than Float32/Float64), and everything
/// `distance_image` rejects.
[[nodiscard]] ImageData implicit_modeller(const PolyData& input,
                                          const ImplicitModellerOptions& options = {},
                                          DistanceStats* stats = nullptr);

/// Sets the samples on the six faces of a 3D image's active scalars (Float32 or Float64) to
/// `value` — the capping step of the modeller, for fields computed otherwise.
/// \throw Error if the image has no floating-point active scalars or `value` is NaN.
void cap_boundary(ImageData& image, double value);

/// The same field in an OpenVDB narrow band (`distance_grid`) on the modeller's grid, which must
/// then have cubic voxels (choose bounds and dimensions accordingly, e.g. a cube with equal
/// dimensions and `adjust_bounds`). No capping: a sparse band has no boundary to cap; voxels
/// beyond the maximum distance are inactive. On the band, values equal `implicit_modeller`'s
/// Float32 values bit for bit. \throw Error as `implicit_modeller`, or on unequal spacing.
[[nodiscard]] openvdb::FloatGrid::Ptr implicit_modeller_vdb(
    const PolyData& input, const ImplicitModellerOptions& options = {},
    DistanceStats* stats = nullptr);

}  // namespace isoforge
