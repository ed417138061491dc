// Exact Euclidean distance fields into OpenVDB narrow bands (model/distance_sparse.hpp): the
// block engine (distance_engine.hpp) on blocks aligned with OpenVDB's 8³ leaves, which become
// the tree's leaves directly; signs beyond the band by OpenVDB's signedFloodFill (K. Museth,
// "VDB: High-resolution sparse volumes with dynamic topology", ACM TOG 32(3), 2013).

#include "isoforge/model/distance_sparse.hpp"

#include <fmt/format.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <memory>
#include <vector>

#include "distance_engine.hpp"
#include "isoforge/sparse/grid.hpp"

namespace isoforge {

using namespace model_detail;

DistanceGridResult distance_grid(const PolyData& input, const GridSpec& grid,
                                 const DistanceOptions& options) {
  ensure_openvdb_initialized();
  check_common(grid, options);
  const double h = grid.spacing.x;
  if (grid.spacing.y != h || grid.spacing.z != h) {
    throw Error(
        fmt::format("distance: OpenVDB voxels must be cubes (equal spacing on all axes), "
                    "got {:g}, {:g}, {:g}",
                    grid.spacing.x, grid.spacing.y, grid.spacing.z));
  }
  const openvdb::math::Transform::Ptr xform = vdb_transform(h, grid.origin, "distance");
  const PrimitiveSet P = distance_primitives(input, options);
  std::unique_ptr<Pseudonormals> signs;
  if (options.signed_distance) {
    signs = std::make_unique<Pseudonormals>(build_pseudonormals(input, P, options.require_closed));
    if (options.max_distance < h) {
      throw Error(
          fmt::format("distance: signed distance needs max_distance ({:g}) >= the voxel "
                      "size ({:g}) so that the band separates inside from outside",
                      options.max_distance, h));
    }
  }
  using Leaf = openvdb::FloatTree::LeafNodeType;
  const float background = static_cast<float>(options.max_distance);
  DistanceGridResult r;
  std::vector<std::unique_ptr<Leaf>> leaves;  // by task, owned until added to the tree
  run_blocks(
      P, signs.get(), grid, options, 8, r.stats, [&](std::size_t n) { leaves.resize(n); },
      [&](std::size_t t, const BlockOut& b) {
        if (b.n_active == 0) return;
        auto leaf = std::make_unique<Leaf>(
            openvdb::Coord(static_cast<int>(b.i0), static_cast<int>(b.j0), static_cast<int>(b.k0)),
            background, false);
        for (int off = 0; off < 512; ++off) {  // kz = 8: leaf offsets
          const int i = off >> 6, j = (off >> 3) & 7, k = off & 7;
          if (i < b.ni && j < b.nj && k < b.nk && b.active[off]) {
            leaf->setValueOn(static_cast<openvdb::Index>(off), static_cast<float>(b.value[off]));
          }
        }
        leaves[t] = std::move(leaf);
      });
  auto result = openvdb::FloatGrid::create(background);
  result->setName(options.name);
  result->setTransform(xform);
  result->setGridClass(options.signed_distance ? openvdb::GRID_LEVEL_SET : openvdb::GRID_UNKNOWN);
  auto& tree = result->tree();
  for (auto& leaf : leaves) {
    if (leaf) tree.addLeaf(leaf.release());
  }
  if (options.signed_distance) openvdb::tools::signedFloodFill(tree);
  report_progress(options.progress, 1.0, "distance");
  r.stats.memory_bytes = static_cast<std::size_t>(tree.memUsage());
  r.output = std::move(result);
  return r;
}

}  // namespace isoforge
