#pragma once
// The chapter's figures for `isoforge figures` (docs/figures.md). Each figure is one function in
// its own file (fig_1_31.cpp makes Fig. 1.31) that computes the figure with the chapter's
// parameters through the library's public API and returns its datasets (written as VTK XML),
// the meshes of its picture (one .glb) and one line of numbers with the figure's key check.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/filters/colormap.hpp"

namespace isoforge::cli::figures {

/// One mesh of a figure's picture.
struct Mesh {
  std::string name;
  PolyData data;
  std::string color_by;  ///< point array coloured through `map` ("" = the solid `color`)
  Colormap map = Colormap::Rainbow;
  std::optional<std::array<double, 2>> range;  ///< of `color_by` (default: its own range)
  Rgba8 color = {230, 230, 230, 255};          ///< without `color_by`
  double opacity = 1;  ///< < 1: the viewer draws it translucent, sorted back to front
};

/// What a figure makes.
struct Output {
  std::vector<std::pair<std::string, Dataset>> datasets;  ///< written as NAME.vti/.vts/.vtp/.vtu
  std::vector<Mesh> meshes;                               ///< the picture (one .glb)
  std::string counts;  ///< e.g. "130168 triangles"
  std::string check;   ///< the key property, measured, e.g. "closed, manifold, genus 0"
  bool ok = true;      ///< whether the check holds
};

/// What a figure's function gets.
struct Context {
  std::filesystem::path data;  ///< the data/ directory
  ProgressCallback progress;   ///< the figure's own progress (fraction of its work)
};

struct Figure {
  std::string_view id;       ///< "1.31"
  std::string_view title;    ///< a few words
  std::string_view caption;  ///< the chapter's caption
  std::array<double, 3> view;  ///< camera direction: from the model's centre toward the eye
  std::array<double, 3> up;    ///< camera up vector
  Output (*make)(const Context&);
};

/// Every figure, in the chapter's order.
[[nodiscard]] const std::vector<Figure>& all();
/// "fig_1_31" for "1.31".
[[nodiscard]] std::string file_stem(std::string_view id);

// ---- helpers shared by the figure files ----

/// `pd` moved by `t` (points only).
[[nodiscard]] PolyData translated(PolyData pd, const Vec3& t);
/// The edges of the polygons of `pd` as line segments, each once (a wireframe for the picture).
[[nodiscard]] PolyData wireframe(const PolyData& pd);
/// "closed, manifold, 1 component, genus 0" (genus listed when all components are closed).
[[nodiscard]] std::string topology_text(const SurfaceTopology& t);
/// The data file `name` of `ctx.data`. \throw Error naming it when it is missing.
[[nodiscard]] std::filesystem::path data_file(const Context& ctx, std::string_view name);
/// The 12 edges of a structured grid (i, j or k varying, the other two at their extremes) as
/// polylines over the grid's points.
[[nodiscard]] PolyData grid_outline(const StructuredGrid& sg);
/// The 12 edges of an axis-aligned box as line segments.
[[nodiscard]] PolyData box_outline(const Bounds& b);
/// The smallest cosine between a streamline's steps (chords from one point to the next, taken
/// along the flow) and the mean of the point array `vectors` at their ends, over the steps where
/// that mean is at least 1% of the fastest speed (near stagnation the direction means little):
/// 1 for lines exactly along the flow.
[[nodiscard]] double worst_tangency(const PolyData& lines, const std::string& vectors);
/// The output of a streamline figure: the lines and their tubes as datasets, the tubes coloured
/// by `color_by` over its range in `lines`, and the grid's outline in dark grey.
[[nodiscard]] Output stream_output(const PolyData& lines, const PolyData& tubes,
                                   const std::string& tubes_name, const std::string& color_by,
                                   const StructuredGrid& grid, const std::string& outline_name);
/// The combustor (data/combxyz.bin with combq.bin) as a structured grid.
[[nodiscard]] StructuredGrid combustor(const Context& ctx);

// The figures (one file each).
Output fig_1_4a(const Context&);
Output fig_1_4b(const Context&);
Output fig_1_4c(const Context&);
Output fig_1_23a(const Context&);
Output fig_1_23b(const Context&);
Output fig_1_23c(const Context&);
Output fig_1_24a(const Context&);
Output fig_1_24b(const Context&);
Output fig_1_25(const Context&);
Output fig_1_26(const Context&);
Output fig_1_27(const Context&);
Output fig_1_28(const Context&);
Output fig_1_29(const Context&);
Output fig_1_30(const Context&);
Output fig_1_31(const Context&);
Output fig_1_32(const Context&);
Output fig_1_33(const Context&);
Output fig_1_35(const Context&);
Output fig_1_36(const Context&);
Output fig_1_37(const Context&);

}  // namespace isoforge::cli::figures
