#pragma once
// The parts of the subcommands that handle OpenVDB grids (.vdb files, sparse output). In a shared
// build they are a module of their own (isoforge-vdb-commands.so), which the command loads only
// when one of them runs: the commands that never touch a sparse grid do not load OpenVDB, whose
// loading costs about 70 ms per run (src/CMakeLists.txt). In a static build they are linked in.
// The module uses the program's own helpers (common.hpp, progress_bar.hpp): the program exports
// its symbols to it.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/implicit/function.hpp"
#include "isoforge/model/csg.hpp"
#include "isoforge/model/distance.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

/// Size of a written sparse grid, for the command's report.
struct VdbGridStats {
  std::size_t active_voxels = 0;
  std::size_t memory_bytes = 0;  ///< the tree's
};

struct VdbCommands {
  /// `info FILE.vdb`: prints the file's grids on stdout.
  void (*print_info)(const std::filesystem::path& path);
  /// `contour IN.vdb`: grid `grid` of `path` (the first float grid if empty) contoured with `o`
  /// (stage "contouring" of `bar`); warns when there is no surface.
  PolyData (*contour)(const std::string& path, const std::string& grid, ContourOptions& o,
                      ProgressBar& bar);
  /// `offset IN.vdb`: the surfaces at `distances` of distance field `grid` of `path`;
  /// `range` gets what the field holds (for the warning on an empty result).
  PolyData (*offset_file)(const std::string& path, const std::string& grid,
                          const std::vector<double>& distances, ProgressBar& bar,
                          std::string& range);
  /// `offset IN --voxel-size`: the surfaces at `distances` of the narrow-band distance field of
  /// `input` on `g` (options `o`); `range` as above.
  PolyData (*offset_band)(const PolyData& input, const GridSpec& g, const DistanceOptions& o,
                          const std::vector<double>& distances, ProgressBar& bar,
                          std::string& range);
  /// `csg OP A.vdb B.vdb`: level sets A and B (offset by `offset_a`, `offset_b`; other fields are
  /// made level sets) combined by `op`. With `field_out` the result is written to `out` and
  /// reported (unless `quiet`), and nothing is returned; else its zero surface is returned.
  /// Warns when the result is empty.
  std::optional<PolyData> (*csg)(const std::string& a, const std::string& b, double offset_a,
                                 double offset_b, CsgOperation op, const std::string& op_name,
                                 bool field_out, const std::string& out, bool quiet,
                                 ProgressBar& bar);
  /// `distance IN -o OUT.vdb`: the narrow-band distance field of `input` on `g` written to
  /// `out`; `computed` runs between computing and writing (for a warning).
  DistanceStats (*distance)(const PolyData& input, const GridSpec& g, const DistanceOptions& o,
                            const std::string& out, ProgressBar& bar,
                            const std::function<void(const DistanceStats&)>& computed);
  /// `sample -o OUT.vdb`: the narrow-band level set of `f` on `g` (half width in voxels) written
  /// to `out` as grid "F"; `computed` runs between sampling and writing.
  VdbGridStats (*sample)(const ImplicitFunction& f, const GridSpec& g, double half_width,
                         const std::string& out, ProgressBar& bar,
                         const std::function<void(const VdbGridStats&)>& computed);
};

/// The module's commands, loaded on the first call. \throw Error if it cannot be loaded.
[[nodiscard]] const VdbCommands& vdb_commands();

}  // namespace isoforge::cli

/// Defined by the module (vdb_commands.cpp); looked up by name when it is loaded.
extern "C" const isoforge::cli::VdbCommands* isoforge_cli_vdb_commands();
