// Fig. 1.37: decimation of data/bunny.ply (69 451 triangles) to 10% by the chapter's three
// methods — edge collapse (quadric), vertex deletion, cell deletion — side by side at the same
// triangle count, each with its measured distance to the original.

#include <fmt/core.h>

#include <cstdlib>

#include "figure.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/reduce/decimate.hpp"
#include "isoforge/reduce/mesh_distance.hpp"

namespace isoforge::cli::figures {

Output fig_1_37(const Context& ctx) {
  const PolyData bunny = std::get<PolyData>(read(data_file(ctx, "bunny.ply")));
  const std::size_t target = 7000;
  const DecimateMethod methods[3] = {DecimateMethod::Quadric, DecimateMethod::VertexRemoval,
                                     DecimateMethod::CellCollapse};
  const char* names[3] = {"edge_collapse", "vertex_deletion", "cell_deletion"};
  const double dx = 1.2 * bunny.bounds().size().x;
  Output out;
  out.datasets.emplace_back("bunny", bunny);
  out.meshes.push_back({"original", translated(bunny, {-1.5 * dx, 0, 0}), "", Colormap::Rainbow,
                        std::nullopt, {200, 200, 200, 255}});
  std::string counts = "69451 ->", errors;
  bool ok = true;
  for (int k = 0; k < 3; ++k) {
    DecimateOptions o;
    o.method = methods[k];
    o.target_triangles = target;
    const auto [mesh, stats] = decimate(bunny, o);
    const MeshDistance d = mesh_distance(bunny, mesh);
    const std::size_t n = stats.output_triangles;
    ok = ok && n <= target && n + 8 >= target;
    counts += fmt::format(" {}", n);
    errors += fmt::format("{}{} {:.2g}%", k ? ", " : "", names[k], 100 * d.relative_hausdorff());
    out.datasets.emplace_back(names[k], mesh);
    out.meshes.push_back({names[k], translated(mesh, {(k - 0.5) * dx, 0, 0}), "",
                          Colormap::Rainbow, std::nullopt, {230, 215, 190, 255}});
    if (ctx.progress) (void)ctx.progress((k + 1) / 3.0);
  }
  out.counts = counts + " triangles";
  out.check = "Hausdorff / diagonal: " + errors;
  out.ok = ok;
  return out;
}

}  // namespace isoforge::cli::figures
