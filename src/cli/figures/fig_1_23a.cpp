// Fig. 1.23a: a sphere's function F = |p| - 1 sampled on the plane z = 0 (41 x 41 samples over
// [-2, 2]^2), contoured at F = -0.5 (inside), F = 0 (the sphere) and F = 0.5 (outside).

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/filters/surface.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge::cli::figures {

Output fig_1_23a(const Context& ctx) {
  Bounds b;
  b.min = {-2, -2, 0};
  b.max = {2, 2, 0};
  const GridSpec grid = GridSpec::from_bounds(b, {41, 41, 1});
  SampleOptions so;
  so.progress = ctx.progress;
  const ImageData img = sample_image(ImplicitFunction::sphere({0, 0, 0}, 1), grid, so);
  ContourOptions co;
  co.values = {-0.5, 0, 0.5};
  PolyData lines = contour(img, co).output;
  // Each line point lies on the circle |p| = 1 + value, up to the linear interpolation of |p|.
  double worst = 0;
  const DataArray& iso = lines.point_data.get("IsovalueIndex");
  for (std::size_t i = 0; i < lines.num_points(); ++i) {
    const double r = 1 + co.values[static_cast<std::size_t>(iso.get(i))];
    worst = std::max(worst, std::abs(norm(lines.points[i]) - r));
  }
  std::size_t closed = 0;
  for (std::size_t l = 0; l < lines.lines.size(); ++l) {
    const auto ids = lines.lines.cell(l);
    closed += ids.front() == ids.back() ? 1 : 0;
  }
  PolyData plane = extract_surface(img).output;
  Output out;
  out.datasets.emplace_back("sampled_plane", img);
  out.datasets.emplace_back("contour_lines", lines);
  out.meshes.push_back({"F on the plane", plane, "F", Colormap::CoolWarm, std::array{-1.0, 1.0}});
  out.meshes.push_back({"F = -0.5, 0, 0.5", translated(lines, {0, 0, 0.01}), "", Colormap::Rainbow,
                        std::nullopt, {20, 20, 20, 255}});
  out.counts = fmt::format("{} samples, {} lines, {} points", img.num_points(), lines.lines.size(),
                           lines.num_points());
  const double h = grid.spacing.x;
  out.check = fmt::format("{} closed circles, radius error max {:.2g} ({:.2g} h)", closed, worst,
                          worst / h);
  out.ok = closed == 3 && lines.lines.size() == 3 && worst < 0.1 * h;
  return out;
}

}  // namespace isoforge::cli::figures
