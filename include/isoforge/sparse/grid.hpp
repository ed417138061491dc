#pragma once
/// \file
/// The OpenVDB layer below the algorithms: initialisation and the transforms of isoforge's
/// sparse grids (voxel (i, j, k) at origin + (i, j, k) * voxel size). Every module that makes or
/// reads OpenVDB grids goes through these, so the uniform-scale rules are written once.

#include <cstdint>
#include <string_view>

#include <openvdb/openvdb.h>

#include "isoforge/core/vec.hpp"

namespace isoforge {

/// Calls openvdb::initialize() once (thread-safe). Every isoforge function taking or making
/// grids calls it; call it yourself before using OpenVDB directly.
void ensure_openvdb_initialized();

/// The uniform-scale transform of isoforge's grids: voxel (i, j, k) at origin + (i, j, k) *
/// voxel_size. \throw Error naming `what` if OpenVDB cannot represent it: a voxel size not
/// positive and finite, or so small that OpenVDB's transforms reject the scale (below about
/// 1e-5: its determinant must exceed 1e-15), or a non-finite origin.
[[nodiscard]] openvdb::math::Transform::Ptr vdb_transform(double voxel_size, const Vec3& origin,
                                                          std::string_view what);

/// A grid's transform as a uniform scale + translation, with the values stored in its matrix.
struct UniformTransform {
  Vec3 origin;            ///< world position of voxel (0, 0, 0)
  double voxel_size = 0;  ///< > 0

  /// World coordinate of index i along `axis`: origin + i * voxel_size, computed as every
  /// sampler computes its grid coordinates (so dense and sparse results agree bit for bit).
  [[nodiscard]] double coordinate(int axis, std::int64_t i) const {
    return origin[axis] + static_cast<double>(i) * voxel_size;
  }
};

/// The uniform transform of `grid`. \throw Error naming `what` if the transform is not linear,
/// not a positive uniform scale + translation (to 1e-9 relative), or not finite.
[[nodiscard]] UniformTransform uniform_transform(const openvdb::GridBase& grid,
                                                 std::string_view what);

/// \throw Error naming `what` unless grids a and b have the same transform (voxel size and
/// origin), as voxel-wise operations on two grids need.
void check_same_transform(const openvdb::GridBase& a, const openvdb::GridBase& b,
                          std::string_view what);

}  // namespace isoforge
