// Fig. 1.23c: the ice cream cone (two spheres, a cone and two planes: implicit/function.hpp's
// ice_cream_cone()) sampled on 128^3 points over [-0.1, 2] x [-0.7, 0.7]^2 and contoured at 0.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge::cli::figures {

Output fig_1_23c(const Context& ctx) {
  Bounds b;
  b.min = {-0.1, -0.7, -0.7};
  b.max = {2, 0.7, 0.7};
  const GridSpec grid = GridSpec::from_bounds(b, {128, 128, 128});
  SampleOptions so;
  so.progress = ctx.progress;
  const ImageData img = sample_image(ice_cream_cone(), grid, so);
  ContourOptions co;
  co.values = {0};
  co.normals = ContourNormals::Gradient;
  const PolyData surface = contour(img, co).output;
  const SurfaceTopology t = analyze_topology(surface);
  Output out;
  out.datasets.emplace_back("icecream", surface);
  out.meshes.push_back({"ice cream", surface, "", Colormap::Rainbow, std::nullopt, {240, 200, 150, 255}});
  out.counts = fmt::format("128^3 samples, {} triangles", surface.polys.size());
  out.check = topology_text(t);
  out.ok = t.closed() && t.manifold() && !t.components.empty();
  return out;
}

}  // namespace isoforge::cli::figures
