// Fig. 1.28: the strokes of HELLO (data/hello.vtk) thickened by implicit modeling: distances on
// 110 x 40 x 20 samples over (-1, 10, -1, 3, -1, 1), maximum distance 0.25 of the largest side,
// contoured at 0.25; the original strokes inside the translucent surface.

#include <fmt/core.h>

#include <set>

#include "figure.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/csg.hpp"
#include "isoforge/model/implicit_modeller.hpp"

namespace isoforge::cli::figures {

Output fig_1_28(const Context& ctx) {
  const PolyData strokes = std::get<PolyData>(read(data_file(ctx, "hello.vtk")));
  ImplicitModellerOptions o;
  o.sample_dimensions = {110, 40, 20};
  o.model_bounds.min = {-1, -1, -1};
  o.model_bounds.max = {10, 3, 1};
  o.maximum_distance = 0.25;
  o.progress = ctx.progress;
  const ImageData img = implicit_modeller(strokes, o).output;
  const PolyData surface = offset_surfaces(img, {0.25}).output;
  const SurfaceTopology t = analyze_topology(surface);
  std::multiset<long> genera;
  for (const auto& c : t.components) genera.insert(c.genus);
  Output out;
  out.datasets.emplace_back("distance", img);
  out.datasets.emplace_back("hello_surface", surface);
  out.meshes.push_back({"strokes", strokes, "", Colormap::Rainbow, std::nullopt, {255, 80, 60, 255}});
  out.meshes.push_back({"offset 0.25", surface, "", Colormap::Rainbow, std::nullopt,
                        {170, 200, 240, 255}, 0.35});
  out.counts = fmt::format("110x40x20 samples, {} triangles", surface.polys.size());
  out.check = topology_text(t) + " (H E L L O)";
  out.ok = t.closed() && t.manifold() && genera == std::multiset<long>{0, 0, 0, 0, 1};
  return out;
}

}  // namespace isoforge::cli::figures
