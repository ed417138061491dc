#pragma once
/// \file
/// The implicit modeller (implicit_modeller.hpp) into an OpenVDB narrow band.

#include <openvdb/openvdb.h>

#include "isoforge/model/distance_sparse.hpp"
#include "isoforge/model/implicit_modeller.hpp"

namespace isoforge {

/// The same field in an OpenVDB narrow band (`distance_grid`) on the modeller's grid, which must
/// then have cubic voxels (choose bounds and dimensions accordingly, e.g. a cube with equal
/// dimensions and `adjust_bounds`). No capping: a sparse band has no boundary to cap; voxels
/// beyond the maximum distance are inactive. On the band, values equal `implicit_modeller`'s
/// Float32 values bit for bit. \throw Error as `implicit_modeller`, or on unequal spacing.
[[nodiscard]] DistanceGridResult implicit_modeller_vdb(const PolyData& input,
                                                       const ImplicitModellerOptions& options = {});

}  // namespace isoforge
