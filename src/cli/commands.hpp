#pragma once
// Subcommands of the isoforge command. Each add_* function registers one subcommand on the app;
// its callback does the work and throws isoforge::Error on failure (main prints it as one line
// and exits non-zero).

#include <CLI/CLI.hpp>

namespace isoforge::cli {

/// Options shared by all subcommands.
struct Context {
  bool quiet = false;  ///< --quiet: no progress bar, no informational output on stderr
};

void add_info_command(CLI::App& app, Context& ctx);
void add_convert_command(CLI::App& app, Context& ctx);
void add_sample_command(CLI::App& app, Context& ctx);
void add_select_command(CLI::App& app, Context& ctx);
void add_contour_command(CLI::App& app, Context& ctx);
void add_distance_command(CLI::App& app, Context& ctx);
void add_offset_command(CLI::App& app, Context& ctx);
void add_csg_command(CLI::App& app, Context& ctx);
void add_attractor_command(CLI::App& app, Context& ctx);
void add_point_load_command(CLI::App& app, Context& ctx);
void add_decimate_command(CLI::App& app, Context& ctx);
void add_fit_command(CLI::App& app, Context& ctx);
void add_view_command(CLI::App& app, Context& ctx);
void add_colormap_command(CLI::App& app, Context& ctx);
void add_probe_command(CLI::App& app, Context& ctx);
void add_streamlines_command(CLI::App& app, Context& ctx);
void add_subsample_command(CLI::App& app, Context& ctx);
void add_threshold_command(CLI::App& app, Context& ctx);
void add_surface_command(CLI::App& app, Context& ctx);
void add_elevation_command(CLI::App& app, Context& ctx);
void add_warp_command(CLI::App& app, Context& ctx);
void add_gradient_command(CLI::App& app, Context& ctx);
void add_calc_command(CLI::App& app, Context& ctx);
void add_glyph_command(CLI::App& app, Context& ctx);
void add_tensor_glyph_command(CLI::App& app, Context& ctx);
void add_normals_command(CLI::App& app, Context& ctx);
void add_tube_command(CLI::App& app, Context& ctx);
void add_cut_command(CLI::App& app, Context& ctx);
void add_clip_command(CLI::App& app, Context& ctx);
void add_figures_command(CLI::App& app, Context& ctx);

}  // namespace isoforge::cli
