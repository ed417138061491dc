// Fig. 1.32: 100 planes perpendicular to the view direction (1, 0.4, 0.6) cutting the whole
// combustor, coloured by density with opacity 0.05; each plane is its own mesh, so the viewer
// sorts them back to front.

#include <fmt/core.h>

#include <algorithm>

#include "figure.hpp"
#include "isoforge/filters/cut.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge::cli::figures {

Output fig_1_32(const Context& ctx) {
  const StructuredGrid sg = combustor(ctx);
  const Vec3 view = Vec3{1, 0.4, 0.6} / norm(Vec3{1, 0.4, 0.6});
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0}, view);
  const DataArray F = sample_points(f, sg);
  const auto [flo, fhi] = F.range();
  const double step = (fhi - flo) / 101;
  const std::vector<double> values = generate_values(100, flo + step, fhi - step);
  const auto [lo, hi] = sg.point_data.get("Density").range();
  CutOptions co;
  co.values = values;
  const auto [all, stats] = cut(sg, f, co);
  Output out;
  out.datasets.emplace_back("cut_planes", all);
  std::size_t nonempty = 0, polygons = 0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    CutOptions one;
    one.values = {values[k]};
    PolyData plane = cut(sg, f, one).output;
    nonempty += plane.polys.size() > 0 ? 1 : 0;
    polygons += plane.polys.size();
    out.meshes.push_back({fmt::format("plane {}", k), std::move(plane), "Density",
                          Colormap::Rainbow, std::array{lo, hi}, {}, 0.05});
    if (ctx.progress) (void)ctx.progress(double(k + 1) / double(values.size()));
  }
  out.counts = fmt::format("100 planes, {} polygons", all.polys.size());
  out.check = fmt::format("{} of 100 planes cross the grid; planes cut one by one: {} polygons",
                          nonempty, polygons);
  out.ok = nonempty == 100 && polygons == all.polys.size();
  return out;
}

}  // namespace isoforge::cli::figures
