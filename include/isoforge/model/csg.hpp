#pragma once
/// \file
/// Booleans and offsets of distance fields (section 1.5.3, Figs. 1.26–1.28): union,
/// intersection and difference (Equations 1.15–1.17: min, max, max(a, −b)), offsets (dilate or
/// erode by a distance) and several offset surfaces at once.
///
/// **Sparse** fields are OpenVDB level sets (negative inside, inactive values ±background); the
/// booleans are OpenVDB's `csgUnion` / `csgIntersection` / `csgDifference` (in place: the result
/// replaces A and B is emptied) and `csgUnionCopy` / ... (copying). An unsigned distance field
/// (`distance_grid`) becomes the level set of the solid within distance r of its generator with
/// `offset(field, r)`; that is how points and lines are combined in Fig. 1.27.
///
/// **Dense** fields are images on the same grid; the booleans are the same formulas per sample.
///
/// Both inputs of a sparse boolean are first brought to the narrower of their two bands (the
/// result is exact only where both are known), so the result's background is the smaller one.
///
/// An offset by d > 0 dilates (the surface moves outward by d: values − d), d < 0 erodes. On a
/// narrow band of half width B the result is exact on the band of half width B − |d| (the values
/// beyond it are not known): it becomes the new band and background.

#include <string_view>
#include <vector>

#include <openvdb/openvdb.h>

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

/// A new level set `a op b`; a and b are unchanged. Named after a.
/// \throw Error if either grid is not a level set (class GRID_LEVEL_SET, background > 0) or
/// the two transforms differ (voxel size or origin).
[[nodiscard]] openvdb::FloatGrid::Ptr csg(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b,
                                          CsgOperation op);

/// `a = a op b` in place; b is left empty (OpenVDB's in-place CSG). \throw Error as `csg`.
void csg_in_place(openvdb::FloatGrid& a, openvdb::FloatGrid& b, CsgOperation op);

/// The same per sample on two images with identical dims, origin and spacing, using their
/// active scalars (1 component). The result has a's geometry and one array named after a's
/// scalars: Float32 if both are Float32, else Float64. \throw Error on mismatched grids or
/// missing/multi-component scalars.
[[nodiscard]] ImageData csg(const ImageData& a, const ImageData& b, CsgOperation op);

/// The level set of the offset solid: values − distance, on the band of half width
/// background − |distance|, class GRID_LEVEL_SET (see the file comment). Works on unsigned
/// distance fields (giving the solid within `distance` of the generator) and on level sets.
/// \throw Error if the background is not positive or |distance| ≥ background, or distance is not
/// finite.
[[nodiscard]] openvdb::FloatGrid::Ptr offset(const openvdb::FloatGrid& field, double distance);
/// In place. \throw Error as `offset`.
void offset_in_place(openvdb::FloatGrid& field, double distance);
/// Dense: the active scalars − distance (same type, same name). \throw Error on missing scalars
/// or a non-finite distance.
[[nodiscard]] ImageData offset(const ImageData& field, double distance);

/// The offset surfaces of a dense distance field at each of `distances` (one contour pass:
/// `options.values` is replaced by them). Oriented outward for distance fields (toward
/// increasing distance). The point array "IsovalueIndex" tells which distance each point
/// belongs to. \throw Error on an empty list or non-finite distances, and as `contour_image`.
[[nodiscard]] PolyData offset_surfaces(const ImageData& field, const std::vector<double>& distances,
                                       ContourOptions options = {});
/// The same on a sparse field (`contour_vdb`); every distance must lie strictly inside the band
/// (|d| < background). \throw Error otherwise, and as `contour_vdb`.
[[nodiscard]] PolyData offset_surfaces(const openvdb::FloatGrid& field,
                                       const std::vector<double>& distances,
                                       ContourOptions options = {});

}  // namespace isoforge
