// The OpenVDB layer: initialisation and uniform transforms (sparse/grid.hpp).

#include "isoforge/sparse/grid.hpp"

#include <fmt/format.h>
#include <openvdb/math/Transform.h>

#include <cmath>
#include <mutex>
#include <string>

#include "isoforge/core/error.hpp"

namespace isoforge {

void ensure_openvdb_initialized() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

openvdb::math::Transform::Ptr vdb_transform(double voxel_size, const Vec3& origin,
                                            std::string_view what) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size)) {
    throw Error(fmt::format("{}: voxel size {:g} must be positive and finite", what, voxel_size));
  }
  if (!is_finite(origin)) throw Error(fmt::format("{}: the grid origin is not finite", what));
  ensure_openvdb_initialized();
  try {
    auto xf = openvdb::math::Transform::createLinearTransform(voxel_size);
    xf->postTranslate(openvdb::Vec3d(origin.x, origin.y, origin.z));
    return xf;
  } catch (const openvdb::Exception& e) {
    throw Error(
        fmt::format("{}: OpenVDB cannot use the voxel size {:g} ({}; its transforms need "
                    "voxels of about 1e-5 or more): scale the input",
                    what, voxel_size, e.what()));
  }
}

UniformTransform uniform_transform(const openvdb::GridBase& grid, std::string_view what) {
  const openvdb::math::Transform& xf = grid.transform();
  if (!xf.isLinear()) {
    throw Error(fmt::format("{}: non-linear (frustum) transforms are not supported", what));
  }
  // Row vectors: world = (index, 1) * M; rows 0-2 are the images of the index axes, row 3 the
  // translation (exact copies of a scale-translate map's values).
  const openvdb::Mat4d m = xf.baseMap()->getAffineMap()->getMat4();
  const double s = m(0, 0);
  const double tol = 1e-9 * std::abs(s);
  bool uniform = std::isfinite(s) && s > 0;
  for (int r = 0; r < 3 && uniform; ++r) {
    for (int c = 0; c < 3; ++c) {
      const double expect = r == c ? s : 0.0;
      if (!(std::abs(m(r, c) - expect) <= tol)) uniform = false;
    }
    if (!std::isfinite(m(3, r))) uniform = false;
  }
  if (!uniform) {
    throw Error(fmt::format(
        "{}: transform is not a uniform scale + translation (index axes map "
        "to ({:g}, {:g}, {:g}), ({:g}, {:g}, {:g}), ({:g}, {:g}, {:g}))",
        what, m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)));
  }
  return {{m(3, 0), m(3, 1), m(3, 2)}, s};
}

void check_same_transform(const openvdb::GridBase& a, const openvdb::GridBase& b,
                          std::string_view what) {
  if (a.transform() != b.transform()) {
    throw Error(
        fmt::format("{}: the grids have different transforms (voxel size {:g} vs {:g}); "
                    "sample both on the same grid",
                    what, a.voxelSize()[0], b.voxelSize()[0]));
  }
}

}  // namespace isoforge
