// Fig. 1.23b: the isosurface F = 0 of the sphere F = |p| - 1 sampled on 32^3 points over
// [-1.25, 1.25]^3.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge::cli::figures {

Output fig_1_23b(const Context& ctx) {
  Bounds b;
  b.min = {-1.25, -1.25, -1.25};
  b.max = {1.25, 1.25, 1.25};
  const GridSpec grid = GridSpec::from_bounds(b, {32, 32, 32});
  SampleOptions so;
  so.progress = ctx.progress;
  const ImageData img = sample_image(ImplicitFunction::sphere({0, 0, 0}, 1), grid, so);
  ContourOptions co;
  co.values = {0};
  co.normals = ContourNormals::Gradient;
  const PolyData surface = contour(img, co).output;
  double worst = 0;
  for (std::size_t i = 0; i < surface.num_points(); ++i) {
    worst = std::max(worst, std::abs(norm(surface.points[i]) - 1));
  }
  const SurfaceTopology t = analyze_topology(surface);
  Output out;
  out.datasets.emplace_back("sampled_sphere", img);
  out.datasets.emplace_back("isosurface", surface);
  out.meshes.push_back({"F = 0", surface, "", Colormap::Rainbow, std::nullopt, {235, 200, 150, 255}});
  out.counts = fmt::format("{}^3 samples, {} triangles", grid.dims[0], surface.polys.size());
  const double h = grid.spacing.x;
  out.check = topology_text(t) + fmt::format(", radius error max {:.2g} h", worst / h);
  out.ok = t.closed() && t.manifold() && t.components.size() == 1 && t.components[0].genus == 0 &&
           worst < 0.1 * h;
  return out;
}

}  // namespace isoforge::cli::figures
