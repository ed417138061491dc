#pragma once
/// \file
/// Point normals of polygonal surfaces, shared by contouring, cutting and decimation.

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Area-weighted point normals of `surface`'s polygons (fan-triangulated; right-hand rule): per
/// point the normalized sum of the incident triangles' normals times their areas; (0, 0, 0) at
/// points on no polygon or where the sum vanishes. A Float32 3-component array "Normals".
[[nodiscard]] DataArray point_normals(const PolyData& surface);

}  // namespace isoforge
