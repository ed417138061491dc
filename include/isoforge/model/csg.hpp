#pragma once
/// \file
/// Booleans and offsets of dense distance fields (section 1.5.3, Figs. 1.26–1.28): union,
/// intersection and difference (Equations 1.15–1.17: min, max, max(a, −b)) per sample of two
/// images on one grid, offsets (values − d: d > 0 dilates, d < 0 erodes) and several offset
/// surfaces in one contour pass. The sparse forms on OpenVDB level sets are in csg_sparse.hpp.

#include <string_view>
#include <vector>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/dataset.hpp"

namespace isoforge {

enum class CsgOperation {
  Union,         ///< min(a, b)
  Intersection,  ///< max(a, b)
  Difference,    ///< max(a, −b): A minus B
};

/// "union", "intersection", "difference".
[[nodiscard]] std::string_view csg_operation_name(CsgOperation op);
/// Inverse of `csg_operation_name`. \throw Error naming the string otherwise.
[[nodiscard]] CsgOperation csg_operation_from_name(std::string_view name);

/// `op` per sample on two images with identical dims, origin and spacing, using their active
/// scalars (1 component). The result has a's geometry and one array named after a's scalars:
/// Float32 if both are Float32, else Float64. \throw Error on mismatched grids or
/// missing/multi-component scalars.
[[nodiscard]] ImageData csg(const ImageData& a, const ImageData& b, CsgOperation op);

/// The active scalars − distance (same type, same name). \throw Error on missing or integer
/// scalars, or a distance that is not finite or whose subtraction overflows the scalars' type.
[[nodiscard]] ImageData offset(const ImageData& field, double distance);

/// The offset surfaces of a dense distance field at each of `distances` (one contour pass:
/// `options.values` is replaced by them). Oriented outward for distance fields (toward
/// increasing distance). The point array "IsovalueIndex" tells which distance each point
/// belongs to. \throw Error on an empty list or non-finite distances, and as `contour_image`.
[[nodiscard]] ContourResult offset_surfaces(const ImageData& field,
                                            const std::vector<double>& distances,
                                            ContourOptions options = {});

}  // namespace isoforge
