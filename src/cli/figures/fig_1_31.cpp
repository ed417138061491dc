// Fig. 1.31: the combustor (data/combxyz.bin, combq.bin) cut by the plane through its centre
// with normal (-0.287, 0, 0.9579), coloured by density; the grid's computational plane k = 9
// shown as a wireframe for comparison.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/filters/cut.hpp"
#include "isoforge/filters/subsample.hpp"
#include "isoforge/filters/surface.hpp"

namespace isoforge::cli::figures {

Output fig_1_31(const Context& ctx) {
  const StructuredGrid sg = combustor(ctx);
  const ImplicitFunction f = ImplicitFunction::plane(sg.bounds().center(), {-0.287, 0, 0.9579});
  CutOptions co;
  co.progress = ctx.progress;
  const auto [pd, stats] = cut(sg, f, co);
  double worst = 0;  // distance of the cut points from the plane
  for (std::size_t i = 0; i < pd.num_points(); ++i) {
    worst = std::max(worst, std::abs(f.value(pd.points[i])));
  }
  SubsampleOptions so;
  so.voi = Voi{0, sg.dims[0] - 1, 0, sg.dims[1] - 1, 9, 9};
  const StructuredGrid k9 = extract_voi(sg, so);
  const PolyData k9_surface = extract_surface(k9).output;
  const auto [lo, hi] = sg.point_data.get("Density").range();
  Output out;
  out.datasets.emplace_back("cut_plane", pd);
  out.datasets.emplace_back("grid_k9", k9);
  out.meshes.push_back({"cut plane", pd, "Density", Colormap::Rainbow, std::array{lo, hi}});
  out.meshes.push_back({"k = 9 (wireframe)", wireframe(k9_surface), "", Colormap::Rainbow,
                        std::nullopt, {235, 235, 235, 255}});
  out.counts = fmt::format("{} polygons, {} points", pd.polys.size(), pd.num_points());
  out.check = fmt::format("points on the plane within {:.1g}", worst);
  out.ok = pd.polys.size() > 0 && worst < 1e-4;
  return out;
}

}  // namespace isoforge::cli::figures
