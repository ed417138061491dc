// Fig. 1.4b (section 1.4; the VTK textbook shows stream tubes in the carotid artery, which is not
// in data/: the combustor's flow stands in for it): stream tubes in the combustor from 25 seeds
// on a rake across its inlet side, RK45 both ways, the tube radius growing with the speed and
// the tubes coloured by it; the grid's outline around them.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/filters/calculator.hpp"
#include "isoforge/filters/probe.hpp"
#include "isoforge/filters/streamline.hpp"
#include "isoforge/filters/tube.hpp"

namespace isoforge::cli::figures {

Output fig_1_4b(const Context& ctx) {
  const StructuredGrid sg = combustor(ctx);
  const PolyData seeds = probe_line({3, -2, 27.5}, {3, 2, 32}, 25);
  StreamlineOptions so;
  so.vectors = "Velocity";
  so.integrator = StreamIntegrator::RK45;
  so.direction = StreamDirection::Both;
  so.vorticity = false;
  so.progress = ctx.progress;
  auto [lines, stats] = streamlines(sg, seeds, so);
  lines.point_data.add(calculate(lines, "Speed", "mag(Velocity)"), AttributeRole::Scalars);
  TubeOptions to;
  to.radius = 0.04;
  to.max_radius = 0.16;
  to.radius_array = "Speed";
  to.sides = 10;
  const auto [tubes, ts] = tube(lines, to);
  // Every line point inside the grid's bounds (to float precision).
  const Bounds b = sg.bounds();
  std::size_t outside = 0;
  for (std::size_t i = 0; i < lines.points.size(); ++i) {
    const Vec3 p = lines.points[i];
    for (int a = 0; a < 3; ++a) {
      if (p[a] < b.min[a] - 1e-4 || p[a] > b.max[a] + 1e-4) {
        ++outside;
        break;
      }
    }
  }
  const double worst = worst_tangency(lines, "Velocity");
  Output out = stream_output(lines, tubes, "stream tubes", "Speed", sg, "combustor outline");
  out.counts = fmt::format("{} lines, {} points, {} tubes", stats.lines, stats.points, ts.tubes);
  out.check = fmt::format(
      "{} of 25 seeds inside, {} line points outside the grid, radius {:.3g} .. {:.3g}; steps "
      "along the flow (cos >= {:.4f})",
      stats.seeds - stats.seeds_outside, outside, ts.min_radius, ts.max_radius, worst);
  out.ok = stats.seeds_outside == 0 && outside == 0 && ts.tubes + ts.skipped_lines == stats.lines &&
           ts.tubes > 40 && worst > 0.98;
  return out;
}

}  // namespace isoforge::cli::figures
