// Fig. 1.29: a concave generator gives several offset surfaces. The generator is a closed
// dumbbell (two balls of radius 0.45 joined by a neck of radius 0.15, itself contoured from
// an implicit function); its signed distance (implicit modeller, 48 x 48 x 72 samples) is
// contoured outside (+0.1: one surface) and inside (-0.2, deeper than the neck: one surface
// per ball), the inner ones coloured by connectivity.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/contour/connectivity.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/model/csg.hpp"
#include "isoforge/model/implicit_modeller.hpp"

namespace isoforge::cli::figures {

Output fig_1_29(const Context& ctx) {
  using F = ImplicitFunction;
  const F neck = F::cylinder({0, 0, 0}, {0, 0, 1}, 0.15) & F::box({-1, -1, -0.6}, {1, 1, 0.6});
  const F shape = F::sphere({0, 0, -0.55}, 0.45) | F::sphere({0, 0, 0.55}, 0.45) | neck;
  Bounds sb;
  sb.min = {-0.6, -0.6, -1.1};
  sb.max = {0.6, 0.6, 1.1};
  const ImageData sampled = sample_image(shape, GridSpec::from_bounds(sb, {49, 49, 89}));
  const PolyData generator = contour(sampled, {}).output;
  ImplicitModellerOptions o;
  o.sample_dimensions = {48, 48, 72};
  o.model_bounds.min = {-0.8, -0.8, -1.2};
  o.model_bounds.max = {0.8, 0.8, 1.2};
  o.adjust_bounds = false;
  o.maximum_distance = 0.15;  // 0.36 world units
  o.signed_distance = true;
  o.clamp = true;
  o.progress = ctx.progress;
  const ImageData img = implicit_modeller(generator, o).output;
  const PolyData outer = offset_surfaces(img, {0.1}).output;
  const ConnectivityResult inner = connectivity(offset_surfaces(img, {-0.2}).output);
  const std::size_t n_outer = connectivity(outer).stats.components;
  const SurfaceTopology ti = analyze_topology(inner.output);
  Output out;
  out.datasets.emplace_back("generator", generator);
  out.datasets.emplace_back("signed_distance", img);
  out.datasets.emplace_back("offset_outside", outer);
  out.datasets.emplace_back("offset_inside", inner.output);
  out.meshes.push_back({"generator", translated(generator, {-1.6, 0, 0}), "", Colormap::Rainbow,
                        std::nullopt, {200, 200, 200, 255}});
  out.meshes.push_back({"distance +0.1", outer, "", Colormap::Rainbow, std::nullopt,
                        {120, 170, 230, 255}});
  out.meshes.push_back({"distance -0.2", translated(inner.output, {1.6, 0, 0}), "ComponentId",
                        Colormap::Rainbow, std::array{0.0, 1.0}});
  out.counts = fmt::format("{} + {} triangles", outer.polys.size(), inner.output.polys.size());
  out.check = fmt::format("outside {} surface, inside {} surfaces ({})", n_outer,
                          inner.stats.components, topology_text(ti));
  out.ok = n_outer == 1 && inner.stats.components == 2 && ti.closed() && ti.manifold();
  return out;
}

}  // namespace isoforge::cli::figures
