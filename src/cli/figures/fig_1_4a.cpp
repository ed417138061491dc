// Fig. 1.4a (section 1.4, whose pages the seed text lacks; the VTK textbook's office streamlines):
// streamlines in the office (data/office.binary.vtk) from 20 seeds on the line (0.1, 2.1, 0.5)
// to (0.1, 2.7, 0.5), RK45 forward, coloured by the office's scalar, in thin tubes; the room's
// outline around them.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/filters/probe.hpp"
#include "isoforge/filters/streamline.hpp"
#include "isoforge/filters/tube.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::cli::figures {

Output fig_1_4a(const Context& ctx) {
  const StructuredGrid office = std::get<StructuredGrid>(read(data_file(ctx, "office.binary.vtk")));
  const PolyData seeds = probe_line({0.1, 2.1, 0.5}, {0.1, 2.7, 0.5}, 20);
  StreamlineOptions so;
  so.integrator = StreamIntegrator::RK45;
  so.direction = StreamDirection::Forward;
  so.max_steps = 3000;
  so.vorticity = false;
  so.progress = ctx.progress;
  const auto [lines, stats] = streamlines(office, seeds, so);
  TubeOptions to;
  to.radius = 0.012;
  to.sides = 8;
  const auto [tubes, ts] = tube(lines, to);
  const double worst = worst_tangency(lines, "vectors");
  // Coloured by the office's scalar over its range on the lines.
  Output out = stream_output(lines, tubes, "streamlines", "scalars", office, "office outline");
  const auto& r = stats.by_reason;
  out.counts = fmt::format("{} lines, {} points", stats.lines, stats.points);
  out.check = fmt::format(
      "{} of 20 seeds inside; ended: {} left the room, {} stagnated, {} at max steps; steps "
      "along the flow (cos >= {:.4f})",
      stats.seeds - stats.seeds_outside, r[std::size_t(StreamTermination::OutOfDomain)],
      r[std::size_t(StreamTermination::Stagnation)], r[std::size_t(StreamTermination::OutOfSteps)],
      worst);
  out.ok = stats.seeds_outside == 0 && stats.lines == 20 && ts.tubes == 20 && worst > 0.98;
  return out;
}

}  // namespace isoforge::cli::figures
