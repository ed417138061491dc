// OpenVDB's meshToVolume as a peer and fast path of the distance fields
// (model/distance_sparse.hpp).

#include <fmt/format.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cmath>
#include <vector>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/model/distance_sparse.hpp"
#include "isoforge/sparse/grid.hpp"

namespace isoforge {

openvdb::FloatGrid::Ptr openvdb_mesh_to_volume(const PolyData& input, const GridSpec& grid,
                                               double half_width_voxels, bool signed_distance) {
  ensure_openvdb_initialized();
  input.validate();
  const double h = grid.spacing.x;
  if (!(h > 0) || grid.spacing.y != h || grid.spacing.z != h) {
    throw Error("mesh to volume: voxels must be cubes (equal positive spacing)");
  }
  if (!(half_width_voxels >= 1) || !std::isfinite(half_width_voxels)) {
    throw Error(
        fmt::format("mesh to volume: half width must be >= 1 voxel, got {:g}", half_width_voxels));
  }
  const auto tris = triangulate_faces(input);
  if (tris.empty()) throw Error("mesh to volume: the input has no triangles");
  if (input.points.first_non_finite() < input.points.size()) {
    throw Error("mesh to volume: point " + std::to_string(input.points.first_non_finite()) +
                " is not finite");
  }
  auto xform = vdb_transform(h, grid.origin, "mesh to volume");
  std::vector<openvdb::Vec3s> pts(input.points.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec3 p = input.points[i];
    pts[i] = xform->worldToIndex(openvdb::Vec3d(p.x, p.y, p.z));
  }
  std::vector<openvdb::Vec3I> idx(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    idx[t] = openvdb::Vec3I(static_cast<openvdb::Index32>(tris[t][0]),
                            static_cast<openvdb::Index32>(tris[t][1]),
                            static_cast<openvdb::Index32>(tris[t][2]));
  }
  openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> mesh(pts, idx);
  const float hw = static_cast<float>(half_width_voxels);
  auto result = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      mesh, *xform, hw, hw, signed_distance ? 0 : openvdb::tools::UNSIGNED_DISTANCE_FIELD);
  result->setGridClass(signed_distance ? openvdb::GRID_LEVEL_SET : openvdb::GRID_UNKNOWN);
  return result;
}

}  // namespace isoforge
