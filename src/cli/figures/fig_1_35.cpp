// Fig. 1.35: probing the combustor. Three planes of 50 x 50 points (VTK's probeComb: x = 3.7,
// 9.2 and 13.27, 5 units wide in y and z) sample the density, and their quads whose points were
// all found are contoured into density lines; the combustor's outline (its grid's 12 edges)
// around them.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/filters/cut.hpp"
#include "isoforge/filters/probe.hpp"

namespace isoforge::cli::figures {

Output fig_1_35(const Context& ctx) {
  const StructuredGrid sg = combustor(ctx);
  const Prober prober(sg);
  const auto [lo, hi] = sg.point_data.get("Density").range();
  const double xs[3] = {3.7, 9.2, 13.27}, zs[3] = {28.37, 31.2, 33.3};
  Output out;
  std::string found;
  bool ok = true;
  std::size_t segments = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 o{xs[k], -2.5, zs[k] - 2.5};
    const PolyData plane = probe_plane(o, o + Vec3{0, 5, 0}, o + Vec3{0, 0, 5}, 50, 50);
    const auto [probed, stats] = prober.probe(plane);
    PolyData pd = std::get<PolyData>(probed);
    // Keep the quads whose four points lie inside the combustor (the others hold NaN).
    const DataArray& valid = pd.point_data.get("vtkValidPointMask");
    CellArray kept;
    for (std::size_t c = 0; c < pd.polys.size(); ++c) {
      const auto ids = pd.polys.cell(c);
      bool all = true;
      for (Index id : ids) all = all && valid.get(std::size_t(id)) != 0;
      if (all) kept.add(ids);
    }
    pd.polys = kept;
    ContourOptions co;
    co.values = generate_values(12, lo, hi);
    co.array = "Density";
    const PolyData lines = contour(pd, co).output;
    // Probed values are convex combinations: inside the input's range.
    const auto [plo, phi] = lines.num_points() ? lines.point_data.get("Density").range()
                                               : std::pair{lo, hi};
    ok = ok && lines.lines.size() > 0 && plo >= lo - 1e-6 && phi <= hi + 1e-6;
    found += fmt::format("{}{}", k ? ", " : "", stats.found);
    segments += lines.lines.size();
    out.datasets.emplace_back(fmt::format("probe_{}", k), pd);
    out.datasets.emplace_back(fmt::format("contours_{}", k), lines);
    out.meshes.push_back({fmt::format("probe plane {}", k), pd, "Density", Colormap::Rainbow,
                          std::array{lo, hi}});
    out.meshes.push_back({fmt::format("contours {}", k), lines, "", Colormap::Rainbow,
                          std::nullopt, {20, 20, 20, 255}});
    if (ctx.progress) (void)ctx.progress((k + 1) / 3.0);
  }
  out.meshes.push_back({"combustor outline", grid_outline(sg), "", Colormap::Rainbow, std::nullopt,
                        {230, 230, 230, 255}});
  out.counts = fmt::format("3 x 2500 probes, {} contour lines", segments);
  out.check = fmt::format("found {} of 2500; contour values inside the data's range", found);
  out.ok = ok;
  return out;
}

}  // namespace isoforge::cli::figures
