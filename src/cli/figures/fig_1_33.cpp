// Fig. 1.33: the skin (data/Torso.vtp) cut by the planes y = c for 46 values 1.5 ... 136.5
// (3 units apart): contour lines, wrapped in tubes of radius 0.8.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/filters/cut.hpp"
#include "isoforge/filters/tube.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::cli::figures {

Output fig_1_33(const Context& ctx) {
  const PolyData torso = std::get<PolyData>(read(data_file(ctx, "Torso.vtp")));
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0}, {0, 1, 0});
  CutOptions co;
  co.values = generate_values(46, 1.5, 136.5);
  const PolyData lines = cut(torso, f, co).output;
  double worst = 0;  // each line point on its plane
  const DataArray& vi = lines.point_data.get("CutValueIndex");
  for (std::size_t i = 0; i < lines.num_points(); ++i) {
    worst = std::max(worst, std::abs(lines.points[i].y - co.values[std::size_t(vi.get(i))]));
  }
  std::size_t closed = 0;
  for (std::size_t l = 0; l < lines.lines.size(); ++l) {
    const auto ids = lines.lines.cell(l);
    closed += ids.front() == ids.back() ? 1 : 0;
  }
  TubeOptions to;
  to.radius = 0.8;
  to.sides = 8;
  to.progress = ctx.progress;
  const auto [tubes, ts] = tube(lines, to);
  Output out;
  out.datasets.emplace_back("contour_lines", lines);
  out.datasets.emplace_back("tubes", tubes);
  out.meshes.push_back({"tubes", tubes, "", Colormap::Rainbow, std::nullopt, {240, 190, 160, 255}});
  out.counts = fmt::format("{} lines ({} closed), {} tube triangles", lines.lines.size(), closed,
                           tubes.polys.size());
  out.check = fmt::format("{} tubes; line points on their planes within {:.1g}", ts.tubes, worst);
  out.ok = lines.lines.size() > 0 && closed > 0 && ts.tubes == lines.lines.size() && worst < 1e-4;
  return out;
}

}  // namespace isoforge::cli::figures
