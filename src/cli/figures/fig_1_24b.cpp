// Fig. 1.24b: the voxels of a 20^3 volume over [-1, 1]^3 inside the union of two ellipsoids
// (the unit sphere scaled by (0.83, 0.41, 0.41) and by (0.41, 0.83, 0.41)), shrunk 50%.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/filters/shrink.hpp"
#include "isoforge/filters/surface.hpp"
#include "isoforge/implicit/select.hpp"

namespace isoforge::cli::figures {

Output fig_1_24b(const Context&) {
  ImageData img;
  img.dims = {21, 21, 21};
  img.origin = {-1, -1, -1};
  img.spacing = {0.1, 0.1, 0.1};
  const Vec3 a{0.83, 0.41, 0.41}, b{0.41, 0.83, 0.41};
  const ImplicitFunction both =
      ImplicitFunction::sphere({0, 0, 0}, 1).transformed(Affine::scaling(a)) |
      ImplicitFunction::sphere({0, 0, 0}, 1).transformed(Affine::scaling(b));
  const UnstructuredGrid selected = extract_cells(img, both);
  const UnstructuredGrid shrunk = shrink(selected, 0.5);
  // Every shrunk voxel is a cube of side 0.05 (half the spacing).
  double worst = 0;
  for (std::size_t c = 0; c < shrunk.num_cells(); ++c) {
    Bounds cb;
    for (Index id : shrunk.cells.cell(c)) cb.extend(shrunk.points[static_cast<std::size_t>(id)]);
    const Vec3 s = cb.size();
    worst = std::max({worst, std::abs(s.x - 0.05), std::abs(s.y - 0.05), std::abs(s.z - 0.05)});
  }
  PolyData faces = extract_surface(shrunk).output;
  Output out;
  out.datasets.emplace_back("selected_voxels", selected);
  out.datasets.emplace_back("shrunk_voxels", shrunk);
  out.meshes.push_back({"voxels shrunk 50%", faces, "", Colormap::Rainbow, std::nullopt,
                        {220, 110, 70, 255}});
  out.counts = fmt::format("{} of 8000 voxels, {} faces", selected.num_cells(), faces.polys.size());
  out.check = fmt::format("each voxel a cube of side 0.05 (error max {:.1g})", worst);
  out.ok = selected.num_cells() > 0 && faces.polys.size() == 6 * selected.num_cells() &&
           worst < 1e-6;
  return out;
}

}  // namespace isoforge::cli::figures
