#pragma once
// Private: what every contour kernel shares to build its output — the option checks, the output
// arrays (carried attributes and normals), the per-isovalue driver and the finishing step.

#include <cmath>
#include <cstddef>
#include <vector>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/append.hpp"
#include "isoforge/core/interpolate.hpp"

namespace isoforge::contour_detail {

/// Checks that the isovalues are present and finite. \throw Error naming `who`.
void check_values(const ContourOptions& options, const char* who);

/// Checks the options (check_values) and returns the scalar array to contour (`options.array`
/// or the active scalars; one component). \throw Error naming `who`.
const DataArray& contour_scalars(const Attributes& point_data, const ContourOptions& options,
                                 const char* who);

/// The output arrays of one contour part: the input's point data interpolated and cell data
/// copied (when options.interpolate_attributes), and "Normals" (when options.normals is
/// Gradient: 3 floats per point written through `normals`).
struct ContourArrays {
  ContourArrays(const Attributes& point_data, const Attributes& cell_data, std::size_t points,
                std::size_t cells, const ContourOptions& options);

  AttributeInterpolator attributes;
  float* normals = nullptr;  ///< 3 floats per output point, or null
  bool cell_data = false;    ///< whether there are cell arrays to copy

  /// Moves the arrays into the output's attributes (normals as the active normals).
  void move_into(PolyData& out);

 private:
  DataArray normal_array_;
};

/// Stores the unit vector of g (zero if g is zero or not finite), negated when `flip`.
inline void store_normal(float* n, Vec3 g, bool flip) {
  const double len = norm(g);
  g = len > 0 && std::isfinite(len) ? g / len : Vec3{0, 0, 0};
  if (flip) g = -g;
  n[0] = static_cast<float>(g.x);
  n[1] = static_cast<float>(g.y);
  n[2] = static_cast<float>(g.z);
}

/// A triangle mesh of `points` float points and `triangles` triangles, all uninitialized (the
/// parallel passes write every point, offset and id, and are the first to touch the memory).
[[nodiscard]] PolyData triangle_output(std::size_t points, std::size_t triangles);

/// Adds the Int32 point array "IsovalueIndex" filled with `index`.
void add_isovalue_index(PolyData& pd, int index);

/// Drops undefined points (see crossing() in tables.hpp: not finite, from an edge with a NaN
/// end) and the cells using them, reverses cells when options.flip is set, then adds "Normals"
/// computed from the triangles when options ask for ContourNormals::Triangles. Subtracts what
/// it dropped from `stats` (points, and cells in its units: triangles, segments or vertices).
void finish_output(PolyData& pd, const ContourOptions& options, ContourStats& stats);

/// The driver every contour shares: part(v, progress) contours isovalue options.values[v],
/// reporting its own fraction through `progress`; each part's points are tagged with
/// IsovalueIndex v, and the parts come back appended and finished (finish_output).
template <class Part>
[[nodiscard]] PolyData contour_each_value(const ContourOptions& options, ContourStats& stats,
                                          Part&& part) {
  const std::size_t n = options.values.size();
  std::vector<PolyData> parts;
  parts.reserve(n);
  for (std::size_t v = 0; v < n; ++v) {
    const double from = static_cast<double>(v) / static_cast<double>(n);
    const double to = static_cast<double>(v + 1) / static_cast<double>(n);
    parts.push_back(part(v, progress_range(options.progress, from, to)));
    add_isovalue_index(parts.back(), static_cast<int>(v));
    report_progress(options.progress, to, "contour");
  }
  PolyData out = append(std::move(parts));
  finish_output(out, options, stats);
  return out;
}

}  // namespace isoforge::contour_detail
