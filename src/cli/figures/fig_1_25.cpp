// Fig. 1.25: the Lorenz attractor. 10 million RK4 steps (sigma 10, rho 28, beta 8/3) counted
// into a 200^3 volume, whose surface of 50 visits is extracted by marching cubes.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/contour/connectivity.hpp"
#include "isoforge/model/attractor.hpp"

namespace isoforge::cli::figures {

Output fig_1_25(const Context& ctx) {
  AttractorOptions o;  // the chapter's numbers are the defaults
  o.trajectory.steps = 10'000'000;
  o.trajectory.dims = {200, 200, 200};
  o.value = 50;
  o.normals = ContourNormals::Gradient;
  o.trajectory.progress = ctx.progress;
  AttractorResult a = lorenz_attractor(o);
  const PolyData& surface = a.output.surface;
  const SurfaceTopology t = analyze_topology(surface);
  ConnectivityOptions c;
  c.mode = ConnectivityMode::Largest;
  const ConnectivityStats cs = connectivity(surface, c).stats;
  const double largest = cs.sizes.empty() ? 0 : double(cs.sizes[0]) / double(surface.polys.size());
  Output out;
  out.datasets.emplace_back("visits", std::move(a.output.volume));
  out.datasets.emplace_back("attractor", surface);
  out.meshes.push_back({"50 visits", surface, "", Colormap::Rainbow, std::nullopt, {240, 170, 90, 255}});
  out.counts = fmt::format("{} steps, {} triangles", a.stats.trajectory.counted, surface.polys.size());
  out.check = fmt::format("{}, {} components, largest {:.0f}% of triangles",
                          t.closed() && t.manifold() ? "closed, manifold" : topology_text(t),
                          t.components.size(), 100 * largest);
  out.ok = a.stats.trajectory.counted == 10'000'000 && t.closed() && t.manifold() && largest > 0.5;
  return out;
}

}  // namespace isoforge::cli::figures
