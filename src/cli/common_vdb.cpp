#include "common_vdb.hpp"

#include <fmt/core.h>
#include <openvdb/tools/Count.h>

namespace isoforge::cli {

std::string range_text(const openvdb::FloatGrid& grid) {
  const std::string name = grid.getName().empty() ? "the grid" : "'" + grid.getName() + "'";
  const auto active = grid.activeVoxelCount();
  if (active == 0) {
    return fmt::format("{} has no active voxels (background {:g})", name, grid.background());
  }
  const auto mm = openvdb::tools::minMax(grid.tree());
  return fmt::format("{} ranges {:g} .. {:g} over {} active voxels (background {:g})", name,
                     mm.min(), mm.max(), active, grid.background());
}

}  // namespace isoforge::cli
