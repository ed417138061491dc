// Fig. 1.36: subsampling a structured grid. The combustor (57 x 33 x 25 points) keeps every
// other point along i, j and k; both grids' outer surfaces as wireframes, the subsampled one below.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/filters/subsample.hpp"
#include "isoforge/filters/surface.hpp"

namespace isoforge::cli::figures {

Output fig_1_36(const Context& ctx) {
  const StructuredGrid sg = combustor(ctx);
  SubsampleOptions so;
  so.rate = {2, 2, 2};
  const StructuredGrid sub = extract_voi(sg, so);
  // Every kept point is the input's point (2i, 2j, 2k), with its density.
  std::size_t mismatches = 0;
  const DataArray& rho = sg.point_data.get("Density");
  const DataArray& srho = sub.point_data.get("Density");
  for (Index k = 0; k < sub.dims[2]; ++k) {
    for (Index j = 0; j < sub.dims[1]; ++j) {
      for (Index i = 0; i < sub.dims[0]; ++i) {
        const auto o = std::size_t(sub.point_id(i, j, k));
        const auto in = std::size_t(sg.point_id(2 * i, 2 * j, 2 * k));
        mismatches += sub.points[o] == sg.points[in] && srho.get(o) == rho.get(in) ? 0 : 1;
      }
    }
  }
  const auto [lo, hi] = rho.range();
  const double dz = 1.3 * sg.bounds().size().z;
  Output out;
  out.datasets.emplace_back("combustor", sg);
  out.datasets.emplace_back("subsampled", sub);
  out.meshes.push_back({"original", wireframe(extract_surface(sg).output), "Density",
                        Colormap::Rainbow, std::array{lo, hi}});
  out.meshes.push_back({"every other point", translated(wireframe(extract_surface(sub).output), {0, 0, -dz}),
                        "Density", Colormap::Rainbow, std::array{lo, hi}});
  out.counts = fmt::format("{}x{}x{} -> {}x{}x{} points", sg.dims[0], sg.dims[1], sg.dims[2],
                           sub.dims[0], sub.dims[1], sub.dims[2]);
  out.check = fmt::format("{} kept points differ from the input's", mismatches);
  out.ok = mismatches == 0 && sub.dims[0] == 29 && sub.dims[1] == 17 && sub.dims[2] == 13;
  return out;
}

}  // namespace isoforge::cli::figures
