#pragma once
/// \file
/// Booleans and offsets of OpenVDB level sets (negative inside, inactive values ±background):
/// OpenVDB's `csgUnion` / `csgIntersection` / `csgDifference`, in place (the result replaces A
/// and B is emptied) and copying. An unsigned distance field (`distance_grid`) becomes the level
/// set of the solid within distance r of its generator with `offset(field, r)`; that is how
/// points and lines are combined in Fig. 1.27. Both inputs of a boolean are first brought to the
/// narrower of their two bands (the result is exact only where both are known). An offset by
/// d on a band of half width B is exact on the band of half width B − |d|, which becomes the new
/// band and background.

#include <vector>

#include <openvdb/openvdb.h>

#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/model/csg.hpp"

namespace isoforge {

/// A new level set `a op b`; a and b are unchanged. Named after a.
/// \throw Error if either grid is not a level set (class GRID_LEVEL_SET, background > 0) or
/// the two transforms differ (voxel size or origin).
[[nodiscard]] openvdb::FloatGrid::Ptr csg(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b,
                                          CsgOperation op);

/// `a = a op b` in place; b is left empty (OpenVDB's in-place CSG). \throw Error as `csg`.
void csg_in_place(openvdb::FloatGrid& a, openvdb::FloatGrid& b, CsgOperation op);

/// The level set of the offset solid: values − distance, on the band of half width
/// background − |distance|, class GRID_LEVEL_SET. Works on unsigned distance fields (giving the
/// solid within `distance` of the generator) and on level sets. \throw Error if the background
/// is not positive, |distance| ≥ background, or distance is not finite.
[[nodiscard]] openvdb::FloatGrid::Ptr offset(const openvdb::FloatGrid& field, double distance);
/// In place. \throw Error as `offset`.
void offset_in_place(openvdb::FloatGrid& field, double distance);

/// The offset surfaces of a sparse field (`contour_vdb`); every distance must lie strictly
/// inside the band (|d| < background). \throw Error otherwise, and as `contour_vdb`.
[[nodiscard]] VdbContourResult offset_surfaces(const openvdb::FloatGrid& field,
                                               const std::vector<double>& distances,
                                               ContourOptions options = {});

}  // namespace isoforge
