// The subcommands' work on OpenVDB grids (vdb_commands.hpp): the module isoforge-vdb-commands.so
// in a shared build.

#include "vdb_commands.hpp"

#include <fmt/core.h>
#include <openvdb/tools/Count.h>

#include "common.hpp"
#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/implicit/sample_sparse.hpp"
#include "isoforge/io/vdb.hpp"
#include "isoforge/model/csg_sparse.hpp"
#include "isoforge/model/distance_sparse.hpp"

namespace isoforge::cli {

namespace {

/// What a grid holds, for a warning: "'distance' ranges 0.01 .. 0.3 over 1234 active voxels
/// (background 0.3)", or "'F' has no active voxels (background 3)".
std::string grid_range_text(const openvdb::FloatGrid& grid) {
  const std::string name = grid.getName().empty() ? "the grid" : "'" + grid.getName() + "'";
  const auto active = grid.activeVoxelCount();
  if (active == 0) {
    return fmt::format("{} has no active voxels (background {:g})", name, grid.background());
  }
  const auto mm = openvdb::tools::minMax(grid.tree());
  return fmt::format("{} ranges {:g} .. {:g} over {} active voxels (background {:g})", name,
                     mm.min(), mm.max(), active, grid.background());
}

void print_info(const std::filesystem::path& path) {
  const auto grids = inspect_vdb(path);
  fmt::print("file: {} (OpenVDB)\n", path.string());
  fmt::print("grids: {}\n", grids.size());
  for (const auto& g : grids) {
    const auto& b = g.active_bbox;
    fmt::print(
        "  '{}'  {}  class {}  voxel size {}  active voxels {}  index bbox [{} {} {}] .. [{} {} "
        "{}]\n",
        g.name, g.type, g.grid_class, g.voxel_size, g.active_voxels, b.min().x(), b.min().y(),
        b.min().z(), b.max().x(), b.max().y(), b.max().z());
  }
}

PolyData contour(const std::string& path, const std::string& grid_name, ContourOptions& o,
                 ProgressBar& bar) {
  const auto grid = read_vdb_grid(path, grid_name);
  bar.stage("contouring");
  o.progress = bar.callback();
  PolyData surface = contour_vdb(*grid, o).output;
  if (surface.num_points() == 0) {
    bar.finish();
    warn(fmt::format("contour: no surface at {}: {}", values_text(o.values, "value"),
                     grid_range_text(*grid)));
  }
  return surface;
}

PolyData offset_file(const std::string& path, const std::string& grid_name,
                     const std::vector<double>& distances, ProgressBar& bar, std::string& range) {
  const auto grid = read_vdb_grid(path, grid_name);
  bar.stage("contouring");
  PolyData surface = offset_surfaces(*grid, distances).output;
  range = grid_range_text(*grid);
  return surface;
}

PolyData offset_band(const PolyData& input, const GridSpec& g, const DistanceOptions& o,
                     const std::vector<double>& distances, ProgressBar& bar, std::string& range) {
  const auto grid = distance_grid(input, g, o).output;
  bar.stage("contouring");
  PolyData surface = offset_surfaces(*grid, distances).output;
  range = grid_range_text(*grid);
  return surface;
}

std::optional<PolyData> csg(const std::string& a_path, const std::string& b_path, double offset_a,
                            double offset_b, CsgOperation op, const std::string& op_name,
                            bool field_out, const std::string& out, bool quiet, ProgressBar& bar) {
  // An empty result is written (it is the answer), with a warning naming the field's range.
  const auto warn_empty = [&](const std::string& range) {
    bar.finish();
    warn(fmt::format("csg: the {} is empty (no value <= 0): {}", op_name, range));
  };
  auto a = read_vdb_grid(a_path);
  auto b = read_vdb_grid(b_path);
  if (offset_a != 0 || a->getGridClass() != openvdb::GRID_LEVEL_SET) offset_in_place(*a, offset_a);
  if (offset_b != 0 || b->getGridClass() != openvdb::GRID_LEVEL_SET) offset_in_place(*b, offset_b);
  bar.stage("csg");
  csg_in_place(*a, *b, op);
  const std::string range = grid_range_text(*a);
  if (field_out) {
    if (a->activeVoxelCount() == 0 || openvdb::tools::minMax(a->tree()).min() > 0) {
      warn_empty(range);
    }
    bar.stage("writing");
    write_vdb(*a, out);
    bar.finish();
    if (!quiet) fmt::print(stderr, "wrote {}: {} active voxels\n", out, a->activeVoxelCount());
    return std::nullopt;
  }
  bar.stage("contouring");
  PolyData surface = offset_surfaces(*a, {0.0}).output;
  if (surface.num_points() == 0) warn_empty(range);
  return surface;
}

DistanceStats distance(const PolyData& input, const GridSpec& g, const DistanceOptions& o,
                       const std::string& out, ProgressBar& bar,
                       const std::function<void(const DistanceStats&)>& computed) {
  auto [grid, stats] = distance_grid(input, g, o);
  computed(stats);
  bar.stage("writing");
  write_vdb(*grid, out);
  return stats;
}

VdbGridStats sample(const ImplicitFunction& f, const GridSpec& g, double half_width,
                    const std::string& out, ProgressBar& bar,
                    const std::function<void(const VdbGridStats&)>& computed) {
  SparseSampleOptions o;
  o.half_width = half_width;
  o.progress = bar.callback();
  auto [grid, stats] = sample_level_set(f, g, o);
  grid->setName("F");
  const VdbGridStats result{stats.active_voxels, stats.memory_bytes};
  computed(result);
  bar.stage("writing");
  write_vdb(*grid, out);
  return result;
}

constexpr VdbCommands kCommands{print_info, contour,  offset_file, offset_band,
                                csg,        distance, sample};

}  // namespace

}  // namespace isoforge::cli

extern "C" const isoforge::cli::VdbCommands* isoforge_cli_vdb_commands() {
  return &isoforge::cli::kCommands;
}
